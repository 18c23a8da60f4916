#include "hv/layers/visibility_layers.h"

#include "hv/layers/object_layers.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace hv::layers {

void PixelHits::appendPixel(std::vector<SurfaceHit> pixelHits) {
  std::stable_sort(pixelHits.begin(), pixelHits.end(),
                   [](const SurfaceHit& a, const SurfaceHit& b) { return a.depth < b.depth; });
  hits.insert(hits.end(), pixelHits.begin(), pixelHits.end());
  first.push_back(std::uint32_t(hits.size()));
}

std::int64_t VisibilityLayers::hitOfLayer(const PixelHits& h, std::size_t pixel, int layer) const {
  for (std::uint32_t i = h.first[pixel]; i < h.first[pixel + 1]; ++i)
    if (layerOfHit[i] == layer) return std::int64_t(i);
  return -1;
}

namespace {

constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

void checkHits(const PixelHits& h) {
  if (h.width < 0 || h.height < 0 || h.first.size() != h.pixelCount() + 1 || h.first.back() != h.hits.size())
    throw std::invalid_argument("visibility layers: the per-pixel hit lists do not match a " + std::to_string(h.width) +
                                " x " + std::to_string(h.height) + " image (" + std::to_string(h.first.size()) +
                                " offsets, " + std::to_string(h.hits.size()) + " hits)");
}

// Peels the hits `out` leaves unassigned, appending layers after out.layers.
void peelRest(const PixelHits& h, VisibilityLayers& out) {
  std::size_t unassigned = std::size_t(std::count(out.layerOfHit.begin(), out.layerOfHit.end(), 0));
  const std::size_t pixels = h.pixelCount();

  while (unassigned > 0) {
    if (out.layers.size() >= std::numeric_limits<std::uint16_t>::max())
      throw std::invalid_argument("visibility layers: more than 65535 layers");
    const auto layer = std::uint16_t(out.layers.size() + 1);
    // One pass over the rays: the working set (objects with unassigned hits), and for each object
    // hidden somewhere by another one, the object nearest on such a ray (its occluder).
    std::unordered_map<std::uint32_t, std::uint32_t> occluderOf;  // object -> an object in front of it
    std::unordered_set<std::uint32_t> working;
    for (std::size_t p = 0; p < pixels; ++p) {
      std::uint32_t front = kNone;
      for (std::uint32_t i = h.first[p]; i < h.first[p + 1]; ++i) {
        if (out.layerOfHit[i] != 0) continue;
        const std::uint32_t o = h.hits[i].object;
        working.insert(o);
        if (front == kNone)
          front = o;
        else if (o != front)
          occluderOf.try_emplace(o, front);
      }
    }
    std::vector<std::uint32_t> free;
    for (std::uint32_t o : working)
      if (!occluderOf.count(o)) free.push_back(o);
    std::sort(free.begin(), free.end());

    VisibilityLayer current;
    if (!free.empty()) {
      current.objects = free;
      const std::unordered_set<std::uint32_t> take(free.begin(), free.end());
      for (std::size_t i = 0; i < h.hits.size(); ++i)
        if (out.layerOfHit[i] == 0 && take.count(h.hits[i].object)) out.layerOfHit[i] = layer, --unassigned;
    } else {
      // Every object is hidden by another: follow occluders from the smallest id until one
      // repeats. Each occluder is the nearest surface of some ray, so every object of the cycle
      // owns pixels where it is in front, and splitting there always makes progress.
      std::vector<std::uint32_t> ids(working.begin(), working.end());
      std::sort(ids.begin(), ids.end());
      std::vector<std::uint32_t> path;
      std::unordered_map<std::uint32_t, std::size_t> position;
      std::uint32_t o = ids.front();
      while (!position.count(o)) {
        position[o] = path.size();
        path.push_back(o);
        o = occluderOf.at(o);
      }
      std::vector<std::uint32_t> cycle(path.begin() + std::ptrdiff_t(position[o]), path.end());
      // path follows "is hidden by"; report in occlusion order (each hides the next).
      std::reverse(cycle.begin(), cycle.end());
      out.cycles.push_back(cycle);
      const std::unordered_set<std::uint32_t> inCycle(cycle.begin(), cycle.end());
      for (std::size_t p = 0; p < pixels; ++p)
        for (std::uint32_t i = h.first[p]; i < h.first[p + 1]; ++i) {
          if (out.layerOfHit[i] != 0) continue;
          // The nearest working-set surface of this ray: taken when it belongs to the cycle, with
          // the same object's further hits on the ray (its own far side does not block it).
          const std::uint32_t front = h.hits[i].object;
          if (inCycle.count(front))
            for (std::uint32_t j = i; j < h.first[p + 1]; ++j)
              if (out.layerOfHit[j] == 0 && h.hits[j].object == front) out.layerOfHit[j] = layer, --unassigned;
          break;
        }
      current.objects.assign(cycle.begin(), cycle.end());
      std::sort(current.objects.begin(), current.objects.end());
      current.split = current.objects;
    }
    out.layers.push_back(std::move(current));
  }
}

}  // namespace

VisibilityLayers peelVisibilityLayers(const PixelHits& h) {
  checkHits(h);
  VisibilityLayers out;
  out.layerOfHit.assign(h.hits.size(), 0);
  peelRest(h, out);
  return out;
}

VisibilityLayers completeVisibilityLayers(const PixelHits& h, const std::vector<std::uint16_t>& layerOfObject) {
  checkHits(h);
  // The given layers, renumbered without those no hit is in (an object the pass saw on no ray here).
  std::uint16_t deepest = 0;
  for (const SurfaceHit& hit : h.hits)
    if (hit.object < layerOfObject.size()) deepest = std::max(deepest, layerOfObject[hit.object]);
  std::vector<std::vector<std::uint32_t>> objects(deepest + 1u);
  for (const SurfaceHit& hit : h.hits)
    if (hit.object < layerOfObject.size() && layerOfObject[hit.object] > 0)
      objects[layerOfObject[hit.object]].push_back(hit.object);
  std::vector<std::uint16_t> renumber(deepest + 1u, 0);
  VisibilityLayers out;
  for (std::size_t k = 1; k < objects.size(); ++k) {
    if (objects[k].empty()) continue;
    std::sort(objects[k].begin(), objects[k].end());
    objects[k].erase(std::unique(objects[k].begin(), objects[k].end()), objects[k].end());
    out.layers.push_back({objects[k], {}});
    renumber[k] = std::uint16_t(out.layers.size());
  }
  out.layerOfHit.assign(h.hits.size(), 0);
  for (std::size_t i = 0; i < h.hits.size(); ++i)
    if (h.hits[i].object < layerOfObject.size()) out.layerOfHit[i] = renumber[layerOfObject[h.hits[i].object]];
  peelRest(h, out);
  return out;
}

}  // namespace hv::layers
