// The desktop platform layer: a GLFW window with a GLES 3.0 context (an hv::gpu::Context, so the
// renderer runs in it unchanged) and the Dear ImGui backends for it. Nothing here knows about
// scenes or photographs.
#pragma once

#include "hv/gpu/context.h"

#include <glm/glm.hpp>

#include <functional>
#include <string>

struct GLFWwindow;

namespace hv::viewer {

class GlfwWindow final : public gpu::Context {
 public:
  // Opens the window and makes its context current. Throws std::runtime_error with GLFW's reason
  // (no display, no GLES 3 context).
  GlfwWindow(int width, int height, const std::string& title, bool vsync);
  ~GlfwWindow() override;
  GlfwWindow(const GlfwWindow&) = delete;
  GlfwWindow& operator=(const GlfwWindow&) = delete;

  void makeCurrent() override;
  std::string description() const override;

  GLFWwindow* handle() const { return window_; }
  glm::ivec2 framebufferSize() const;
  bool shouldClose() const;
  void requestClose();
  void setTitle(const std::string& title);
  void swapBuffers();
  // Processes pending events; waits up to `timeoutSeconds` for one when > 0 (an idle viewer).
  void pollEvents(double timeoutSeconds = 0.0);
  // Every key press and release as it happens (GLFW's key callback, chained with Dear ImGui's),
  // and a release of every key when the window loses the focus (`down` false, key -1): a viewer
  // that polls keys once per frame loses taps shorter than a frame.
  void setKeyHandler(std::function<void(int key, bool down)> handler);

  // Dear ImGui on this window: beginUi() starts a UI frame, endUi() draws it into the bound
  // framebuffer. Debian's ImGui backend is built for desktop GL and leaves a GL error behind on
  // GLES (docs/viewer.md); endUi() clears it so the renderer's error checks start clean.
  void beginUi();
  void endUi();

 private:
  GLFWwindow* window_ = nullptr;
  bool imgui_ = false;
  std::function<void(int, bool)> keyHandler_;
};

}  // namespace hv::viewer
