#include "hv/pose/pose_session.h"

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace hv::pose {

PoseSession::PoseSession(const Camera& photo, bool solveFocal) : photo_(photo), solveFocal_(solveFocal) {
  message_ = "click a point on the photograph, then the same point in the 3D view (" + std::to_string(pairsNeeded()) +
             " pairs or more)";
}

void PoseSession::setSolveFocal(bool on) {
  if (on == solveFocal_) return;
  solveFocal_ = on;
  solve();
}

bool PoseSession::clickPhoto(glm::dvec2 px) {
  if (!(px.x >= 0.0 && px.y >= 0.0 && px.x <= photo_.width && px.y <= photo_.height)) {
    message_ = "that click is outside the photograph";
    return false;
  }
  pending_ = px;
  message_ = "now click the same point in the 3D view";
  return true;
}

bool PoseSession::clickScene(const std::optional<glm::dvec3>& world) {
  if (!pending_) {
    message_ = "click the point on the photograph first";
    return false;
  }
  if (!world) {
    message_ = "no surface under that click (the sky?): click the point on a building, the terrain or the mesh";
    return false;
  }
  pairs_.push_back({*pending_, *world});
  pending_.reset();
  solve();
  return true;
}

bool PoseSession::removePair(int index) {
  if (index < 0 || index >= int(pairs_.size())) return false;
  pairs_.erase(pairs_.begin() + index);
  solve();
  return true;
}

bool PoseSession::movePair(int index, glm::dvec2 px) {
  if (index < 0 || index >= int(pairs_.size())) {
    message_ = "no pair " + std::to_string(index + 1) + " to move";
    return false;
  }
  if (!(px.x >= 0.0 && px.y >= 0.0 && px.x <= photo_.width && px.y <= photo_.height)) {
    message_ = "pair " + std::to_string(index + 1) + " cannot leave the photograph";
    return false;
  }
  pairs_[size_t(index)].pixel = px;
  solve();
  return true;
}

void PoseSession::solve() {
  const int n = int(pairs_.size());
  if (n < pairsNeeded()) {
    if (solution_) ++version_;
    solution_.reset();
    message_ = std::to_string(n) + " pair(s): " + std::to_string(pairsNeeded() - n) + " more to solve the camera";
    return;
  }
  std::vector<pose::ControlPoint> points;
  for (int i = 0; i < n; ++i) {
    pose::ControlPoint p;
    p.pixel = pairs_[size_t(i)].pixel;
    p.world = pairs_[size_t(i)].world;
    p.label = "pair " + std::to_string(i + 1);
    points.push_back(p);
  }
  pose::PoseOptions options;
  options.refine.focal = solveFocal_;
  try {
    solution_ = pose::solvePose(points, photo_, false, options);
    ++version_;
    char line[160];
    std::snprintf(line, sizeof line, "solved from %d pairs (%d inliers): %.2f px RMS", n, solution_->inlierCount,
                  solution_->rmsPixels);
    message_ = line;
  } catch (const std::exception& e) {
    if (solution_) ++version_;
    solution_.reset();
    message_ = std::string("not solved: ") + e.what();
  }
}

std::vector<ResidualLine> PoseSession::residualLines() const {
  std::vector<ResidualLine> lines;
  if (!solution_) return lines;
  for (size_t i = 0; i < pairs_.size(); ++i) {
    ResidualLine l;
    l.clicked = pairs_[i].pixel;
    const Projection p = solution_->camera.project(pairs_[i].world);
    l.projected = p.pxDistorted;
    l.pixels = glm::distance(l.clicked, l.projected);
    l.inlier = i < solution_->inliers.size() && solution_->inliers[i];
    lines.push_back(l);
  }
  return lines;
}

WorldRay rayThroughPixel(const Camera& view, glm::dvec2 px) {
  WorldRay r;
  const std::optional<glm::dvec2> ideal = view.undistort(px);
  if (!ideal) return r;
  r.origin = view.center;
  r.direction = view.rayDirection(*ideal);
  r.valid = true;
  return r;
}

std::string checkSavePath(const std::string& path, const std::vector<std::string>& inputs, bool exists, bool replace) {
  namespace fs = std::filesystem;
  if (path.empty()) return "give the cameras.json to write";
  std::error_code ec;
  const fs::path out = fs::absolute(path, ec).lexically_normal();
  for (const std::string& in : inputs) {
    if (in.empty()) continue;
    const fs::path p = fs::absolute(in, ec).lexically_normal();
    if (p == out) return path + " is one of the viewer's input files: choose another name";
  }
  if (exists && !replace) return path + " exists: tick \"replace\" to overwrite it, or choose another name";
  return {};
}

}  // namespace hv::pose
