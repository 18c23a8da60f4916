#include "hv/app/web_export_extras.h"

#include "hv/io/native/georef.h"
#include "hv/io/native/orthophoto_reader.h"
#include "hv/io/web_geocentric.h"
#include "hv/io/web_orthophoto.h"
#include "hv/scene/terrain_quadtree.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hv::app {

namespace {

// EPSG:4978 -> the scene CRS (through PROJ) over the scene's bounds widened by half their size (at
// least 500 m) and 200 m up and down: a 9 x 9 x 5 grid, ten unknowns per coordinate many times over.
GeocentricFit geocentricFit(const Scene& scene, Diagnostics& diag) {
  const GeoTransform toEcef(scene.crs, "EPSG:4978", diag);
  const Aabb b = scene.bounds();
  const glm::dvec3 size = b.size();
  const double widen = std::max(500.0, 0.5 * std::max(size.x, size.y));
  const glm::dvec3 lo = b.lo - glm::dvec3(widen, widen, 200.0), hi = b.hi + glm::dvec3(widen, widen, 200.0);
  std::vector<glm::dvec3> sceneSamples, ecef;
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      for (int k = 0; k <= 4; ++k) {
        const glm::dvec3 p = lo + (hi - lo) * glm::dvec3(i / 8.0, j / 8.0, k / 4.0);
        sceneSamples.push_back(p);
        ecef.push_back(toEcef.point(p));
      }
  return fitGeocentric(ecef, sceneSamples);
}

}  // namespace

void writeWebSceneExtras(const Scene& scene, const std::string& manifestPath, Diagnostics& diag) {
  nlohmann::json m;
  {
    std::ifstream in(manifestPath);
    std::stringstream text;
    text << in.rdbuf();
    m = nlohmann::json::parse(text.str());
  }
  if (!scene.crs.empty()) {
    try {
      m["geocentric"] = geocentricJson(geocentricFit(scene, diag));
    } catch (const std::exception& e) {
      diag.warn(manifestPath + ": geocentric: no EPSG:4978 fit for " + scene.crs + " (" + e.what() +
                "): the page cannot place earth-centred 3D Tiles");
    }
  }
  // The rectangle the native loader drapes an orthophoto over (scene_loader.cpp, readSceneOrthophoto).
  const Aabb extent = scene.terrainTiles ? scene.terrainTiles->tile(TerrainQuadtree::root()).bounds : scene.terrain.bounds();
  if (!extent.empty()) m["terrainExtent"] = {extent.lo.x, extent.lo.y, extent.hi.x, extent.hi.y};
  if (const std::shared_ptr<const Orthophoto> o = loadOrthophoto(scene, diag); o && !o->empty()) {
    try {
      m["orthophoto"] = writeWebOrthophoto(*o, std::filesystem::path(manifestPath).parent_path().string());
    } catch (const std::exception& e) {
      diag.warn(manifestPath + ": orthophoto: " + e.what() + " (left out of the export)");
    }
  }
  std::ofstream(manifestPath, std::ios::trunc) << m.dump(1) << "\n";
}

}  // namespace hv::app
