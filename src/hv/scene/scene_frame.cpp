#include "hv/scene/scene_frame.h"

#include "hv/scene/robust_extent.h"
#include "hv/scene/scene_scale.h"
#include "hv/scene/terrain_quadtree.h"
#include "hv/util/log.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <memory>
#include <numbers>
#include <sstream>
#include <vector>

namespace hv {

void terrainFromGrid(Scene& scene, Heightfield dtm, const std::string& name) {
  if (std::uint64_t(dtm.cols) * std::uint64_t(dtm.rows) <= kTerrainTilesAboveCells) {
    scene.terrainTiles.reset();
    scene.terrain = dtm.toMesh();
    return;
  }
  auto source = std::make_shared<const HeightfieldTerrainSource>(std::move(dtm));
  auto tree = std::make_shared<TerrainQuadtree>(source, TerrainTileOptions{kTerrainTileCells});
  if (tree->tile(TerrainQuadtree::root()).bounds.empty())
    throw InputError(inputMessage(name, "", "every sample is no-data: no terrain to make"));
  scene.terrainTiles = std::move(tree);
  scene.terrainTilesInfo.reads = "a pyramid of averages built in memory";
}

// Scene::terrain from the quadtree: the tiles the photographs' cameras need (docs/design.md,
// "Terrain tiles"), within the triangle budget, with their skirts.
void meshTerrainTiles(Scene& scene) {
  const auto t0 = std::chrono::steady_clock::now();
  TerrainQuadtree& tree = *scene.terrainTiles;
  std::vector<Camera> cameras;
  cameras.reserve(scene.photos.size());
  for (const Photo& p : scene.photos) cameras.push_back(p.camera);
  const TerrainSelection sel = tree.select(cameras, kTerrainTolerancePx, kTerrainTriangleBudget);
  scene.terrain = tree.mesh(sel.nodes);
  Scene::TerrainTilesInfo& info = scene.terrainTilesInfo;
  info.tiles = sel.nodes.size();
  info.coarsestLevel = sel.coarsestLevel;
  info.finestLevel = sel.finestLevel;
  info.maxLevel = tree.maxLevel();
  info.tileCells = tree.tileCells();
  info.tolerancePx = kTerrainTolerancePx;
  info.triangleBudget = kTerrainTriangleBudget;
  info.budgetLimited = sel.budgetLimited;
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log::debug("terrain: " + std::to_string(sel.nodes.size()) + " tiles, levels " + std::to_string(sel.coarsestLevel) +
             ".." + std::to_string(sel.finestLevel) + " of 0.." + std::to_string(tree.maxLevel()) + ", " +
             std::to_string(scene.terrain.triangles.size()) + " triangles, " + std::to_string(tree.loadedTiles()) +
             " tiles read, " + std::to_string(s) + " s");
}

Aabb terrainExtent(const Scene& scene) {
  return scene.terrainTiles ? scene.terrainTiles->tile(TerrainQuadtree::root()).bounds : scene.terrain.bounds();
}

// The up axis of a scene that declares neither a CRS nor `up` (an SfM frame: Sceaux's is -z) is
// the one the cameras agree on (hv/scene/scene_scale.h cameraUp), when they agree well enough; a
// declared `up` that the cameras contradict is named. `info` says where the axis came from
// (hv/scene/scene_scale.h upOrigin).
void settleUp(Scene& scene, bool upDeclared, const std::string& path, Diagnostics& diag) {
  const CameraUp fromCameras = cameraUp(scene.photos);
  const bool agree = fromCameras.cameras > 0 && fromCameras.agreement >= kCameraUpAgreement;
  auto vec = [](const glm::dvec3& v) {
    std::ostringstream t;
    t << std::fixed << std::setprecision(3) << "(" << v.x << ", " << v.y << ", " << v.z << ")";
    return t.str();
  };
  if (upDeclared) {
    const double angle =
        std::acos(std::clamp(glm::dot(scene.up, fromCameras.up), -1.0, 1.0)) * 180.0 / std::numbers::pi;
    if (agree && angle > kCameraUpDisagreementDeg)
      diag.warn(path + ": up: " + vec(scene.up) + " is " + std::to_string(int(std::lround(angle))) +
                " degrees from the cameras' mean image up " + vec(fromCameras.up) + " (" +
                std::to_string(fromCameras.cameras) + " cameras); the views would be tilted or upside down");
    return;
  }
  if (!scene.crs.empty() || !agree) return;
  scene.up = fromCameras.up;
  const double fromZ = std::acos(std::clamp(scene.up.z, -1.0, 1.0)) * 180.0 / std::numbers::pi;
  if (fromZ > kCameraUpDisagreementDeg)
    diag.warn(path + ": no crs and no up: up " + vec(scene.up) + " inferred from the " +
              std::to_string(fromCameras.cameras) + " cameras (" + std::to_string(int(std::lround(fromZ))) +
              " degrees from z); give \"up\" in scene.json to choose another");
}

glm::dvec3 dataOrigin(const Scene& scene) {
  // Rounded to whole metres so the render frame is easy to read in logs; outliers left out (one
  // absurd coordinate would move it off the data).
  const Aabb inliers = robustExtent(scene).bounds;
  return glm::round(inliers.empty() ? glm::dvec3(0.0) : inliers.center());
}

}  // namespace hv
