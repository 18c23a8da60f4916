#include "hv/io/tiles3d_select.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hv {

PointTileSelection::PointTileSelection(Tiles3dTileset tileset, std::vector<Camera> cameras,
                                       std::function<glm::dvec3(const glm::dvec3&)> toScene, double tolerancePx,
                                       std::size_t budget)
    : ts_(std::move(tileset)),
      cameras_(std::move(cameras)),
      toScene_(std::move(toScene)),
      tolerance_(tolerancePx),
      budget_(budget) {}

double PointTileSelection::priority(int t) {
  const Tiles3dTile& tile = ts_.tiles[std::size_t(t)];
  if (cameras_.empty()) return tile.geometricError;
  glm::dvec3 c = tile.bounds.centre;
  if (toScene_) {
    try {
      c = toScene_(c);
    } catch (const std::exception&) {
      c = glm::dvec3(std::numeric_limits<double>::max() / 4);  // outside the map's domain: far away
    }
  }
  double worst = 0.0;
  for (const Camera& cam : cameras_) {
    const double distance = std::max(glm::length(cam.center - c) - tile.bounds.radius, 1e-3);
    worst = std::max(worst, tile.geometricError * std::max(cam.focal.x, cam.focal.y) / distance);
  }
  return worst;
}

bool PointTileSelection::refinable(int t, double p) const {
  if (ts_.tiles[std::size_t(t)].children.empty()) return false;
  return cameras_.empty() ? p > 0.0 : p > tolerance_;
}

// The tiles that stand for `t` when it is drawn: itself when it has content, else its children's.
void PointTileSelection::frontier(int t, std::vector<int>& out) {
  const Tiles3dTile& tile = ts_.tiles[std::size_t(t)];
  if (tile.external) {
    errors_.push_back(tile.content + ": an external tileset, not followed here (expected pnts content; tile " +
                      tile.path + " left out)");
    return;
  }
  if (!tile.content.empty()) {
    out.push_back(t);
    return;
  }
  for (int k : tile.children) frontier(k, out);
}

void PointTileSelection::arrived(int tile, PointCloud points) {
  ++read_;
  got_[tile] = std::move(points);
}

void PointTileSelection::failed(int tile, const std::string& message) {
  errors_.push_back(message + " (tile " + ts_.tiles[std::size_t(tile)].path + " left out)");
}

void PointTileSelection::accept(const std::vector<int>& tiles) {
  for (int t : tiles) {
    if (auto g = got_.find(t); g != got_.end()) {
      total_ += g->second.size();
      selected_[t] = std::move(g->second);
    }
    if (const double p = priority(t); refinable(t, p)) queue_.push({p, t});
  }
  got_.clear();
}

std::vector<int> PointTileSelection::next() {
  if (state_ == -3) {
    frontier(0, batch_);
    state_ = -1;
    if (!batch_.empty()) return batch_;
  }
  if (state_ == -1) {
    accept(batch_);
  } else if (state_ >= 0) {
    const int t = state_;
    const bool replace = ts_.tiles[std::size_t(t)].refine == TileRefine::Replace;
    std::size_t added = 0;
    for (const auto& [k, c] : got_) added += c.size();
    const auto own = selected_.find(t);
    const std::size_t removed = replace && own != selected_.end() ? own->second.size() : 0;
    if (total_ + added - removed > budget_) {
      budgetLimited_ = true;  // a smaller refinement further down the queue may still fit
      got_.clear();
    } else {
      if (replace && own != selected_.end()) {
        total_ -= removed;
        selected_.erase(own);
      }
      accept(batch_);
    }
  }
  state_ = -2;
  batch_.clear();
  while (!queue_.empty()) {
    const int t = queue_.top().second;
    queue_.pop();
    for (int k : std::vector<int>(ts_.tiles[std::size_t(t)].children)) frontier(k, batch_);
    if (batch_.empty()) continue;
    state_ = t;
    return batch_;
  }
  return {};
}

PointCloud PointTileSelection::points() const {
  PointCloud into;
  for (const auto& [t, add] : selected_) into.append(add);
  return into;
}

}  // namespace hv
