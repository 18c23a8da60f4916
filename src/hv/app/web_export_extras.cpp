#include "hv/app/web_export_extras.h"

#include "hv/io/native/georef.h"
#include "hv/io/native/orthophoto_reader.h"
#include "hv/io/web_geocentric.h"
#include "hv/io/web_orthophoto.h"
#include "hv/scene/scene_frame.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hv::app {

namespace {

// EPSG:4978 -> the scene CRS (through PROJ) at the samples of hv/scene/geocentric_fit.h.
GeocentricFit geocentricFit(const Scene& scene, Diagnostics& diag) {
  const GeoTransform toEcef(scene.crs, "EPSG:4978", diag);
  const std::vector<glm::dvec3> sceneSamples = geocentricFitSamples(scene.bounds());
  std::vector<glm::dvec3> ecef;
  ecef.reserve(sceneSamples.size());
  for (const glm::dvec3& p : sceneSamples) ecef.push_back(toEcef.point(p));
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
  const Aabb extent = terrainExtent(scene);  // hv/scene/scene_frame.h: also the page's without an export
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
