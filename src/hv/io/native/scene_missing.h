// The scene loader's side of the list of what is missing (hv/scene/missing_sources.h): where a
// source of scene.json was asked from, and the entry for one left out.
#pragma once

#include "hv/scene/scene.h"

#include <nlohmann/json_fwd.hpp>

#include <string>

namespace hv {

// Where scene.json's `key` source ("terrain", "buildings", "cameras", ...) was asked from: its
// `path` as given when it is a URL or connection string, else resolved against `dir`; the
// cameras' catalog (`postgis`, the password left out) or their first file; "" when it names none.
std::string sourceLocation(const nlohmann::json& doc, const std::string& key, const std::string& dir);

// Records `kind` at `location` as missing in `scene`, for `message` (the error the loader reports).
void noteMissing(const Scene& scene, const std::string& kind, const std::string& location, const std::string& message);

}  // namespace hv
