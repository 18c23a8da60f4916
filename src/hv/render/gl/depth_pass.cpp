// Depth passes: each photograph's depth map in its slot (the shadow maps of Brédif 2013 §3, with
// the surfaces its date rules out left out) and the view's own linear depth and building ids.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"

namespace hv::render::gl {

namespace {

// A depth pass calls glFlush once it has handed the GL this many indices (a third as many
// triangles) since the last one: in practice after every streamed building tile (7,500 triangles
// on average in the 100k demo city). llvmpipe bins the triangles it is given until a flush: the
// depth maps of the 100k city's ~560k triangles held ~180 MiB of bins at its peak RSS, and
// flushing every tile took that peak from ~800 to ~690 MiB, flushing every 11k triangles only to
// ~775 (docs/performance.md, "City scale"). The depths are the same: a flush only hands over the
// work so far, in the same order.
constexpr std::size_t kFlushIndices = 8192;

void countAndFlush(std::size_t count, std::size_t& sinceFlush) {
  sinceFlush += count;
  if (sinceFlush < kFlushIndices) return;
  glFlush();
  sinceFlush = 0;
}

}  // namespace

void GlBackend::drawDepth(const DepthProgram& program, const glm::dmat4& clip, double near, double far,
                          const DateInterval& date, const std::vector<DrawRange>& draws,
                          const std::vector<std::uint64_t>& streamedTiles, double pushBack, glm::dvec3 centerRender) {
  program.program.use();
  glUniform1f(program.pushBack, float(pushBack));
  glUniform3f(program.center, float(centerRender.x), float(centerRender.y), float(centerRender.z));
  gpu::uploadMat4(program.clipFromRender, clip);
  glUniform1f(program.near, float(near));
  glUniform1f(program.far, float(far));
  const glm::vec2 days = ibr::gpuDays(date);
  glUniform2f(program.date, days.x, days.y);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glClearDepthf(1.0f);
  glClear(GL_DEPTH_BUFFER_BIT);
  std::size_t sinceFlush = 0;
  if (indexCount_ > 0) drawRanges(draws, sinceFlush);
  for (const std::uint64_t id : streamedTiles) {
    const auto it = streamedTiles_.find(id);
    if (it == streamedTiles_.end() || it->second.indexCount == 0) continue;
    glBindVertexArray(it->second.vao.id());
    glDrawElements(GL_TRIANGLES, it->second.indexCount, GL_UNSIGNED_INT, nullptr);
    countAndFlush(std::size_t(it->second.indexCount), sinceFlush);
  }
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
}

// The index ranges the frame builder chose (the visible tiles of the layers that are on).
void GlBackend::drawRanges(const std::vector<DrawRange>& draws, std::size_t& sinceFlush) {
  glBindVertexArray(meshVao_.id());
  for (const DrawRange& r : draws)
    if (r.count > 0) {
      glDrawElements(GL_TRIANGLES, r.count, GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(std::uintptr_t(r.first) * sizeof(std::uint32_t)));
      countAndFlush(std::size_t(r.count), sinceFlush);
    }
  glBindVertexArray(0);
}

void GlBackend::drawDepthMap(const DepthMapJob& job) {
  const int slot = job.slot;
  ensureDepthLayer(slot);
  glBindFramebuffer(GL_FRAMEBUFFER, depthFbo_.id());
  if (naive())
    gpu::attachDepth(naiveDepths_[size_t(slot)].id());
  else
    glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, depthArray_.id(), 0, slot);
  gpu::drawToNoColour();
  glReadBuffer(GL_NONE);
  gpu::checkFramebuffer("depth map");
  glViewport(0, 0, job.size, job.size);
  drawDepth(depthProgram_, job.clipFromRender, job.frustum.near, job.frustum.far, job.date, job.draws, job.streamedTiles,
            job.pushBack, job.centerRender);
  if (job.withPoints) {
    // Non-transient points refine the occlusion (2016 §4.2, 2022 §2.4); transient ones never occlude.
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    drawPoints(pointDepthProgram_, job.points, job.camera, job.frustum, {job.size, job.size}, job.centerRender);
    glDisable(GL_DEPTH_TEST);
  }
}

void GlBackend::ensureViewTargets(glm::ivec2 depthSz, glm::ivec2 colorSz) {
  if (depthSz != viewDepthSize_) {
    viewDepth_ = gpu::makeDepthTarget(depthSz.x, depthSz.y);
    viewBuilding_ = gpu::makeRgba8Target(depthSz.x, depthSz.y);
    viewDepthSize_ = depthSz;
  }
  if (colorSz != viewColorSize_) {
    viewColor_ = gpu::makeRgba8Target(colorSz.x, colorSz.y);
    viewColorSize_ = colorSz;
  }
  gpu::checkGlError("view targets");
}

// The view's linear depth over the pinhole rectangle covering the (distorted) view, and the
// building under each pixel. Leaves viewFbo bound.
void GlBackend::viewDepthPass(const Frame& f) {
  const glm::ivec2 depthSz = f.rect.depthSize;
  ensureViewTargets(depthSz, {f.view.width, f.view.height});
  glBindFramebuffer(GL_FRAMEBUFFER, viewFbo_.id());
  gpu::attachColour(viewBuilding_.id());
  gpu::attachDepth(viewDepth_.id());
  gpu::drawToColour();
  gpu::checkFramebuffer("view depth");
  glViewport(0, 0, depthSz.x, depthSz.y);
  const GLfloat noBuilding[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, noBuilding);
  // The view shows today's geometry: every surface, whatever its dates.
  drawDepth(viewDepthProgram_, f.rect.clipFromRender, f.rect.frustum.near, f.rect.frustum.far, DateInterval{}, f.draws,
            f.streamedTiles, 0.0, glm::dvec3(0.0));
}

}  // namespace hv::render::gl
