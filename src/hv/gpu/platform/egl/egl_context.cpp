#include "hv/gpu/context.h"

#include "hv/gpu/gl.h"
#include "hv/util/log.h"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <stdexcept>
#include <vector>

namespace hv::gpu {
namespace {

class EglContext final : public Context {
 public:
  EglContext(EGLDisplay d, EGLContext c) : display_(d), context_(c) {}
  ~EglContext() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
  void makeCurrent() override {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_))
      throw std::runtime_error("eglMakeCurrent failed (surfaceless context)");
  }
  std::string description() const override { return glDescription(); }

 private:
  EGLDisplay display_;
  EGLContext context_;
};

EGLDisplay openDisplay(std::string& how) {
  auto getPlatformDisplay =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (getPlatformDisplay) {
    EGLDisplay d = getPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    EGLint major, minor;
    if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
      how = "EGL surfaceless";
      return d;
    }
    auto queryDevices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
    if (queryDevices) {
      EGLDeviceEXT devices[16];
      EGLint count = 0;
      if (queryDevices(16, devices, &count)) {
        for (EGLint i = 0; i < count; ++i) {
          d = getPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
          if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
            how = "EGL device " + std::to_string(i);
            return d;
          }
        }
      }
    }
  }
  EGLDisplay d = eglGetDisplay(EGL_DEFAULT_DISPLAY);
  EGLint major, minor;
  if (d != EGL_NO_DISPLAY && eglInitialize(d, &major, &minor)) {
    how = "EGL default display";
    return d;
  }
  return EGL_NO_DISPLAY;
}

}  // namespace

std::unique_ptr<Context> createHeadlessContext() {
  std::string how;
  EGLDisplay display = openDisplay(how);
  if (display == EGL_NO_DISPLAY)
    throw std::runtime_error(
        "no EGL display: neither the surfaceless Mesa platform, an EGL device nor the default display "
        "initialised (install libegl-mesa0 and libgl1-mesa-dri)");
  if (!eglBindAPI(EGL_OPENGL_ES_API)) throw std::runtime_error("eglBindAPI(EGL_OPENGL_ES_API) failed");
  // PBUFFER_BIT: Mesa's surfaceless platform has no window configs (PLATFORM.md).
  const EGLint configAttribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT, EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT,
                                  EGL_NONE};
  EGLConfig config;
  EGLint n = 0;
  if (!eglChooseConfig(display, configAttribs, &config, 1, &n) || n == 0) {
    const EGLint any[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_ES3_BIT, EGL_NONE};
    if (!eglChooseConfig(display, any, &config, 1, &n) || n == 0) {
      eglTerminate(display);
      throw std::runtime_error("eglChooseConfig found no OpenGL ES 3 config on " + how);
    }
  }
  const EGLint ctxAttribs[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 0, EGL_NONE};
  EGLContext ctx = eglCreateContext(display, config, EGL_NO_CONTEXT, ctxAttribs);
  if (ctx == EGL_NO_CONTEXT) {
    eglTerminate(display);
    throw std::runtime_error("eglCreateContext (OpenGL ES 3.0) failed on " + how);
  }
  auto out = std::make_unique<EglContext>(display, ctx);
  out->makeCurrent();
  log::debug("GL context: " + how + ", " + out->description());
  return out;
}

}  // namespace hv::gpu
