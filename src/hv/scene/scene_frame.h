// The rules that place a scene's render frame and terrain, shared by the native loader
// (hv/io/native/scene_loader.h), `web-export` and the page's service scenes read without an export
// (hv/io/web_scene.h, docs/services.md "In the browser"): one rule, so that a scene read from
// services in the browser gets the origin, up and terrain that `render` gives the same data.
//
//   terrain  a DTM grid of at most kTerrainTilesAboveCells is meshed whole (Heightfield::toMesh,
//            two triangles a cell); a larger one becomes a quadtree of kTerrainTileCells tiles
//            (hv/scene/terrain_quadtree.h) whose tiles the photographs' cameras need are meshed
//            within kTerrainTolerancePx and kTerrainTriangleBudget (docs/design.md, "Terrain tiles").
//   up       as declared; without a CRS and without a declared up, the axis the cameras agree on
//            (hv/scene/scene_scale.h cameraUp); else +z.
//   origin   the centre of the data without its outliers (hv/scene/robust_extent.h), rounded to
//            whole metres.
#pragma once

#include "hv/math/aabb.h"
#include "hv/scene/heightfield.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace hv {

// Above this many cells a DTM becomes a quadtree of tiles (docs/formats.md, Limits).
constexpr std::uint64_t kTerrainTilesAboveCells = std::uint64_t(1024) * 1024;
// A terrain quadtree's tiles: cells a side, the screen-space tolerance from every photograph's
// camera, and the triangle budget (estimated: two a cell and two a skirt segment).
constexpr int kTerrainTileCells = 64;
constexpr double kTerrainTolerancePx = 2.0;
constexpr std::size_t kTerrainTriangleBudget = 2'000'000;

// The terrain of a DTM already in the scene frame: Scene::terrain meshed whole, or, above
// kTerrainTilesAboveCells, Scene::terrainTiles over the grid in memory, to be meshed by
// meshTerrainTiles once the cameras are known. Throws InputError naming `name` when every sample
// is no-data.
void terrainFromGrid(Scene& scene, Heightfield dtm, const std::string& name);

// Scene::terrain from Scene::terrainTiles: the tiles the photographs' cameras need, within the
// triangle budget, with their skirts; fills Scene::terrainTilesInfo's selection fields.
void meshTerrainTiles(Scene& scene);

// The rectangle an orthophoto is draped over: the terrain's (the quadtree's root tile, else the
// terrain mesh's bounds); empty without terrain.
Aabb terrainExtent(const Scene& scene);

// Scene::up by the rule above; `path` names scene.json (or the description) in the warnings: a
// declared up the cameras contradict, an up inferred far from z.
void settleUp(Scene& scene, bool upDeclared, const std::string& path, Diagnostics& diag);

// The render origin by the rule above.
glm::dvec3 dataOrigin(const Scene& scene);

}  // namespace hv
