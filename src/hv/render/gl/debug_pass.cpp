// The debug views (RenderSettings::debug): contributing images per pixel, one photograph's share
// of the blend (Brédif 2013 eq. 2), and one photograph's depth map letterboxed into the view;
// coloured with hv::colorRamp, their raw values read back.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/render/gl/programs.h"
#include "hv/image/colormap.h"

#include <algorithm>
#include <cmath>

namespace hv::render::gl {

// Draws the frame's debug view into the colour target (viewFbo bound, the shading program's
// inputs set). Returns its raw values when the colour is read back.
Image16 GlBackend::debugViewPass(const Frame& f, ViewPassStats& stats) {
  const int w = f.view.width, h = f.view.height;
  const bool raw = f.readBackColour;
  switch (f.debug.view) {
    case DebugView::Counts: {
      Image16 values = raw ? decodeCounts(shade(kShadeCount, w, h, true)) : Image16{};
      shade(kShadeCountColour, w, h, false);
      return values;
    }
    case DebugView::Weight: {
      Image16 values = raw ? decodeCounts(shade(kShadeShare, w, h, true)) : Image16{};
      shade(kShadeShareColour, w, h, false);
      return values;
    }
    case DebugView::DepthMap: {
      Image16 values = depthMapView(f, stats);
      return raw ? values : Image16{};
    }
    case DebugView::None:
      break;
  }
  return {};
}

// DebugView::DepthMap: the slot's depth map letterboxed into the colour target. The raw values are
// read back (always: the colours span the nearest to the farthest stored depth, a range only a
// reduction finds) and the coloured picture uploaded over them.
Image16 GlBackend::depthMapView(const Frame& f, ViewPassStats& stats) {
  const int w = f.view.width, h = f.view.height;
  int slot = f.debug.slot;
  stats.debugDepthNear = stats.debugDepthFar = 0.0;
  if (slot >= 0 && naive()) {
    if (!warnedDebugNaive_) diag_.warn("the depth-map debug view needs the texture-array binding");
    warnedDebugNaive_ = true;
    slot = -1;
  }
  const hv::PinholeFrustum& fr = f.debug.slotFrustum;
  Image16 values(w, h, 1, 65535);
  std::vector<bool> inside(size_t(w) * h, false);
  if (slot >= 0) {
    if (!debugDepthProgram_.program.id()) {
      debugDepthProgram_ = DebugDepthProgram(programs().debugDepth);
    }
    // The map covers the frustum's ideal rectangle: shown with that aspect ratio, centred.
    const double aspect = (fr.pxMax.x - fr.pxMin.x) / (fr.pxMax.y - fr.pxMin.y);
    const glm::dvec2 rect = aspect * h > w ? glm::dvec2(w, w / aspect) : glm::dvec2(h * aspect, h);
    const glm::dvec2 rectMin = (glm::dvec2(w, h) - rect) / 2.0;
    ensureDepthLayer(slot);  // a slot never drawn reads a cleared layer, as with every layer at start
    const DebugDepthProgram& p = debugDepthProgram_;
    p.program.use();
    gpu::bindUnit(kUnitDepthMaps, GL_TEXTURE_2D_ARRAY, depthArray_.id());
    glUniform1i(p.depthMaps, kUnitDepthMaps);
    glUniform1f(p.slice, float(slot));
    glUniform2f(p.rectMin, float(rectMin.x), float(rectMin.y));
    glUniform2f(p.rectSize, float(rect.x), float(rect.y));
    gpu::drawFullscreen(emptyVao_);
    const Image8 enc = readColour(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        values.at(x, y, 0) = std::uint16_t(enc.at(x, y, 0) + 256 * enc.at(x, y, 1));
        inside[size_t(y) * w + x] = enc.at(x, y, 2) > 127;
      }
    shade_->program.use();
  }
  int lo = 65535, hi = 0;
  for (size_t i = 0; i < inside.size(); ++i)
    if (inside[i] && values.data[i] < 65535) {
      lo = std::min<int>(lo, values.data[i]);
      hi = std::max<int>(hi, values.data[i]);
    }
  if (lo <= hi) {
    stats.debugDepthNear = fr.near + lo / 65535.0 * (fr.far - fr.near);
    stats.debugDepthFar = fr.near + hi / 65535.0 * (fr.far - fr.near);
  }
  // Near bright (yellow), far dark; black where the photograph sees nothing; the background
  // colour outside the map.
  Image8 rgba(w, h, 4, 0);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = size_t(y) * w + x;
      std::uint8_t* o = rgba.px(x, y);
      glm::dvec3 c = f.background;
      if (inside[i]) c = glm::dvec3(0.0);
      if (inside[i] && values.data[i] < 65535) {
        c = colorRamp(hi > lo ? double(hi - values.data[i]) / (hi - lo) : 1.0);
        o[3] = 255;
      }
      for (int k = 0; k < 3; ++k) o[k] = std::uint8_t(std::lround(255.0 * std::clamp(c[k], 0.0, 1.0)));
    }
  glBindTexture(GL_TEXTURE_2D, viewColor_.id());
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data.data());
  gpu::checkGlError("depth-map debug view");
  return values;
}

}  // namespace hv::render::gl
