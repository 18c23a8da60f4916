#include "hv/io/native/points_tiles.h"

#include "hv/io/tiles3d.h"
#include "hv/util/input_file.h"
#include "hv/util/log.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <queue>
#include <thread>

namespace hv {
namespace {

// Pnts tiles are fetched whole, at most this large each.
constexpr std::uint64_t kMaxPntsBytes = std::uint64_t(1) << 30;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

struct Fetched {
  std::optional<PointCloud> points;  // in the tileset frame
  std::uint64_t bytes = 0;
  std::string error;
  std::vector<std::string> notes;
};

// One pnts content: fetched (through the response cache when by URL), parsed, brought into the
// tileset frame by the tile's transform (normals by its inverse transpose).
Fetched fetchTile(const Tiles3dTile& tile) {
  Fetched f;
  try {
    const std::vector<std::uint8_t> bytes =
        readInputBytes(tile.content, kMaxPntsBytes, "points tile", RemoteCache::Yes);
    f.bytes = bytes.size();
    PntsTile t = parsePnts(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), tile.content);
    PointCloud& c = t.points;
    for (glm::dvec3& p : c.positions) p = glm::dvec3(tile.transform * glm::dvec4(p, 1.0));
    if (!c.normals.empty()) {
      const glm::dmat3 turn = glm::inverse(glm::transpose(glm::dmat3(tile.transform)));
      for (glm::vec3& n : c.normals) {
        const glm::dvec3 m = turn * glm::dvec3(n);
        const double len = glm::length(m);
        n = len > 0.0 && std::isfinite(len) ? glm::vec3(m / len) : glm::vec3(0, 0, 1);
      }
    }
    f.points = std::move(c);
    f.notes = std::move(t.notes);
  } catch (const std::exception& e) {
    f.error = std::string(e.what()) + " (tile " + tile.path + " left out)";
  }
  return f;
}

}  // namespace

bool isTilesetPath(const std::string& path) {
  const std::string p = lower(path.substr(0, path.find_first_of("?#")));
  const std::string name = "tileset.json";
  return p.size() >= name.size() && p.compare(p.size() - name.size(), name.size(), name) == 0;
}

