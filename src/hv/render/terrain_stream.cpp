#include "hv/render/terrain_stream.h"

#include "hv/ibr/frame_plan.h"
#include "hv/render/frame.h"
#include "hv/render/geometry_tiles.h"

#include <algorithm>
#include <limits>
#include <queue>
#include <stdexcept>

namespace hv::render {

TerrainStream::TerrainStream(const TerrainQuadtree& tree, glm::dvec3 origin, int workerThreads, std::size_t memoryBytes)
    : tree_(tree.sharedSource(), tree.options()), origin_(origin), budget_(memoryBytes) {
  if (workerThreads < 0) throw std::invalid_argument("terrain stream: negative worker thread count");
  if (memoryBytes == 0) throw std::invalid_argument("terrain stream: zero memory budget");
  queue_ = std::make_unique<TileQueue<Job, Done>>(
      workerThreads, [this](std::uint64_t id, const Job& job) { return read(TerrainNodeId(id), job); });
}

TerrainStream::~TerrainStream() = default;

std::size_t TerrainStream::tileBytesBound(TerrainNodeId id) const {
  const glm::ivec2 n = tree_.tileCellCount(id);
  const std::size_t samples = std::size_t(n.x + 1) * std::size_t(n.y + 1);
  // Skirts: a lowered copy of each border sample, two triangles a border segment.
  const std::size_t vertices = samples + 2 * std::size_t(n.x + 1) + 2 * std::size_t(n.y + 1);
  const std::size_t triangles = 2 * std::size_t(n.x) * std::size_t(n.y) + 4 * std::size_t(n.x + n.y);
  return vertices * GeometryBuffers::kStride * sizeof(float) + triangles * 3 * sizeof(std::uint32_t) +
         samples * sizeof(float);
}

void TerrainStream::beginFrame() {
  ++frame_;
  usedThisFrame_.clear();
  frameBytes_ = 0;
}

bool TerrainStream::touch(TerrainNodeId id) {
  if (usedThisFrame_.count(id)) return true;
  const std::size_t bytes = tileBytesBound(id);
  if (frameBytes_ + bytes > budget_ && id != TerrainQuadtree::root()) return false;
  frameBytes_ += bytes;
  usedThisFrame_.insert(id);
  if (const auto it = resident_.find(id); it != resident_.end()) it->second.lastUsed = frame_;
  return true;
}

void TerrainStream::request(TerrainNodeId id, double priority) {
  if (resident_.count(id) || broken_.count(id)) return;
  Job job;
  for (TerrainNodeId a = id; TerrainQuadtree::levelOf(a) > 0;) {
    a = tree_.parent(a);
    const auto it = resident_.find(a);
    if (it == resident_.end()) return;  // asked for again once its ancestors are back
    job.ancestors.push_back(it->second.tile);
  }
  queue_->request(id, priority, std::move(job));
}

TerrainCut TerrainStream::select(const Camera& camera, double tolerancePx, double priority,
                                 const glm::dmat4* clipFromRender) {
  TerrainCut cut;
  const TerrainNodeId root = TerrainQuadtree::root();
  const auto rootIt = resident_.find(root);
  touch(root);
  if (rootIt == resident_.end()) {
    if (!broken_.count(root)) {
      request(root, priority);
      cut.missing = 1;
    }
    return cut;
  }
  // A child's priority: its footprint with its parent's heights (all that is known before it is read).
  auto childPriority = [&](TerrainNodeId kid, const TerrainTile& parent) {
    const glm::dvec4 f = tree_.footprint(kid);
    const glm::dvec3 lo(f.x, f.y, parent.bounds.lo.z), hi(f.z, f.w, parent.bounds.hi.z);
    const glm::dvec3 d = glm::max(glm::max(lo - camera.center, camera.center - hi), glm::dvec3(0.0));
    double p = priority + glm::length(d);
    if (clipFromRender && !boxMayBeVisible(*clipFromRender, glm::vec3(lo - origin_), glm::vec3(hi - origin_)))
      p += kOutOfViewPenalty;
    return p;
  };
  // The quadtree's own order (TerrainQuadtree::select): the largest screen-space error first.
  auto refinable = [&](const TerrainTile& t, double sse) {
    return t.level < tree_.maxLevel() && !t.bounds.empty() && sse > tolerancePx;
  };
  std::set<TerrainNodeId> chosen{root};
  std::priority_queue<std::pair<double, TerrainNodeId>> queue;
  {
    const TerrainTile& t = *rootIt->second.tile;
    if (const double sse = TerrainQuadtree::screenSpaceError(t, camera); refinable(t, sse)) queue.push({sse, root});
  }
  while (!queue.empty()) {
    const TerrainNodeId id = queue.top().second;
    queue.pop();
    const std::vector<TerrainNodeId> kids = tree_.children(id);
    std::size_t need = 0;
    for (TerrainNodeId k : kids)
      if (!usedThisFrame_.count(k)) need += tileBytesBound(k);
    if (frameBytes_ + need > budget_) {
      cut.budgetLimited = true;
      continue;
    }
    bool all = true;
    for (TerrainNodeId k : kids)
      if (!resident_.count(k)) {
        all = false;
        if (broken_.count(k)) continue;
        request(k, childPriority(k, *resident_.at(id).tile));
        ++cut.missing;
      }
    if (!all) continue;
    for (TerrainNodeId k : kids) touch(k);
    chosen.erase(id);
    for (TerrainNodeId k : kids) {
      chosen.insert(k);
      const TerrainTile& t = *resident_.at(k).tile;
      if (const double sse = TerrainQuadtree::screenSpaceError(t, camera); refinable(t, sse)) queue.push({sse, k});
    }
  }
  cut.nodes.assign(chosen.begin(), chosen.end());
  return cut;
}

std::vector<TerrainNodeId> TerrainStream::endFrame() {
  std::vector<TerrainNodeId> evicted;
  if (residentBytes_ <= budget_) return evicted;
  std::vector<std::pair<std::uint64_t, TerrainNodeId>> candidates;
  for (const auto& [id, r] : resident_)
    if (!usedThisFrame_.count(id)) candidates.push_back({r.lastUsed, id});
  // Least recently used first; among equals the finest (largest id: level in the high bits) first,
  // so a parent outlives its children.
  std::sort(candidates.begin(), candidates.end(),
            [](const auto& a, const auto& b) { return a.first != b.first ? a.first < b.first : a.second > b.second; });
  for (const auto& [used, id] : candidates) {
    if (residentBytes_ <= budget_) break;
    residentBytes_ -= resident_.at(id).bytes;
    resident_.erase(id);
    evicted.push_back(id);
    ++evictions_;
  }
  return evicted;
}

TerrainStream::Done TerrainStream::read(TerrainNodeId id, const Job& job) const {
  Done d;
  d.mesh.id = id;
  try {
    auto tile = std::make_shared<TerrainTile>(tree_.readTile(id));
    std::vector<const TerrainTile*> ancestors;
    for (const auto& a : job.ancestors) ancestors.push_back(a.get());
    const Mesh mesh = tree_.tileMesh(*tile, true, tree_.skirtDepth(*tile, ancestors));
    const glm::vec2 always = ibr::gpuDays(DateInterval{});
    d.mesh.vertices.reserve(mesh.positions.size() * GeometryBuffers::kStride);
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::dvec3& p : mesh.positions) {
      const glm::dvec3 r = p - origin_;  // the render frame keeps coordinates small for floats
      d.mesh.vertices.insert(d.mesh.vertices.end(), {float(r.x), float(r.y), float(r.z), always.x, always.y, 0.0f});
      lo = glm::min(lo, glm::dvec3(glm::vec3(r)));
      hi = glm::max(hi, glm::dvec3(glm::vec3(r)));
    }
    if (!mesh.positions.empty()) d.mesh.lo = glm::vec3(lo), d.mesh.hi = glm::vec3(hi);
    d.mesh.indices.reserve(mesh.triangles.size() * 3);
    for (const glm::uvec3& t : mesh.triangles) d.mesh.indices.insert(d.mesh.indices.end(), {t.x, t.y, t.z});
    d.tile = std::move(tile);
  } catch (const std::exception& e) {
    d.mesh = TerrainTileMesh{};
    d.mesh.id = id;
    d.mesh.error = std::string("terrain tile (level ") + std::to_string(TerrainQuadtree::levelOf(id)) + ", " +
                   std::to_string(TerrainQuadtree::txOf(id)) + ", " + std::to_string(TerrainQuadtree::tyOf(id)) +
                   "): " + e.what();
  }
  return d;
}

