#include "hv/gpu/platform/glfw/glfw_window.h"

#include "hv/gpu/gl.h"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include <stdexcept>

namespace hv::viewer {

namespace {

std::string g_lastGlfwError;

void onGlfwError(int code, const char* text) {
  g_lastGlfwError = std::string(text ? text : "unknown") + " (GLFW error " + std::to_string(code) + ")";
}

std::string glfwReason(const std::string& what) {
  return what + (g_lastGlfwError.empty() ? std::string() : ": " + g_lastGlfwError);
}

}  // namespace

GlfwWindow::GlfwWindow(int width, int height, const std::string& title, bool vsync) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit())
    throw std::runtime_error(glfwReason("cannot open a window (is there a display? under no X server, run it with "
                                        "xvfb-run -a)"));
  glfwWindowHint(GLFW_CLIENT_API, GLFW_OPENGL_ES_API);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 0);
  glfwWindowHint(GLFW_SAMPLES, 0);  // the view is blitted into the window: no multisampled default framebuffer
  window_ = glfwCreateWindow(width, height, title.c_str(), nullptr, nullptr);
  if (!window_) {
    glfwTerminate();
    throw std::runtime_error(glfwReason("cannot create a window with a GLES 3.0 context"));
  }
  glfwMakeContextCurrent(window_);
  glfwSwapInterval(vsync ? 1 : 0);
  // Installed before Dear ImGui's backend, which keeps them and calls them from its own.
  glfwSetWindowUserPointer(window_, this);
  glfwSetKeyCallback(window_, [](GLFWwindow* w, int key, int, int action, int) {
    auto* self = static_cast<GlfwWindow*>(glfwGetWindowUserPointer(w));
    if (self && self->keyHandler_ && action != GLFW_REPEAT) self->keyHandler_(key, action == GLFW_PRESS);
  });
  glfwSetWindowFocusCallback(window_, [](GLFWwindow* w, int focused) {
    auto* self = static_cast<GlfwWindow*>(glfwGetWindowUserPointer(w));
    if (self && self->keyHandler_ && !focused) self->keyHandler_(-1, false);
  });

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini left in the working directory
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(window_, true);
  ImGui_ImplOpenGL3_Init("#version 300 es");
  imgui_ = true;
  gpu::clearGlErrors();
}

GlfwWindow::~GlfwWindow() {
  if (imgui_) {
    ImGui_ImplOpenGL3_Shutdown();
    ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
  }
  if (window_) glfwDestroyWindow(window_);
  glfwTerminate();
}

void GlfwWindow::makeCurrent() { glfwMakeContextCurrent(window_); }

std::string GlfwWindow::description() const { return "GLFW window, " + gpu::glDescription(); }

glm::ivec2 GlfwWindow::framebufferSize() const {
  glm::ivec2 s;
  glfwGetFramebufferSize(window_, &s.x, &s.y);
  return s;
}

bool GlfwWindow::shouldClose() const { return glfwWindowShouldClose(window_); }
void GlfwWindow::requestClose() { glfwSetWindowShouldClose(window_, GLFW_TRUE); }
void GlfwWindow::setTitle(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }
void GlfwWindow::swapBuffers() { glfwSwapBuffers(window_); }

void GlfwWindow::pollEvents(double timeoutSeconds) {
  if (timeoutSeconds > 0.0)
    glfwWaitEventsTimeout(timeoutSeconds);
  else
    glfwPollEvents();
}

void GlfwWindow::setKeyHandler(std::function<void(int key, bool down)> handler) { keyHandler_ = std::move(handler); }

void GlfwWindow::beginUi() {
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
}

void GlfwWindow::endUi() {
  ImGui::Render();
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  gpu::clearGlErrors();
}

}  // namespace hv::viewer
