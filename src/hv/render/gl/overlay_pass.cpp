// The photographs' frusta over the picture (DebugSettings::frusta): grey, the frame's images
// yellow, the debug photograph cyan; depth-tested against the view's depth, hidden parts faint.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/render/gl/programs.h"

namespace hv::render::gl {

namespace {

// Frustum colours (RGBA); hidden parts are drawn at kHiddenLineAlpha of these.
constexpr float kFrustumOther[4] = {0.8f, 0.8f, 0.8f, 0.9f};
constexpr float kFrustumInFrame[4] = {1.0f, 0.85f, 0.15f, 1.0f};
constexpr float kFrustumDebug[4] = {0.2f, 0.95f, 1.0f, 1.0f};
constexpr float kHiddenLineAlpha = 0.3f;

}  // namespace

// Over the picture in the colour target (viewFbo bound). Pinhole views only: the lines go through
// the view's pinhole transform, which a distorted picture does not follow.
void GlBackend::frustaPass(const Frame& f) {
  const FrustumLines* lines = f.debug.frustumLines;
  if (f.rect.distorted || !lines || lines->perPhoto.empty() ||
      f.rect.depthSize != glm::ivec2(f.view.width, f.view.height))
    return;
  if (!frustumVao_ || frustumVersion_ != lines->version) {
    if (!frustumVao_) {
      frustumVao_ = gpu::makeVertexArray();
      frustumBuffer_ = gpu::makeBuffer();
    }
    glBindVertexArray(frustumVao_.id());
    glBindBuffer(GL_ARRAY_BUFFER, frustumBuffer_.id());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(lines->xyz.size() * sizeof(float)), lines->xyz.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glBindVertexArray(0);
    frustumVersion_ = lines->version;
    gpu::checkGlError("frustum lines");
  }
  if (!linesProgram_.program.id()) {
    linesProgram_ = LinesProgram(programs().lines);
  }
  gpu::attachDepth(viewDepth_.id());
  gpu::checkFramebuffer("frusta");
  const LinesProgram& p = linesProgram_;
  p.program.use();
  gpu::uploadMat4(p.clipFromRender, f.rect.clipFromRender);
  glUniform1f(p.near, float(f.rect.frustum.near));
  glUniform1f(p.far, float(f.rect.frustum.far));
  const GLint colorLoc = p.color;
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);
  glEnable(GL_BLEND);
  // Alpha accumulates as coverage: a line pixel counts as covered.
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
  glBindVertexArray(frustumVao_.id());
  const std::vector<DrawRange>& ranges = lines->perPhoto;
  const DrawRange all{0, ranges.back().first + ranges.back().count};
  auto draw = [&](const float* rgba, float alphaScale, int photo) {
    if (photo >= int(ranges.size())) return;
    const DrawRange& r = photo < 0 ? all : ranges[size_t(photo)];
    glUniform4f(colorLoc, rgba[0], rgba[1], rgba[2], rgba[3] * alphaScale);
    glDrawArrays(GL_LINES, r.first, r.count);
  };
  // Complementary depth tests, so each line pixel is drawn once: behind the geometry, then in front.
  for (const bool hidden : {true, false}) {
    glDepthFunc(hidden ? GL_GREATER : GL_LEQUAL);
    const float alpha = hidden ? kHiddenLineAlpha : 1.0f;
    draw(kFrustumOther, alpha, -1);
    for (const ibr::SelectedImage& im : f.plan.images) draw(kFrustumInFrame, alpha, im.photo);
    if (f.debug.photo >= 0) draw(kFrustumDebug, alpha, f.debug.photo);
  }
  glBindVertexArray(0);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  glDisable(GL_DEPTH_TEST);
  gpu::attachDepth(0);
  gpu::checkGlError("frusta");
}

}  // namespace hv::render::gl
