// Terrain tiles streamed per view (docs/design.md, "Terrain streaming"): the quadtree of a DTM too
// large to mesh whole (hv/scene/terrain_quadtree.h) cut for each camera by screen-space error
// (Ulrich 2002), its tiles read and triangulated off the render thread, kept under a byte budget
// with least-recently-used eviction (de Castro & Brédif 2022: data in tiles, fetched for the
// view, within a memory budget). GL-free: the frame builder uploads what poll() hands back.
//
// - A cut refines only through resident tiles: a node whose children are not all resident is
//   drawn as it is and its missing children are requested, so a frame always has a surface to
//   draw (the nearest resident ancestor, or nothing before the root arrives) and improves as
//   tiles arrive. Once everything a camera needs is resident its cut is the one the quadtree's
//   own selection makes (TerrainQuadtree::select), whatever order the tiles came in.
// - Requests are ordered by priority (lower first; the frame builder passes: in the view's frustum
//   before the photographs', before the rest; nearer first) and deduplicated.
// - workerThreads > 0: that many threads read and triangulate. workerThreads == 0 (the browser
//   build, no threads): poll() does a bounded amount of that work on the caller's thread and
//   waitAll() does all of it, as ibr::ImageLoader does with photographs.
// - Budget: the cuts of one frame (every camera's, ancestors included) refine only while the
//   bounds of their tiles' bytes (tileBytesBound) fit in `memoryBytes`; endFrame() then evicts the
//   least recently used tiles the frame did not use until the resident tiles fit. A tile's bytes
//   are its GPU mesh (6 floats a vertex, 3 indices a triangle) and its samples, kept for its
//   children's skirts and errors.
// - A tile that cannot be read (the source throws) is reported once by poll() and never asked for
//   again: its parent stays in the cuts.
//
// Member functions are meant to be called from one thread (the render thread); the reads go
// through the work queue the building stream shares (render/tile_queue.h).
#pragma once

#include "hv/camera/camera.h"
#include "hv/render/tile_queue.h"
#include "hv/scene/terrain_quadtree.h"

#include <glm/glm.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <vector>

namespace hv::render {

// One tile as the GPU takes it: per vertex the render-frame position, the days it exists (always)
// and no building (GeometryBuffers' layout); its box in the render frame.
struct TerrainTileMesh {
  TerrainNodeId id = 0;
  std::vector<float> vertices;  // GeometryBuffers::kStride floats a vertex
  std::vector<std::uint32_t> indices;
  glm::vec3 lo{0.0f}, hi{0.0f};
  std::string error;  // non-empty: the tile could not be read, nothing else is set
};

// One camera's cut of the quadtree in the current frame.
struct TerrainCut {
  std::vector<TerrainNodeId> nodes;  // resident, sorted: they cover the raster's extent once
  int missing = 0;                   // tiles the cut waits for (requested, not resident yet)
  bool budgetLimited = false;        // some node above the tolerance left unrefined by the budget
  bool operator==(const TerrainCut& o) const { return nodes == o.nodes; }
};

class TerrainStream {
 public:
  // Meshes are in the render frame (world minus `origin`). Throws std::invalid_argument for a
  // null tree, a negative thread count or a zero budget.
  TerrainStream(const TerrainQuadtree& tree, glm::dvec3 origin, int workerThreads, std::size_t memoryBytes);
  ~TerrainStream();
  TerrainStream(const TerrainStream&) = delete;
  TerrainStream& operator=(const TerrainStream&) = delete;

  // A new frame: the tiles its cuts use are counted again from none.
  void beginFrame();
  // The cut for `camera` at `tolerancePx`, within what is left of the budget this frame; marks its
  // tiles (and their ancestors) used by this frame and requests what it waits for at `priority`
  // plus the tile's distance to the camera (its footprint with its parent's heights), plus
  // kOutOfViewPenalty when `clipFromRender` is given and the tile is outside that clip volume.
  TerrainCut select(const Camera& camera, double tolerancePx, double priority,
                    const glm::dmat4* clipFromRender = nullptr);
  static constexpr double kOutOfViewPenalty = 1e9;  // metres: after everything in view
  // Evicts the least recently used tiles this frame did not use until the resident ones fit the
  // budget. Returns the evicted tiles (for the GPU to free).
  std::vector<TerrainNodeId> endFrame();

  // Never blocks on reads: the tiles finished so far (meshes handed over; the stream keeps the
  // samples). With no worker threads it first reads the queue's head on this thread, then more
  // while `inlineBudget` has not elapsed.
  std::vector<TerrainTileMesh> poll(std::chrono::microseconds inlineBudget = std::chrono::microseconds(0));
  // Blocks until nothing is queued or being read, handing every result to `sink` as it arrives.
  void waitAll(const std::function<void(TerrainTileMesh&&)>& sink);

  // A resident tile's box in the render frame, skirts included (false: not resident or empty).
  bool boxOf(TerrainNodeId id, glm::vec3& lo, glm::vec3& hi) const;
  std::size_t residentTiles() const { return resident_.size(); }
  std::size_t trianglesOf(TerrainNodeId id) const;  // a resident tile's (0: not resident)
  std::size_t pendingTiles() const;                 // queued, being read, or read and not collected
  std::size_t residentBytes() const { return residentBytes_; }
  // What this frame's cuts reserve so far (tileBytesBound of every tile they use).
  std::size_t frameBytes() const { return frameBytes_; }
  std::size_t peakBytes() const { return peakBytes_; }
  std::size_t memoryBudget() const { return budget_; }
  std::size_t evictions() const { return evictions_; }
  int workerThreads() const { return queue_->workerThreads(); }
  const TerrainQuadtree& tree() const { return tree_; }
  // An upper bound of a node's bytes (its mesh with skirts and its samples), known before it is read.
  std::size_t tileBytesBound(TerrainNodeId id) const;

 private:
  struct Resident {
    std::shared_ptr<const TerrainTile> tile;
    std::size_t bytes = 0;         // actual: mesh + samples
    glm::vec3 lo{0.0f}, hi{0.0f};  // the mesh's box (skirts included), render frame
    std::size_t triangles = 0;
    std::uint64_t lastUsed = 0;
  };
  struct Job {
    std::vector<std::shared_ptr<const TerrainTile>> ancestors;  // for the tile's skirts
  };
  struct Done {
    TerrainTileMesh mesh;
    std::shared_ptr<const TerrainTile> tile;
  };

  void request(TerrainNodeId id, double priority);
  bool touch(TerrainNodeId id);  // false when it does not fit what is left of the budget
  Done read(TerrainNodeId id, const Job& job) const;
  std::vector<TerrainTileMesh> collect(std::deque<Done>& done);

  TerrainQuadtree tree_;  // its const, thread-safe part only (readTile, skirtDepth, tileMesh)
  const glm::dvec3 origin_;
  const std::size_t budget_;

  // Render thread only.
  std::unordered_map<TerrainNodeId, Resident> resident_;
  std::set<TerrainNodeId> broken_;
  std::set<TerrainNodeId> usedThisFrame_;
  std::size_t frameBytes_ = 0, residentBytes_ = 0, peakBytes_ = 0, evictions_ = 0;
  std::uint64_t frame_ = 0;

  // Last: destroyed (its workers joined) before anything they read.
  std::unique_ptr<TileQueue<Job, Done>> queue_;
};

}  // namespace hv::render
