// The frame builder's streamed geometry (docs/design.md, "Terrain streaming" and "Building
// streaming"): the terrain's quadtree and the buildings' tiles, cut per photograph and per view,
// read off the render thread, uploaded as they arrive and evicted under one memory budget.
#include "hv/render/frame_builder.h"

#include "hv/render/geometry_tiles.h"
#include "hv/scene/building_tiles.h"

#include <algorithm>

namespace hv::render {

namespace {

// After the view's visible tiles (kOutOfViewPenalty keeps the rest behind both).
constexpr double kPhotographs = 1e6;

}  // namespace

// The slots whose depth maps this frame may draw: the plan's and the depth-map view's, less the
// layered photographs' sub-images (their maps are uploaded, not drawn).
std::vector<int> FrameBuilder::drawnSlots(const Frame& f, int debugSlot) const {
  std::vector<int> slots;
  auto add = [&](int slot) {
    if (slot < 0 || std::find(slots.begin(), slots.end(), slot) != slots.end()) return;
    const int key = cache_.photoIn(slot);
    if (key >= 0 && !isSubImage(key)) slots.push_back(slot);
  };
  for (int slot : f.slots) add(slot);
  add(debugSlot);
  return slots;
}

// The streamed terrain (render/terrain_stream.h, docs/design.md "Terrain streaming"): collects
// the tiles read since the last frame, cuts the quadtree for each photograph of the frame (their
// depth maps: the occlusion test needs what they see at their own resolution) and then the view,
// requests what the cuts wait for (the view's visible tiles first, nearest first), evicts the
// least recently used tiles over the budget, and marks dirty each depth map whose cut changed.
// Batch frames wait until no cut waits for anything.
void FrameBuilder::streamTerrain(Frame& f, int debugSlot) {
  if (!terrain_) return;
  auto install = [&](TerrainTileMesh&& m) {
    if (!m.error.empty()) {
      diag_.error(m.error + " (its parent drawn instead)");
      return;
    }
    backend_.uploadStreamedTile(m.id, m.vertices, m.indices);
  };
  const std::vector<int> slots = drawnSlots(f, debugSlot);
  const double tolerance = std::max(1e-3, settings_.geometryTolerancePx);
  TerrainCut view;
  auto cut = [&] {
    terrain_->beginFrame();
    int missing = 0;
    for (int slot : slots) {
      const int photo = cache_.photoIn(slot);
      const Camera cam = photoCamera(photo);
      const glm::dmat4 clip = hv::clipFromRender(cam, slotFrustum_[size_t(slot)], scene_.origin);
      TerrainCut c = terrain_->select(cam, tolerance, kPhotographs, &clip);
      missing += c.missing;
      slotCut_[size_t(slot)] = std::move(c.nodes);
    }
    view = terrain_->select(f.view, tolerance, 0.0, &f.rect.clipFromRender);
    return missing + view.missing;
  };
  for (TerrainTileMesh& m : terrain_->poll()) install(std::move(m));
  terrainMissing_ = cut();
  while (f.mode == FrameMode::Batch && terrainMissing_ > 0 && terrain_->pendingTiles() > 0) {
    terrain_->waitAll(install);
    terrainMissing_ = cut();
  }
  for (TerrainNodeId id : terrain_->endFrame()) backend_.releaseStreamedTile(id);
  for (int slot : slots)
    if (slotCut_[size_t(slot)] != slotCutDrawn_[size_t(slot)]) depthScheduler_.markDirty(slot);
  if (settings_.layers.terrain) f.streamedTiles = visibleTerrain(view.nodes, f.rect.clipFromRender);
  stats_.streamingTerrain = true;
  stats_.terrainTilesResident = int(terrain_->residentTiles());
  stats_.terrainTilesPending = int(terrain_->pendingTiles());
  stats_.terrainBytes = terrain_->residentBytes();
  stats_.terrainPeakBytes = terrain_->peakBytes();
  stats_.terrainFrameBytes = terrain_->frameBytes();
  stats_.terrainBudgetBytes = terrain_->memoryBudget();
  stats_.terrainEvictions = terrain_->evictions();
  stats_.terrainViewTiles = int(view.nodes.size());
  stats_.terrainViewMissing = view.missing;
}

// The tiles of a cut whose boxes may be inside the clip volume (all of them without culling).
std::vector<std::uint64_t> FrameBuilder::visibleTerrain(const std::vector<TerrainNodeId>& cut,
                                                        const glm::dmat4& clipFromRender) const {
  std::vector<std::uint64_t> out;
  for (TerrainNodeId id : cut) {
    glm::vec3 lo, hi;
    if (!terrain_->boxOf(id, lo, hi)) continue;
    if (!settings_.geometryCulling || boxMayBeVisible(clipFromRender, lo, hi)) out.push_back(id);
  }
  return out;
}

// The streamed buildings (render/building_stream.h, docs/design.md "Building streaming"), as the
// terrain above: collects the tiles read since the last frame (uploading them and their
// buildings' dates), cuts the tiles for each photograph of the frame and then the view (each
// within kBuildingReachMetresPerPixel x its focal length; the view also without the tiles thinner
// than settings' buildingMinPixels in its picture), requests what the cuts lack, evicts the
// least recently used tiles while the buildings and the terrain together exceed the budget, and
// marks dirty each depth map whose cut changed. Batch frames wait until no cut waits for anything.
void FrameBuilder::streamBuildings(Frame& f, int debugSlot) {
  if (!buildings_) return;
  auto install = [&](BuildingTileMesh&& m) {
    for (const std::string& w : m.warnings) diag_.warn(w);
    // What is missing (hv/scene/missing_sources.h): a tile that failed, named, until it arrives.
    const std::string name = buildings_->tileName(m.tile);
    if (!m.error.empty()) {
      diag_.error(m.error + (m.retrying ? " (its buildings left out until it is read again, try " +
                                              std::to_string(m.attempt) + ")"
                                        : " (its buildings left out)"));
      if (scene_.missing) scene_.missing->add({"building tile", name, m.error, m.retrying, m.attempt});
      return;
    }
    if (m.attempt > 1 && scene_.missing) scene_.missing->resolve("building tile", name);
    if (m.indices.empty()) return;  // a tile without buildings is never drawn
    backend_.uploadStreamedTile(kBuildingTileId | m.tile, m.vertices, m.indices);
    setBuildingValidity(m.firstBuilding, m.validity);
  };
  const std::vector<int> slots = drawnSlots(f, debugSlot);
  auto reach = [](const Camera& c) { return kBuildingReachMetresPerPixel * std::max(c.focal.x, c.focal.y); };
  BuildingCut view;
  auto cut = [&] {
    // The terrain's cuts were taken first: the buildings get what of the budget they left.
    buildings_->beginFrame(terrain_ ? terrain_->frameBytes() : 0);
    int missing = 0;
    for (int slot : slots) {
      const Camera cam = photoCamera(cache_.photoIn(slot));
      const glm::dmat4 clip = hv::clipFromRender(cam, slotFrustum_[size_t(slot)], scene_.origin);
      BuildingCut c = buildings_->select(cam, clip, kPhotographs, reach(cam));
      missing += c.missing;
      slotBuildingCut_[size_t(slot)] = std::move(c.tiles);
    }
    view = buildings_->select(f.view, f.rect.clipFromRender, 0.0, reach(f.view),
                              std::max(0.0, settings_.buildingMinPixels));
    return missing + view.missing;
  };
  for (BuildingTileMesh& m : buildings_->poll()) install(std::move(m));
  buildingsMissing_ = cut();
  while (f.mode == FrameMode::Batch && buildingsMissing_ > 0 && buildings_->pendingTiles() > 0) {
    buildings_->waitAll(install);
    buildingsMissing_ = cut();
  }
  for (std::uint32_t tile : buildings_->endFrame(terrain_ ? terrain_->residentBytes() : 0))
    backend_.releaseStreamedTile(kBuildingTileId | tile);
  if (validityDirty_) {
    backend_.uploadValidity(validity_, kValidityWidth, int(validity_.size() / (4 * kValidityWidth)));
    validityDirty_ = false;
  }
  for (int slot : slots)
    if (slotBuildingCut_[size_t(slot)] != slotBuildingCutDrawn_[size_t(slot)]) depthScheduler_.markDirty(slot);
  if (settings_.layers.buildings) {
    const std::vector<std::uint64_t> tiles = visibleBuildings(view.tiles, f.rect.clipFromRender);
    f.streamedTiles.insert(f.streamedTiles.end(), tiles.begin(), tiles.end());
  }
  stats_.streamingBuildings = true;
  stats_.buildingTilesResident = int(buildings_->residentTiles());
  stats_.buildingTilesPending = int(buildings_->pendingTiles());
  stats_.buildingTilesRetrying = int(buildings_->retryingTiles());
  stats_.buildingTilesGivenUp = int(buildings_->brokenTiles());
  stats_.buildingsResident = buildings_->residentBuildings();
  stats_.buildingBytes = buildings_->residentBytes();
  stats_.buildingPeakBytes = buildings_->peakBytes();
  stats_.buildingEvictions = buildings_->evictions();
  stats_.buildingViewTiles = int(view.tiles.size());
  stats_.buildingViewMissing = view.missing;
  stats_.buildingBudgetLimited = view.budgetLimited;
}

// The building tiles of a cut whose boxes may be inside the clip volume (all of them without
// culling), as streamed-tile ids.
std::vector<std::uint64_t> FrameBuilder::visibleBuildings(const std::vector<std::uint32_t>& cut,
                                                          const glm::dmat4& clipFromRender) const {
  std::vector<std::uint64_t> out;
  for (std::uint32_t tile : cut) {
    glm::vec3 lo, hi;
    if (!buildings_->boxOf(tile, lo, hi)) continue;
    if (!settings_.geometryCulling || boxMayBeVisible(clipFromRender, lo, hi)) out.push_back(kBuildingTileId | tile);
  }
  return out;
}

// The dates of buildings first .. first + days.size() - 1 (their validity texels).
void FrameBuilder::setBuildingValidity(std::uint32_t first, const std::vector<glm::vec2>& days) {
  const std::size_t end = std::size_t(first) + days.size();
  const std::size_t rows = std::max<std::size_t>(1, (end + kValidityWidth - 1) / kValidityWidth);
  if (validity_.size() < rows * kValidityWidth * 4) validity_.resize(rows * kValidityWidth * 4, 0.0f);
  for (std::size_t i = 0; i < days.size(); ++i) {
    validity_[(first + i) * 4] = days[i].x;
    validity_[(first + i) * 4 + 1] = days[i].y;
  }
  validityDirty_ = true;
}

// The triangles of a streamed tile (terrain or buildings) that is resident.
std::size_t FrameBuilder::streamedTriangles(std::uint64_t id) const {
  if (id & kBuildingTileId) return buildings_ ? buildings_->trianglesOf(std::uint32_t(id & ~kBuildingTileId)) : 0;
  return terrain_ ? terrain_->trianglesOf(id) : 0;
}

}  // namespace hv::render
