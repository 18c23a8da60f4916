// Shaders embedded at build time from shaders/ (cmake/embed_shaders.cmake).
#pragma once

#include <string>
#include <vector>

namespace hv::gpu {

// The text of shaders/<name>, or nullptr.
const std::string* findShaderSource(const std::string& name);
std::vector<std::string> shaderNames();

}  // namespace hv::gpu
