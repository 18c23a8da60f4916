#include "hv/render/null_backend.h"

#include <algorithm>

namespace hv::render {

void NullBackend::uploadGeometry(const GeometryBuffers& g) {
  triangles = int(g.indices.size() / 3);
  geometry = g;
}

PointProgramInfo NullBackend::uploadPoints(const std::vector<PointVertex>& vertices, const PointProgramRequest& req) {
  points = vertices.size();
  // Every image count links (9 varying components per image within the limit).
  PointProgramInfo info;
  if (req.form == SpriteForm::Mat3) info.mat3Images = std::max(1, std::min(req.wantImages, limits_.maxVaryingComponents / 9));
  info.maxPointSize = float(std::max(1.0, req.maxPointSizePx));
  return info;
}

// Nothing is drawn: the output stays empty and the passes report no statistics.
RenderOutput NullBackend::runViewPasses(const Frame& frame, ViewPassStats& stats) {
  frames.push_back(frame);
  stats = {};
  return {};
}

}  // namespace hv::render
