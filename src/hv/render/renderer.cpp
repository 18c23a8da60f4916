// The renderer: the orchestration of one frame (docs/design.md). The frame builder
// (render/frame_builder.h) plans it, makes its images resident and draws its depth maps on the
// backend; the GL backend (render/gl/gl_backend.h) then runs the view passes.
#include "hv/render/renderer.h"

#include "hv/gpu/gl.h"
#include "hv/render/frame_builder.h"
#include "hv/render/gl/gl_backend.h"
#include "hv/render/gl/programs.h"
#include "hv/render/view_pick.h"

#include <algorithm>
#include <chrono>
#include <stdexcept>

namespace hv::render {

struct Renderer::Impl {
  RenderSettings settings;
  gl::GlBackend backend;
  FrameBuilder builder;
  // The last frame's view and view-depth rectangle (pickViewPoint).
  Camera lastView;
  ViewRect lastRect;
  bool rendered = false;

  Impl(const Scene& scene, RenderSettings st, Diagnostics& diag)
      : settings(std::move(st)), backend(diag), builder(scene, settings, diag, backend) {}

  RenderOutput render(const Camera& view, bool withCounts, FrameMode mode) {
    const auto t0 = std::chrono::steady_clock::now();
    const Frame frame = builder.build(view, mode, withCounts);
    ViewPassStats passStats;
    RenderOutput out = backend.runViewPasses(frame, passStats);
    lastView = frame.view;
    lastRect = frame.rect;
    rendered = true;
    builder.viewPassesDone(frame, passStats);
    builder.stats().lastFrameMs =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }
};

int probeMat3SpriteImages(int upTo) {
  int best = 0;
  // Not beyond the varying limit: some compilers crash there instead of failing to link.
  upTo = std::min(upTo, gpu::queryLimits().maxVaryingComponents / 9);
  for (int k = 1; k <= upTo; ++k) {
    try {
      gpu::Program p = gl::linkProgram(gl::programs().pointColor, {"HV_MAT3_K=" + std::to_string(k)});
      best = k;
    } catch (const std::runtime_error&) {
      break;
    }
  }
  gpu::clearGlErrors();
  return best;
}

Renderer::Renderer(const Scene& scene, RenderSettings settings, Diagnostics& diag)
    : impl_(std::make_unique<Impl>(scene, std::move(settings), diag)) {}
Renderer::~Renderer() = default;
RenderOutput Renderer::render(const Camera& view, bool withCounts, FrameMode mode) {
  return impl_->render(view, withCounts, mode);
}
bool Renderer::converged() const { return impl_->builder.converged(); }
void Renderer::preload(const Camera& view) { impl_->builder.preload(view); }
void Renderer::setLayeredPhotograph(int photo, std::shared_ptr<const layers::LayeredPhotograph> layered) {
  impl_->builder.setLayeredPhotograph(photo, std::move(layered));
}
void Renderer::replaceImage(int photo) { impl_->builder.replaceImage(photo); }
void Renderer::setOrthophoto(std::shared_ptr<const Orthophoto> orthophoto) {
  impl_->builder.setOrthophoto(std::move(orthophoto));
}
const ibr::FramePlan& Renderer::lastPlan() const { return impl_->builder.lastPlan(); }
const std::vector<ibr::ImageParams>& Renderer::lastImageParams() const { return impl_->builder.lastImageParams(); }
const RenderSettings& Renderer::settings() const { return impl_->settings; }
RenderSettings& Renderer::settings() { return impl_->settings; }
ibr::SliceSize Renderer::sliceSize() const { return impl_->builder.sliceSize(); }
int Renderer::sliceCount() const { return impl_->builder.slotCount(); }
const RenderStats& Renderer::stats() const { return impl_->builder.stats(); }
PhotoState Renderer::photoState(int photo) const { return impl_->builder.photoState(photo); }
int Renderer::slotOf(int photo) const { return impl_->builder.slotOf(photo); }
unsigned int Renderer::colorTexture() const { return impl_->backend.colorTexture(); }
std::optional<glm::dvec3> Renderer::pickViewPoint(glm::dvec2 px) {
  if (!impl_->rendered) return std::nullopt;
  const ViewRect& r = impl_->lastRect;
  const std::optional<ViewDepthTexel> t = viewDepthTexel(impl_->lastView, r.frustum, r.depthSize, px);
  if (!t) return std::nullopt;
  const std::optional<double> stored = impl_->backend.readViewDepth(t->texel);
  if (!stored) return std::nullopt;
  return worldFromViewDepth(impl_->lastView, t->pxIdeal, *stored, r.frustum.near, r.frustum.far);
}

}  // namespace hv::render
