// Building tiles streamed per view (docs/design.md, "Building streaming"): buildings too many to
// load whole (hv/scene/building_tiles.h) read by tile for the cameras that see them, extruded off
// the render thread and kept under a byte budget with least-recently-used eviction (de Castro &
// Brédif 2022: data in tiles, fetched for the view, within a memory budget). The terrain's
// counterpart (render/terrain_stream.h), on the same work queue (render/tile_queue.h). GL-free:
// the frame builder uploads what poll() hands back.
//
// - A camera's cut is the resident tiles whose box may be inside its clip volume; the tiles it
//   lacks are requested (priority: the caller's, plus the tile's distance to the camera) and
//   drawn once they arrive, so a frame always completes (with no building before any arrives).
//   A tile owns its buildings (one building crossing tile borders is in one tile), so the union
//   of the tiles is the whole load, each building once.
// - Building indices (the vertices' building index + 1, the validity texture's texels) are given
//   to a tile when it arrives: a contiguous range, freed when it is evicted. The picture does
//   not depend on which: an index only looks up its building's validity.
// - A tile read once is known by the box of its buildings and its bytes from then on, evicted or
//   not: a camera that does not see its buildings does not read it again (the source's box, wider,
//   is only for tiles never read); a tile without buildings is never drawn nor kept.
// - Budget: a cut takes its tiles nearest first while the bytes of the tiles the frame uses (with
//   `reservedBytes`, what the terrain's cuts use: one budget for both) fit `memoryBytes`, the
//   missing ones counted at their known bytes (none before their first read); the rest are left
//   out (budgetLimited) and not requested. endFrame() evicts the least recently used
//   tiles the frame did not use until the resident bytes (with the terrain's) fit.
// - A tile that cannot be read (the source throws: a service answering 500, a connection reset)
//   is reported by poll() with its attempt and asked for again after a back-off (RetryPolicy:
//   `first`, doubled at each failure up to `cap`), while a camera still wants it; after `attempts`
//   failures it is given up (reported so) and never asked for again. Until its next try it is not
//   requested and not counted missing, so a batch frame does not wait for it.
#pragma once

#include "hv/camera/camera.h"
#include "hv/render/tile_queue.h"
#include "hv/scene/building_tiles.h"

#include <glm/glm.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

namespace hv::render {

// One tile as the GPU takes it: per vertex the render-frame position, its building's validity
// days and its building index + 1 (GeometryBuffers' layout); its box in the render frame.
struct BuildingTileMesh {
  std::uint32_t tile = 0;
  std::vector<float> vertices;  // GeometryBuffers::kStride floats a vertex
  std::vector<std::uint32_t> indices;
  glm::vec3 lo{0.0f}, hi{0.0f};
  std::uint32_t firstBuilding = 0;    // its buildings' indices: firstBuilding ..
  std::vector<glm::vec2> validity;    // .. + validity.size() - 1, their days (ibr::gpuDays)
  std::vector<std::string> warnings;  // the source's, for the caller to report
  std::string error;                  // non-empty: the tile could not be read, nothing else is set
  int attempt = 1;                    // the how-manieth read of this tile this is
  bool retrying = false;              // with `error`: it will be asked for again (RetryPolicy)
};

// When a building tile that failed is asked for again (BuildingStream, above).
struct BuildingRetryPolicy {
  std::chrono::milliseconds first{1000};  // the wait after the first failure
  std::chrono::milliseconds cap{60000};   // the longest wait
  int attempts = 6;                       // reads in all before the tile is given up
};

struct BuildingCut {
  std::vector<std::uint32_t> tiles;  // resident, sorted, those the clip volume may see
  int missing = 0;                   // tiles it waits for (requested, not resident yet)
  bool budgetLimited = false;        // some tile it may see left out by the budget
  bool operator==(const BuildingCut& o) const { return tiles == o.tiles; }
};

// The width and height, in ideal (pinhole, lens distortion aside) pixels of `camera`, of the
// rectangle holding the pictures of the 8 corners of the world-frame box lo..hi: a bound of the
// box's picture (a pinhole projects the box, the convex hull of its corners, inside the hull of
// their pictures). Infinite when a corner is not in front of the camera (depth <= 0: the box
// reaches the camera's plane and may fill the picture).
glm::dvec2 boxPixelExtent(const Camera& camera, const glm::dvec3& lo, const glm::dvec3& hi);

class BuildingStream {
 public:
  // Meshes are in the render frame (world minus `origin`). Throws std::invalid_argument for a
  // null set or one without a reader, a negative thread count or a zero budget.
  BuildingStream(std::shared_ptr<const BuildingTileSet> set, glm::dvec3 origin, int workerThreads,
                 std::size_t memoryBytes);
  BuildingStream(const BuildingStream&) = delete;
  BuildingStream& operator=(const BuildingStream&) = delete;

