#include "hv/render/building_stream.h"

#include "hv/ibr/frame_plan.h"
#include "hv/render/frame.h"
#include "hv/render/geometry_tiles.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace hv::render {

glm::dvec2 boxPixelExtent(const Camera& camera, const glm::dvec3& lo, const glm::dvec3& hi) {
  const glm::dmat3 pixFromWorld = camera.pixFromWorld();
  glm::dvec2 pmin(std::numeric_limits<double>::infinity()), pmax(-std::numeric_limits<double>::infinity());
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z);
    const glm::dvec3 p = pixFromWorld * (corner - camera.center);
    if (!(p.z > 0.0)) return glm::dvec2(std::numeric_limits<double>::infinity());
    const glm::dvec2 px(p.x / p.z, p.y / p.z);
    pmin = glm::min(pmin, px);
    pmax = glm::max(pmax, px);
  }
  return pmax - pmin;
}

BuildingStream::BuildingStream(std::shared_ptr<const BuildingTileSet> set, glm::dvec3 origin, int workerThreads,
                               std::size_t memoryBytes)
    : set_(std::move(set)), origin_(origin), budget_(memoryBytes) {
  if (!set_ || !set_->read) throw std::invalid_argument("building stream: no tile source");
  if (workerThreads < 0) throw std::invalid_argument("building stream: negative worker thread count");
  if (memoryBytes == 0) throw std::invalid_argument("building stream: zero memory budget");
  renderBoxes_.reserve(set_->boxes.size());
  known_.resize(set_->boxes.size());
  for (const Aabb& b : set_->boxes) {
    Aabb r;
    if (!b.empty()) r.lo = b.lo - origin_, r.hi = b.hi - origin_;
    renderBoxes_.push_back(r);
  }
  queue_ = std::make_unique<TileQueue<Job, BuildingTileMesh>>(
      workerThreads, [this](std::uint64_t id, const Job&) { return read(std::uint32_t(id)); });
}

std::size_t BuildingStream::meshBytes(const BuildingTileMesh& m) {
  return m.vertices.size() * sizeof(float) + m.indices.size() * sizeof(std::uint32_t);
}

void BuildingStream::beginFrame(std::size_t reservedBytes) {
  ++frame_;
  usedThisFrame_.clear();
  reservedBytes_ = reservedBytes;
  frameBytes_ = 0;
}

BuildingCut BuildingStream::select(const Camera& camera, const glm::dmat4& clipFromRender, double priority,
                                   double reach, double minPixels) {
  BuildingCut cut;
  const glm::dvec3 eye = camera.center - origin_;
  // The tiles the clip volume may see, nearest first: the budget goes to them first. A tile read
  // before (resident or not) by the box of its buildings, one never read by its box from the source.
  std::vector<std::pair<double, std::uint32_t>> seen;
  const auto now = std::chrono::steady_clock::now();
  for (std::uint32_t t = 0; t < renderBoxes_.size(); ++t) {
    const Known& k = known_[t];
    if (k.broken || (k.read && k.empty)) continue;
    if (k.failures > 0 && now < k.retryAt) continue;  // failed: not before its next try
    const glm::dvec3 lo = k.read ? glm::dvec3(k.lo) : renderBoxes_[t].lo;
    const glm::dvec3 hi = k.read ? glm::dvec3(k.hi) : renderBoxes_[t].hi;
    if (!k.read && renderBoxes_[t].empty()) continue;
    const double distance = glm::length(glm::max(glm::max(lo - eye, eye - hi), glm::dvec3(0.0)));
    if (distance > reach || !boxMayBeVisible(clipFromRender, glm::vec3(lo), glm::vec3(hi))) continue;
    if (minPixels > 0.0) {
      const glm::dvec2 extent = boxPixelExtent(camera, lo + origin_, hi + origin_);
      if (std::min(extent.x, extent.y) < minPixels) continue;
    }
    seen.push_back({distance, t});
  }
  std::sort(seen.begin(), seen.end());
  for (const auto& [d, t] : seen) {
    if (usedThisFrame_.count(t)) {
      if (resident_.count(t))
        cut.tiles.push_back(t);
      else
        ++cut.missing;
      continue;
    }
    // Its bytes: known once it was read, none before (the first read of a tile may overshoot
    // until the frame's end).
    const std::size_t bytes = known_[t].bytes;
    if (reservedBytes_ + frameBytes_ + bytes > budget_ || (bytes == 0 && reservedBytes_ + frameBytes_ >= budget_)) {
      cut.budgetLimited = true;
      continue;
    }
    frameBytes_ += bytes;
    usedThisFrame_.insert(t);
    if (const auto it = resident_.find(t); it != resident_.end()) {
      it->second.lastUsed = frame_;
      cut.tiles.push_back(t);
    } else {
      queue_->request(t, priority + d, Job{});
      ++cut.missing;
    }
  }
  std::sort(cut.tiles.begin(), cut.tiles.end());
  return cut;
}

