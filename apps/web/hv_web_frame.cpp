// The frame of a service scene the page reads without `web-export` (docs/services.md, "In the
// browser"; hv/io/web_scene_frame.h): the page writes a manifest without an origin (the DTM grid
// from the WCS as "terrain", the buildings' GeoJSON pages, the cameras), and asks the module for
// the origin, up and terrain rectangle the native loader gives the same data, before it fetches
// the layers that need them (3D Tiles points stored relative to the origin, the orthophoto over
// the terrain's rectangle).
#include "hv/io/web_geocentric.h"
#include "hv/io/web_scene.h"
#include "hv/io/web_scene_frame.h"
#include "hv/util/diagnostics.h"

#include <emscripten/bind.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <string>
#include <vector>

namespace hv::web {

namespace {

// {"origin", "up", "terrainExtent", "bounds", "errors": [...]} (hv/io/web_scene_frame.h), or
// {"error": "..."} when the manifest cannot be read at all.
std::string webSceneFrame(const std::string& manifestPath) {
  try {
    Diagnostics diag;
    WebSceneOptions options;
    options.checkImageFiles = false;  // the photographs come after the scene
    const Scene scene = readWebScene(manifestPath, options, diag);
    nlohmann::json out = webSceneFrameJson(scene);
    // Where the page samples the EPSG:4978 fit (its proj4js maps them, webGeocentricFit fits).
    if (const Aabb b = scene.bounds(); !scene.crs.empty() && !b.empty()) {
      nlohmann::json flat = nlohmann::json::array();
      for (const glm::dvec3& p : geocentricFitSamples(b)) flat.insert(flat.end(), {p.x, p.y, p.z});
      out["geocentricSamples"] = std::move(flat);
    }
    out["errors"] = nlohmann::json::array();
    for (const std::string& e : diag.errors) out["errors"].push_back(e);
    return out.dump();
  } catch (const std::exception& e) {
    return nlohmann::json{{"error", e.what()}}.dump();
  }
}

// {"scene": [x, y, z, ...], "ecef": [X, Y, Z, ...]} (the samples above, and where the page's
// proj4js puts them in EPSG:4978) -> the manifest's "geocentric" entry (hv/io/web_geocentric.h),
// or {"error": "..."}.
std::string webGeocentricFit(const std::string& samplesJson) {
  try {
    const nlohmann::json j = nlohmann::json::parse(samplesJson);
    auto points = [&](const char* key) {
      const std::vector<double> v = j.at(key).get<std::vector<double>>();
      if (v.size() % 3) throw InputError(std::string(key) + ": expected x, y, z triples");
      std::vector<glm::dvec3> out;
      for (std::size_t i = 0; i + 2 < v.size(); i += 3) {
        const glm::dvec3 p(v[i], v[i + 1], v[i + 2]);
        if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
          throw InputError(std::string(key) + ": sample " + std::to_string(i / 3) + " is not finite");
        out.push_back(p);
      }
      return out;
    };
    const std::vector<glm::dvec3> scene = points("scene"), ecef = points("ecef");
    if (scene.size() != ecef.size()) throw InputError("expected as many EPSG:4978 samples as scene samples");
    return geocentricJson(fitGeocentric(ecef, scene)).dump();
  } catch (const std::exception& e) {
    return nlohmann::json{{"error", e.what()}}.dump();
  }
}

}  // namespace

EMSCRIPTEN_BINDINGS(histoview_frame) {
  emscripten::function("webSceneFrame", &webSceneFrame);
  emscripten::function("webGeocentricFit", &webGeocentricFit);
}

}  // namespace hv::web
