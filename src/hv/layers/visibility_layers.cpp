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

VisibilityLayers::Piece VisibilityLayers::pieceOf(const PixelHits& h, const SurfaceHit& hit) const {
  if (!std::binary_search(splitObjects.begin(), splitObjects.end(), hit.object)) return {PieceKind::Object, hit.object};
  const std::uint32_t face = h.faceOfTriangle.at(hit.triangle);
  if (!std::binary_search(splitFaces.begin(), splitFaces.end(), face)) return {PieceKind::Face, face};
  return {PieceKind::Triangle, hit.triangle};
}

namespace {

void checkHits(const PixelHits& h) {
  if (h.width < 0 || h.height < 0 || h.first.size() != h.pixelCount() + 1 || h.first.back() != h.hits.size())
    throw std::invalid_argument("visibility layers: the per-pixel hit lists do not match a " + std::to_string(h.width) +
                                " x " + std::to_string(h.height) + " image (" + std::to_string(h.first.size()) +
                                " offsets, " + std::to_string(h.hits.size()) + " hits)");
  if (!h.faceOfTriangle.empty())
    for (const SurfaceHit& hit : h.hits)
      if (hit.triangle >= h.faceOfTriangle.size())
        throw std::invalid_argument(
            "visibility layers: a hit of object " + std::to_string(hit.object) + " names triangle " +
            (hit.triangle == kNoTriangle ? std::string("none") : std::to_string(hit.triangle)) +
            ", expected one of the " + std::to_string(h.faceOfTriangle.size()) + " triangles faces are given for");
}

// An item of the working set: a whole object, a face or a triangle (kind in the high word).
using Item = std::uint64_t;
using PieceKind = VisibilityLayers::PieceKind;
constexpr Item kNoItem = std::numeric_limits<Item>::max();
Item makeItem(PieceKind kind, std::uint32_t id) { return (Item(kind) << 32) | id; }
PieceKind kindOf(Item item) { return PieceKind(item >> 32); }

struct Pieces {
  const PixelHits& h;
  std::unordered_set<std::uint32_t> objects, faces;  // split into faces; faces split into triangles
  Item itemOf(const SurfaceHit& hit) const {
    if (objects.empty() || !objects.count(hit.object)) return makeItem(PieceKind::Object, hit.object);
    const std::uint32_t face = h.faceOfTriangle[hit.triangle];
    if (!faces.count(face)) return makeItem(PieceKind::Face, face);
    return makeItem(PieceKind::Triangle, hit.triangle);
  }
};

// The strongly connected components of a graph (Tarjan, iterative): comp[v] for each vertex.
std::vector<std::size_t> components(const std::vector<std::vector<std::size_t>>& next) {
  const std::size_t n = next.size(), unseen = std::numeric_limits<std::size_t>::max();
  std::vector<std::size_t> index(n, unseen), low(n, 0), comp(n, unseen), stack;
  std::vector<bool> onStack(n, false);
  std::vector<std::pair<std::size_t, std::size_t>> call;  // (vertex, next edge to follow)
  std::size_t counter = 0, comps = 0;
  for (std::size_t root = 0; root < n; ++root) {
    if (index[root] != unseen) continue;
    call.push_back({root, 0});
    index[root] = low[root] = counter++;
    stack.push_back(root), onStack[root] = true;
    while (!call.empty()) {
      auto& [v, e] = call.back();
      if (e < next[v].size()) {
        const std::size_t w = next[v][e++];
        if (index[w] == unseen) {
          index[w] = low[w] = counter++;
          stack.push_back(w), onStack[w] = true;
          call.push_back({w, 0});
        } else if (onStack[w]) {
          low[v] = std::min(low[v], index[w]);
        }
        continue;
      }
      const std::size_t done = v;
      call.pop_back();
      if (!call.empty()) low[call.back().first] = std::min(low[call.back().first], low[done]);
      if (low[done] == index[done]) {
        std::size_t w = unseen;
        do {
          w = stack.back();
          stack.pop_back();
          onStack[w] = false;
          comp[w] = comps;
        } while (w != done);
        ++comps;
      }
    }
  }
  return comp;
}

// Peels the hits `out` leaves unassigned, appending layers after out.layers.
void peelRest(const PixelHits& h, VisibilityLayers& out) {
  std::size_t unassigned = std::size_t(std::count(out.layerOfHit.begin(), out.layerOfHit.end(), 0));
  const std::size_t pixels = h.pixelCount();
  Pieces pieces{h, {out.splitObjects.begin(), out.splitObjects.end()}, {out.splitFaces.begin(), out.splitFaces.end()}};

  // The objects of the hits just given `layer`, and those of them here in part.
  auto finishLayer = [&](std::uint16_t layer, const std::unordered_set<std::uint32_t>& broken) {
    VisibilityLayer current;
    std::unordered_set<std::uint32_t> objects, split;
    for (std::size_t i = 0; i < h.hits.size(); ++i) {
      if (out.layerOfHit[i] != layer) continue;
      objects.insert(h.hits[i].object);
      if (broken.count(h.hits[i].object) || kindOf(pieces.itemOf(h.hits[i])) != PieceKind::Object)
        split.insert(h.hits[i].object);
    }
    current.objects.assign(objects.begin(), objects.end());
    std::sort(current.objects.begin(), current.objects.end());
    current.split.assign(split.begin(), split.end());
    std::sort(current.split.begin(), current.split.end());
    out.layers.push_back(std::move(current));
  };

  // The working set (items with unassigned hits, and their objects) and, for each item hidden
  // somewhere by another one, the item nearest on such a ray (its occluder). With `withCycles`,
  // the cycles of the "hides part of" relation too (an item hides those behind it on a ray): its
  // strongly connected components of more than one item, each in the order of its smallest item.
  // No item of such a component can ever be taken whole (each is behind another one of it for as
  // long as both are left); `source` marks those nothing outside hides, which block the peel now.
  struct Cycle {
    std::vector<Item> items;
    bool source = false;
  };
  struct State {
    std::unordered_map<Item, std::uint32_t> working;
    std::unordered_map<Item, Item> occluderOf;
    std::vector<Cycle> cycles;
    std::unordered_map<Item, Item> hiddenInCycleBy;  // an item of its own cycle in front of it
  };
  auto analyse = [&](bool withCycles) {
    State st;
    for (std::size_t p = 0; p < pixels; ++p) {
      Item front = kNoItem;
      for (std::uint32_t i = h.first[p]; i < h.first[p + 1]; ++i) {
        if (out.layerOfHit[i] != 0) continue;
        const Item it = pieces.itemOf(h.hits[i]);
        st.working.try_emplace(it, h.hits[i].object);
        if (front == kNoItem)
          front = it;
        else if (it != front)
          st.occluderOf.try_emplace(it, front);
      }
    }
    if (!withCycles) return st;
    std::vector<Item> items;
    items.reserve(st.working.size());
    for (const auto& [it, object] : st.working) items.push_back(it);
    std::sort(items.begin(), items.end());
    std::unordered_map<Item, std::size_t> indexOf;
    for (std::size_t k = 0; k < items.size(); ++k) indexOf[items[k]] = k;
    std::vector<std::vector<std::size_t>> next(items.size());
    std::vector<std::size_t> ray;
    for (std::size_t p = 0; p < pixels; ++p) {
      ray.clear();
      for (std::uint32_t i = h.first[p]; i < h.first[p + 1]; ++i)
        if (out.layerOfHit[i] == 0) ray.push_back(indexOf.at(pieces.itemOf(h.hits[i])));
      for (std::size_t a = 0; a < ray.size(); ++a)
        for (std::size_t b = a + 1; b < ray.size(); ++b)
          if (ray[a] != ray[b]) next[ray[a]].push_back(ray[b]);
    }
    for (auto& n : next) {
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
    }
    const std::vector<std::size_t> comp = components(next);
    const std::size_t comps = items.empty() ? 0 : *std::max_element(comp.begin(), comp.end()) + 1;
    std::vector<bool> hidden(comps, false);
    for (std::size_t v = 0; v < items.size(); ++v)
      for (std::size_t w : next[v]) {
        if (comp[w] != comp[v])
          hidden[comp[w]] = true;
        else
          st.hiddenInCycleBy.try_emplace(items[w], items[v]);
      }
    std::vector<std::vector<Item>> members(comps);
    std::vector<std::size_t> order;
    for (std::size_t v = 0; v < items.size(); ++v) {
      if (members[comp[v]].empty()) order.push_back(comp[v]);
      members[comp[v]].push_back(items[v]);
    }
    for (std::size_t c : order)
      if (members[c].size() > 1) st.cycles.push_back({std::move(members[c]), !hidden[c]});
    return st;
  };
  // A cycle through a component, from its smallest item along "is hidden by" within it, as
  // objects in occlusion order.
  auto cycleObjects = [](const State& st, const std::vector<Item>& inComp) {
    std::vector<Item> path;
    std::unordered_map<Item, std::size_t> position;
    Item it = inComp.front();
    while (!position.count(it)) {
      position[it] = path.size();
      path.push_back(it);
      it = st.hiddenInCycleBy.at(it);
    }
    std::vector<Item> cycle(path.begin() + std::ptrdiff_t(position[it]), path.end());
    std::reverse(cycle.begin(), cycle.end());  // path follows "is hidden by"
    std::vector<std::uint32_t> objects;
    for (Item c : cycle) {
      const std::uint32_t o = st.working.at(c);
      if (std::find(objects.begin(), objects.end(), o) == objects.end()) objects.push_back(o);
    }
    return objects;
  };

  while (unassigned > 0) {
    if (out.layers.size() >= std::numeric_limits<std::uint16_t>::max())
      throw std::invalid_argument("visibility layers: more than 65535 layers");
    const auto layer = std::uint16_t(out.layers.size() + 1);
    State st = analyse(false);
    std::unordered_set<Item> free;
    for (const auto& [it, object] : st.working)
      if (!st.occluderOf.count(it)) free.insert(it);
    if (!free.empty()) {
      for (std::size_t i = 0; i < h.hits.size(); ++i)
        if (out.layerOfHit[i] == 0 && free.count(pieces.itemOf(h.hits[i]))) out.layerOfHit[i] = layer, --unassigned;
      finishLayer(layer, {});
      continue;
    }

    // Every item is hidden by another: split the cycles' objects into faces, faces into
    // triangles, and again while the pieces still form cycles that can be split. Each cycle has to
    // be split some time (none of its items can be taken before the others); splitting all of them
    // now, those behind others too, spares the layers a split made later would add.
    bool splitAny = false;
    for (;;) {
      st = analyse(true);
      bool splitNow = false;
      for (const Cycle& c : st.cycles) {
        if (h.faceOfTriangle.empty()) break;
        const std::vector<Item>& cycle = c.items;
        bool faces = false, triangles = false;
        for (Item it : cycle) {
          if (kindOf(it) == PieceKind::Object) pieces.objects.insert(std::uint32_t(it)), faces = true;
          if (kindOf(it) == PieceKind::Face) pieces.faces.insert(std::uint32_t(it)), triangles = true;
        }
        if (!faces && !triangles) continue;
        out.splits.push_back({faces ? CycleSplit::Into::Faces : CycleSplit::Into::Triangles, cycleObjects(st, cycle),
                              cycle.size(), int(layer)});
        splitNow = true;
      }
      if (!splitNow) break;
      splitAny = true;
    }
    if (splitAny) continue;  // peel again with the pieces

    // Nothing left to split: each blocking cycle (nothing outside it hides it) is broken at pixel
    // level. The nearest item of a ray where one of its items is hidden is in it, so every such
    // cycle owns pixels where it is in front, and splitting there always makes progress.
    std::unordered_set<Item> inCycle;
    std::unordered_set<std::uint32_t> broken;
    for (const Cycle& c : st.cycles) {
      if (!c.source) continue;
      const std::vector<Item>& cycle = c.items;
      std::vector<std::uint32_t> objects = cycleObjects(st, cycle);
      out.splits.push_back({CycleSplit::Into::Pixels, objects, cycle.size(), int(layer)});
      out.cycles.push_back(std::move(objects));
      inCycle.insert(cycle.begin(), cycle.end());
    }
    for (std::size_t p = 0; p < pixels; ++p)
      for (std::uint32_t i = h.first[p]; i < h.first[p + 1]; ++i) {
        if (out.layerOfHit[i] != 0) continue;
        // The nearest working-set surface of this ray: taken when it belongs to a cycle, with the
        // same item's further hits on the ray (its own far side does not block it).
        const Item front = pieces.itemOf(h.hits[i]);
        if (inCycle.count(front)) {
          broken.insert(h.hits[i].object);
          for (std::uint32_t j = i; j < h.first[p + 1]; ++j)
            if (out.layerOfHit[j] == 0 && pieces.itemOf(h.hits[j]) == front) out.layerOfHit[j] = layer, --unassigned;
        }
        break;
      }
    finishLayer(layer, broken);
  }
  // An object whose pieces all landed in one layer is whole there after all.
  std::unordered_map<std::uint32_t, int> layersOf;
  for (const VisibilityLayer& l : out.layers)
    for (std::uint32_t o : l.objects) ++layersOf[o];
  for (VisibilityLayer& l : out.layers)
    l.split.erase(std::remove_if(l.split.begin(), l.split.end(), [&](std::uint32_t o) { return layersOf[o] < 2; }),
                  l.split.end());
  out.splitObjects.assign(pieces.objects.begin(), pieces.objects.end());
  std::sort(out.splitObjects.begin(), out.splitObjects.end());
  out.splitFaces.assign(pieces.faces.begin(), pieces.faces.end());
  std::sort(out.splitFaces.begin(), out.splitFaces.end());
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