std::vector<std::uint32_t> BuildingStream::endFrame(std::size_t otherResidentBytes) {
  std::vector<std::uint32_t> evicted;
  if (residentBytes_ + otherResidentBytes <= budget_) return evicted;
  std::vector<std::pair<std::uint64_t, std::uint32_t>> candidates;
  for (const auto& [t, r] : resident_)
    if (!usedThisFrame_.count(t)) candidates.push_back({r.lastUsed, t});
  std::sort(candidates.begin(), candidates.end());  // least recently used first, then by tile
  for (const auto& [used, t] : candidates) {
    if (residentBytes_ + otherResidentBytes <= budget_) break;
    const Resident& r = resident_.at(t);
    residentBytes_ -= r.bytes;
    residentBuildings_ -= r.buildings;
    freeIndices(r.firstBuilding, r.buildings);
    resident_.erase(t);
    evicted.push_back(t);
    ++evictions_;
  }
  return evicted;
}

BuildingTileMesh BuildingStream::read(std::uint32_t tile) const {
  BuildingTileMesh out;
  out.tile = tile;
  try {
    BuildingTileData data = set_->read(tile);
    const Mesh& m = data.mesh;
    out.warnings = std::move(data.warnings);
    out.validity.reserve(data.validity.size());
    for (const DateInterval& v : data.validity) out.validity.push_back(ibr::gpuDays(v));
    // As the whole load builds its buffer (FrameBuilder::buildGeometry): a building's vertices
    // are its own; the building index is filled in when the tile arrives (collect).
    std::vector<std::uint32_t> vertexTag(m.positions.size(), 0);
    if (!m.triangleTags.empty())
      for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) vertexTag[m.triangles[t][k]] = m.triangleTags[t];
    const glm::vec2 always = ibr::gpuDays(DateInterval{});
    out.vertices.reserve(m.positions.size() * GeometryBuffers::kStride);
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (std::size_t v = 0; v < m.positions.size(); ++v) {
      const glm::dvec3 r = m.positions[v] - origin_;
      const std::uint32_t tag = vertexTag[v];
      if (!m.triangleTags.empty() && tag >= out.validity.size())
        throw std::runtime_error("triangle tag " + std::to_string(tag) + " past the tile's " +
                                 std::to_string(out.validity.size()) + " buildings");
      const glm::vec2 valid = tag < out.validity.size() ? out.validity[tag] : always;
      // The local tag for now (collect adds the tile's first index + 1).
      out.vertices.insert(out.vertices.end(), {float(r.x), float(r.y), float(r.z), valid.x, valid.y, float(tag)});
      lo = glm::min(lo, glm::dvec3(glm::vec3(r)));
      hi = glm::max(hi, glm::dvec3(glm::vec3(r)));
    }
    if (!m.positions.empty()) out.lo = glm::vec3(lo), out.hi = glm::vec3(hi);
    out.indices.reserve(m.triangles.size() * 3);
    for (const glm::uvec3& t : m.triangles) out.indices.insert(out.indices.end(), {t.x, t.y, t.z});
  } catch (const std::exception& e) {
    out = BuildingTileMesh{};
    out.tile = tile;
    out.error = tileName(tile) + ": " + e.what();
  }
  return out;
}

std::uint32_t BuildingStream::allocateIndices(std::uint32_t count) {
  if (count == 0) return 0;
  for (auto it = freeIndices_.begin(); it != freeIndices_.end(); ++it) {
    if (it->second < count) continue;
    const std::uint32_t first = it->first, left = it->second - count;
    freeIndices_.erase(it);
    if (left) freeIndices_[first + count] = left;
    return first;
  }
  const std::uint32_t first = indexEnd_;
  indexEnd_ += count;
  return first;
}