  // A new frame: the tiles its cuts use are counted again from none, after `reservedBytes` (the
  // terrain's share of the budget this frame).
  void beginFrame(std::size_t reservedBytes = 0);
  // The cut for `camera` through `clipFromRender` (its clip volume, render frame), of the tiles
  // whose box comes within `reach` of the camera's centre (infinite: no limit; the scene loader's
  // rule for photographs is kBuildingReachMetresPerPixel x the focal length in pixels) and, when
  // `minPixels` > 0, whose box's picture is at least `minPixels` thick (the smaller side of
  // boxPixelExtent: a thinner tile would be a sliver of at most that many pixels; a tile never
  // read is judged by the source's box, which is kept); marks its tiles used by this frame and
  // requests the ones it lacks at `priority` plus their distance.
  BuildingCut select(const Camera& camera, const glm::dmat4& clipFromRender, double priority,
                     double reach = std::numeric_limits<double>::infinity(), double minPixels = 0.0);
  // Evicts the least recently used tiles this frame did not use until the resident bytes plus
  // `otherResidentBytes` (the terrain's) fit the budget. Returns the evicted tiles.
  std::vector<std::uint32_t> endFrame(std::size_t otherResidentBytes = 0);

  // Never blocks on reads: the tiles finished so far (meshes handed over). With no worker threads
  // it first reads the queue's head on this thread, then more while `inlineBudget` has not elapsed.
  std::vector<BuildingTileMesh> poll(std::chrono::microseconds inlineBudget = std::chrono::microseconds(0));
  // Blocks until nothing is queued or being read, handing every result to `sink` as it arrives.
  void waitAll(const std::function<void(BuildingTileMesh&&)>& sink);

  std::size_t tileCount() const { return set_->boxes.size(); }
  bool boxOf(std::uint32_t tile, glm::vec3& lo, glm::vec3& hi) const;  // resident, non-empty
  std::size_t residentTiles() const { return resident_.size(); }
  std::size_t residentBuildings() const { return residentBuildings_; }
  std::size_t trianglesOf(std::uint32_t tile) const;  // a resident tile's (0: not resident)
  std::size_t pendingTiles() const { return queue_->pending(); }
  std::size_t residentBytes() const { return residentBytes_; }
  std::size_t frameBytes() const { return frameBytes_; }
  std::size_t peakBytes() const { return peakBytes_; }
  std::size_t memoryBudget() const { return budget_; }
  std::size_t evictions() const { return evictions_; }
  std::size_t brokenTiles() const;   // given up
  std::size_t retryingTiles() const;  // failed, waiting for their next try
  void setRetryPolicy(const BuildingRetryPolicy& p) { retry_ = p; }
  const BuildingRetryPolicy& retryPolicy() const { return retry_; }
  // "<source>: tile N" (BuildingTileSet::source), how a tile is named in the list of what is missing.
  std::string tileName(std::uint32_t tile) const;
  int workerThreads() const { return queue_->workerThreads(); }
  // One past the largest building index given (the validity texture's size).
  std::uint32_t buildingIndexEnd() const { return indexEnd_; }

  // The bytes a tile mesh takes (vertices and indices): its share of the budget.
  static std::size_t meshBytes(const BuildingTileMesh& m);

 private:
  struct Resident {
    std::size_t bytes = 0;
    glm::vec3 lo{0.0f}, hi{0.0f};
    std::size_t triangles = 0;
    std::uint32_t firstBuilding = 0, buildings = 0;
    std::uint64_t lastUsed = 0;
  };
  // What is known of a tile once read, kept after it is evicted: its buildings' box and bytes
  // (a tile the cameras do not see is not read again; the budget counts it before it arrives).
  struct Known {
    bool read = false, empty = false, broken = false;
    int failures = 0;                                // reads that failed since the last success
    std::chrono::steady_clock::time_point retryAt;  // with failures and not broken: not asked before
    glm::vec3 lo{0.0f}, hi{0.0f};
    std::size_t bytes = 0;
  };
  struct Job {};

  BuildingTileMesh read(std::uint32_t tile) const;
  std::vector<BuildingTileMesh> collect(std::deque<BuildingTileMesh>& done);
  std::uint32_t allocateIndices(std::uint32_t count);
  void freeIndices(std::uint32_t first, std::uint32_t count);

  const std::shared_ptr<const BuildingTileSet> set_;
  const glm::dvec3 origin_;
  const std::size_t budget_;
  std::vector<Aabb> renderBoxes_;  // set_->boxes minus the origin

  // Render thread only.
  std::unordered_map<std::uint32_t, Resident> resident_;
  std::vector<Known> known_;
  std::set<std::uint32_t> usedThisFrame_;
  std::map<std::uint32_t, std::uint32_t> freeIndices_;  // first -> count
  std::uint32_t indexEnd_ = 0;
  std::size_t frameBytes_ = 0, reservedBytes_ = 0, residentBytes_ = 0, peakBytes_ = 0, evictions_ = 0;
  std::size_t residentBuildings_ = 0;
  std::uint64_t frame_ = 0;
  BuildingRetryPolicy retry_;

  // Last: destroyed (its workers joined) before anything they read.
  std::unique_ptr<TileQueue<Job, BuildingTileMesh>> queue_;
};

}  // namespace hv::render