PointCloud loadPointTileset(const PointTilesetRequest& request, const std::vector<Camera>& cameras, Diagnostics& diag,
                            PointTilesetInfo* infoOut) {
  const auto t0 = std::chrono::steady_clock::now();
  PointCloud cloud;
  cloud.sourcePath = request.url;
  cloud.crs = request.georef.crs.empty() ? kTilesetDefaultCrs : request.georef.crs;
  PointTilesetInfo info;

  const std::string text = readTextFile(request.url, kMaxJsonBytes, "3D Tiles tileset");
  info.bytes += text.size();
  Tiles3dTileset ts = parseTileset(text, request.url);

  // Tile bounding spheres in the scene frame, for the screen-space error (the radius kept in
  // metres: the scene frames are metric).
  std::optional<GeoTransform> toScene;
  // (Its warnings are the points' georeferencing's, given once by the caller.)
  Diagnostics quiet;
  if (!request.georef.sceneCrs.empty()) toScene.emplace(sourceTransform(request.georef, cloud.crs, request.url, quiet));
  std::vector<std::optional<glm::dvec3>> centres;
  auto centreOf = [&](int t) {
    if (centres.size() < ts.tiles.size()) centres.resize(ts.tiles.size());
    auto& c = centres[std::size_t(t)];
    if (!c) {
      c = ts.tiles[std::size_t(t)].bounds.centre;
      if (toScene && !toScene->isIdentity()) {
        try {
          c = toScene->point(*c);
        } catch (const InputError&) {
          // Outside the scene CRS's domain: far from every camera.
          c = glm::dvec3(std::numeric_limits<double>::max() / 4);
        }
      }
    }
    return *c;
  };
  auto priority = [&](int t) {
    const Tiles3dTile& tile = ts.tiles[std::size_t(t)];
    if (cameras.empty()) return tile.geometricError;
    double worst = 0.0;
    const glm::dvec3 c = centreOf(t);
    for (const Camera& cam : cameras) {
      const double distance = std::max(glm::length(cam.center - c) - tile.bounds.radius, 1e-3);
      worst = std::max(worst, tile.geometricError * std::max(cam.focal.x, cam.focal.y) / distance);
    }
    return worst;
  };
  auto refinable = [&](int t, double p) {
    const Tiles3dTile& tile = ts.tiles[std::size_t(t)];
    if (tile.children.empty()) return false;
    return cameras.empty() ? p > 0.0 : p > request.tolerancePx;
  };

  // External tilesets are read when the traversal reaches them and grafted in their tile's place.
  auto resolveExternal = [&](int t) {
    Tiles3dTile& tile = ts.tiles[std::size_t(t)];
    if (!tile.external) return;
    const std::string url = tile.content, path = tile.path;
    const glm::dmat4 transform = tile.transform;
    const TileRefine refine = tile.refine;
    const int depth = tile.depth + 1;
    try {
      const std::string sub = readTextFile(url, kMaxJsonBytes, "3D Tiles tileset");
      info.bytes += sub.size();
      graftTileset(ts, t, parseTileset(sub, url, transform, refine, depth));
    } catch (const InputError& e) {
      ts.tiles[std::size_t(t)].content.clear();
      ts.tiles[std::size_t(t)].external = false;
      ++info.tilesFailed;
      diag.error(std::string(e.what()) + " (tile " + path + " left out)");
      info.failed.push_back({url, e.what()});
    }
  };
  // The tiles that stand for `t` when it is drawn: itself when it has content, else (an empty
  // tile, or an external tileset's) its children's, recursively.
  std::function<void(int, std::vector<int>&)> frontier = [&](int t, std::vector<int>& out) {
    resolveExternal(t);
    const Tiles3dTile& tile = ts.tiles[std::size_t(t)];
    if (!tile.content.empty()) {
      out.push_back(t);
      return;
    }
    const std::vector<int> kids = tile.children;  // copy: grafting appends to ts.tiles
    for (int k : kids) frontier(k, out);
  };
  // Fetches the contents of `tiles`, kPointTilesConcurrency at a time.
  auto fetchAll = [&](const std::vector<int>& tiles) {
    std::vector<Fetched> out(tiles.size());
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
      for (std::size_t k; (k = next++) < tiles.size();) out[k] = fetchTile(ts.tiles[std::size_t(tiles[k])]);
    };
    const std::size_t threads = std::min<std::size_t>(tiles.size(), kPointTilesConcurrency);
    std::vector<std::thread> pool;
    for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
    for (std::thread& t : pool) t.join();
    for (std::size_t k = 0; k < out.size(); ++k) {
      info.bytes += out[k].bytes;
      if (out[k].points) ++info.tilesRead;
      for (const std::string& n : out[k].notes) log::debug("points: " + n);
    }
    return out;
  };

  std::map<int, PointCloud> selected;  // tile -> its points, in the tileset frame
  std::size_t total = 0;
  std::priority_queue<std::pair<double, int>> queue;
  auto accept = [&](const std::vector<int>& tiles, std::vector<Fetched>& got) {
    for (std::size_t k = 0; k < tiles.size(); ++k) {
      if (!got[k].points) {
        ++info.tilesFailed;
        diag.error(got[k].error);
        info.failed.push_back({ts.tiles[std::size_t(tiles[k])].content, got[k].error});
      } else {
        total += got[k].points->size();
        selected[tiles[k]] = std::move(*got[k].points);
      }
      if (const double p = priority(tiles[k]); refinable(tiles[k], p)) queue.push({p, tiles[k]});
    }
  };
  std::vector<int> first;
  frontier(0, first);
  {
    std::vector<Fetched> got = fetchAll(first);
    accept(first, got);
  }
  // Empty tiles (no content) whose children were taken in their place are refined already; the
  // others, largest screen-space error first, while the points stay within the budget.
  while (!queue.empty()) {
    const int t = queue.top().second;
    queue.pop();
    std::vector<int> kids;
    for (int k : std::vector<int>(ts.tiles[std::size_t(t)].children)) frontier(k, kids);
    std::vector<Fetched> got = fetchAll(kids);
    const bool replace = ts.tiles[std::size_t(t)].refine == TileRefine::Replace;
    std::size_t added = 0;
    for (const Fetched& f : got) added += f.points ? f.points->size() : 0;
    const auto own = selected.find(t);
    const std::size_t removed = replace && own != selected.end() ? own->second.size() : 0;
    if (total + added - removed > request.budget) {
      info.budgetLimited = true;
      continue;  // a smaller refinement further down the queue may still fit
    }
    if (replace && own != selected.end()) {
      total -= removed;
      selected.erase(own);
    }
    accept(kids, got);
  }

  info.tilesInTileset = ts.tiles.size();
  info.tilesKept = selected.size();
  for (const auto& [t, points] : selected) cloud.append(points);
  for (const std::string& n : ts.notes) diag.warn(n);
  if (info.budgetLimited)
    diag.warn(inputMessage(request.url, "points.budget",
                           "the point budget of " + std::to_string(request.budget) +
                               " points stopped the refinement: some tiles are coarser than the tolerance asks"));
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log::debug("points: " + request.url + ": " + std::to_string(info.tilesRead) + " tiles read of " +
             std::to_string(info.tilesInTileset) + ", " + std::to_string(info.tilesKept) + " kept, " +
             std::to_string(info.bytes) + " bytes, " + std::to_string(cloud.size()) + " points, " + std::to_string(s) +
             " s");
  if (infoOut) *infoOut = info;
  return cloud;
}

}  // namespace hv
