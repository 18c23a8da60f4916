// Picking from the view depth (render/view_pick.h): one texel of the last frame's view depth,
// read back. A depth texture cannot be read with glReadPixels in GLES 3.0 / WebGL2, and a float
// colour target needs an extension WebGL2 may lack: the texel is packed into a 1x1 RGBA8 target
// (shaders/pick_depth.frag, 24 bits) and decoded here.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/render/gl/programs.h"

namespace hv::render::gl {

std::optional<double> GlBackend::readViewDepth(glm::ivec2 texel) {
  if (!viewDepth_.id() || texel.x < 0 || texel.y < 0 || texel.x >= viewDepthSize_.x || texel.y >= viewDepthSize_.y)
    return std::nullopt;
  if (!pickDepthProgram_.program.id()) {
    pickDepthProgram_ = PickDepthProgram(programs().pickDepth);
    pickFbo_ = gpu::makeFramebuffer();
    pickTarget_ = gpu::makeRgba8Target(1, 1);
  }
  glBindFramebuffer(GL_FRAMEBUFFER, pickFbo_.id());
  gpu::attachColour(pickTarget_.id());
  gpu::drawToColour();
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  gpu::checkFramebuffer("pick");
  glViewport(0, 0, 1, 1);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_BLEND);
  pickDepthProgram_.program.use();
  gpu::bindUnit(kUnitViewDepth, GL_TEXTURE_2D, viewDepth_.id());
  glUniform1i(pickDepthProgram_.viewDepth, kUnitViewDepth);
  glUniform2i(pickDepthProgram_.texel, texel.x, texel.y);
  gpu::drawFullscreen(emptyVao_);
  const Image8 packed = readColour(1, 1);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gpu::checkGlError("pick");
  const double v = packed.at(0, 0, 0) + 256.0 * packed.at(0, 0, 1) + 65536.0 * packed.at(0, 0, 2);
  return v / 16777215.0;
}

}  // namespace hv::render::gl
