// GL contexts. The renderer only needs "a current GLES 3.0 context"; where it comes from is
// platform code: headless EGL here (Mesa llvmpipe, or a GPU driver), GLFW for the desktop viewer,
// WebGL2 in the browser.
#pragma once

#include <memory>
#include <string>

namespace hv::gpu {

class Context {
 public:
  virtual ~Context() = default;
  virtual void makeCurrent() = 0;
  virtual std::string description() const = 0;  // vendor, renderer, version
};

// A headless GLES 3 context through EGL: the surfaceless Mesa platform first, then the EGL device
// platform, then the default display. Throws std::runtime_error saying what failed.
std::unique_ptr<Context> createHeadlessContext();

}  // namespace hv::gpu
