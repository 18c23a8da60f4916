// The choice of a 3D Tiles point tileset's tiles by screen-space error (docs/formats.md, "Points
// from 3D Tiles"), without fetching: the caller fetches each batch of contents it is given (the
// browser page, a few requests at a time; apps/web/hv_web_tiles.cpp) and reports each tile as
// arrived or failed before asking for the next batch. The rule is the native reader's
// (hv/io/native/points_tiles.h): a tile is refined while its screen-space error from some camera
// (geometric error x focal length in pixels / distance from the camera to its bounding sphere)
// exceeds the tolerance, largest first, as long as the points stay within the budget; without
// cameras, by geometric error. External tilesets are not followed here (named and left out).
#pragma once

#include "hv/camera/camera.h"
#include "hv/io/tiles3d.h"
#include "hv/scene/point_cloud.h"

#include <cstddef>
#include <functional>
#include <map>
#include <queue>
#include <string>
#include <utility>
#include <vector>

namespace hv {

class PointTileSelection {
 public:
  // `toScene`: the tileset frame into the scene frame of `cameras` (tile centres, for the
  // screen-space error; a throw puts the tile far from every camera).
  PointTileSelection(Tiles3dTileset tileset, std::vector<Camera> cameras,
                     std::function<glm::dvec3(const glm::dvec3&)> toScene, double tolerancePx, std::size_t budget);

  const Tiles3dTileset& tileset() const { return ts_; }
  // The tiles whose contents to fetch next (indices into tileset().tiles); empty: the selection is
  // complete. Each must be reported (arrived or failed) before the next call.
  std::vector<int> next();
  // A tile's points, already in the tileset frame (its transform applied).
  void arrived(int tile, PointCloud points);
  // A tile that could not be fetched or read: `message` names the URL and what was expected.
  void failed(int tile, const std::string& message);

  // The kept tiles' points, appended in tile order, in the tileset frame (fields all tiles share).
  PointCloud points() const;
  std::size_t tilesRead() const { return read_; }
  std::size_t tilesKept() const { return selected_.size(); }
  bool budgetLimited() const { return budgetLimited_; }
  // One message per tile left out: "URL: … (tile root.children[2] left out)".
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  double priority(int t);
  bool refinable(int t, double p) const;
  void frontier(int t, std::vector<int>& out);
  void accept(const std::vector<int>& tiles);

  Tiles3dTileset ts_;
  std::vector<Camera> cameras_;
  std::function<glm::dvec3(const glm::dvec3&)> toScene_;
  double tolerance_;
  std::size_t budget_;
  int state_ = -3;  // -3: not started; -1: the first batch out; t >= 0: the children of t out; -2: none out
  std::vector<int> batch_;
  std::map<int, PointCloud> got_;       // the batch's arrivals
  std::map<int, PointCloud> selected_;  // tile -> its points
  std::size_t total_ = 0, read_ = 0;
  bool budgetLimited_ = false;
  std::priority_queue<std::pair<double, int>> queue_;
  std::vector<std::string> errors_;
};

}  // namespace hv