void BuildingStream::freeIndices(std::uint32_t first, std::uint32_t count) {
  if (count == 0) return;
  auto it = freeIndices_.emplace(first, count).first;
  // Merged with its neighbours, so that a freed range can hold a larger tile later.
  if (auto next = std::next(it); next != freeIndices_.end() && it->first + it->second == next->first) {
    it->second += next->second;
    freeIndices_.erase(next);
  }
  if (it != freeIndices_.begin()) {
    auto prev = std::prev(it);
    if (prev->first + prev->second == it->first) {
      prev->second += it->second;
      freeIndices_.erase(it);
    }
  }
}

std::vector<BuildingTileMesh> BuildingStream::collect(std::deque<BuildingTileMesh>& done) {
  std::vector<BuildingTileMesh> out;
  for (BuildingTileMesh& m : done) {
    Known& k = known_[m.tile];
    m.attempt = k.failures + 1;
    if (!m.error.empty()) {
      ++k.failures;
      if (k.failures >= std::max(1, retry_.attempts)) {
        k.broken = true;
      } else {
        // first x 2^(failures - 1), at most cap.
        auto wait = retry_.first;
        for (int i = 1; i < k.failures && wait < retry_.cap; ++i) wait *= 2;
        k.retryAt = std::chrono::steady_clock::now() + std::min(wait, retry_.cap);
        m.retrying = true;
      }
    } else if (!resident_.count(m.tile)) {
      k.failures = 0;
      k.read = true;
      k.empty = m.indices.empty();
      k.bytes = meshBytes(m);
      k.lo = m.lo, k.hi = m.hi;
      if (!k.empty) {
        Resident r;
        r.buildings = std::uint32_t(m.validity.size());
        r.firstBuilding = allocateIndices(r.buildings);
        m.firstBuilding = r.firstBuilding;
        for (std::size_t v = 5; v < m.vertices.size(); v += GeometryBuffers::kStride)
          m.vertices[v] = float(double(m.vertices[v]) + double(r.firstBuilding) + 1.0);
        r.bytes = k.bytes;
        r.lo = m.lo, r.hi = m.hi;
        r.triangles = m.indices.size() / 3;
        r.lastUsed = frame_;
        residentBytes_ += r.bytes;
        residentBuildings_ += r.buildings;
        peakBytes_ = std::max(peakBytes_, residentBytes_);
        resident_.emplace(m.tile, r);
      }
    } else {
      continue;
    }
    out.push_back(std::move(m));
  }
  done.clear();
  return out;
}

std::vector<BuildingTileMesh> BuildingStream::poll(std::chrono::microseconds inlineBudget) {
  std::deque<BuildingTileMesh> done = queue_->take(inlineBudget);
  return collect(done);
}

void BuildingStream::waitAll(const std::function<void(BuildingTileMesh&&)>& sink) {
  queue_->waitAll([&](std::deque<BuildingTileMesh>& done) {
    for (BuildingTileMesh& m : collect(done)) sink(std::move(m));
  });
}

bool BuildingStream::boxOf(std::uint32_t tile, glm::vec3& lo, glm::vec3& hi) const {
  const auto it = resident_.find(tile);
  if (it == resident_.end()) return false;
  lo = it->second.lo, hi = it->second.hi;
  return true;
}

std::size_t BuildingStream::brokenTiles() const {
  return std::size_t(std::count_if(known_.begin(), known_.end(), [](const Known& k) { return k.broken; }));
}

std::size_t BuildingStream::retryingTiles() const {
  return std::size_t(
      std::count_if(known_.begin(), known_.end(), [](const Known& k) { return k.failures > 0 && !k.broken; }));
}

std::string BuildingStream::tileName(std::uint32_t tile) const {
  return (set_->source.empty() ? std::string("buildings") : set_->source) + ": tile " + std::to_string(tile);
}

std::size_t BuildingStream::trianglesOf(std::uint32_t tile) const {
  const auto it = resident_.find(tile);
  return it == resident_.end() ? 0 : it->second.triangles;
}

}  // namespace hv::render