std::vector<TerrainTileMesh> TerrainStream::collect(std::deque<Done>& done) {
  std::vector<TerrainTileMesh> out;
  for (Done& d : done) {
    if (!d.mesh.error.empty()) {
      broken_.insert(d.mesh.id);
    } else if (!resident_.count(d.mesh.id)) {
      Resident r;
      r.tile = std::move(d.tile);
      r.bytes =
          (d.mesh.vertices.size() + r.tile->z.size()) * sizeof(float) + d.mesh.indices.size() * sizeof(std::uint32_t);
      r.lastUsed = frame_;
      r.lo = d.mesh.lo, r.hi = d.mesh.hi;
      r.triangles = d.mesh.indices.size() / 3;
      residentBytes_ += r.bytes;
      peakBytes_ = std::max(peakBytes_, residentBytes_);
      resident_.emplace(d.mesh.id, std::move(r));
    } else {
      continue;
    }
    out.push_back(std::move(d.mesh));
  }
  done.clear();
  return out;
}

std::vector<TerrainTileMesh> TerrainStream::poll(std::chrono::microseconds inlineBudget) {
  std::deque<Done> done = queue_->take(inlineBudget);
  return collect(done);
}

void TerrainStream::waitAll(const std::function<void(TerrainTileMesh&&)>& sink) {
  queue_->waitAll([&](std::deque<Done>& done) {
    for (TerrainTileMesh& m : collect(done)) sink(std::move(m));
  });
}

bool TerrainStream::boxOf(TerrainNodeId id, glm::vec3& lo, glm::vec3& hi) const {
  const auto it = resident_.find(id);
  if (it == resident_.end() || it->second.tile->bounds.empty()) return false;
  lo = it->second.lo, hi = it->second.hi;
  return true;
}

std::size_t TerrainStream::trianglesOf(TerrainNodeId id) const {
  const auto it = resident_.find(id);
  return it == resident_.end() ? 0 : it->second.triangles;
}

std::size_t TerrainStream::pendingTiles() const { return queue_->pending(); }

}  // namespace hv::render
