// Points from a 3D Tiles tileset in the browser (docs/web.md, "Points from 3D Tiles"; docs/services.md,
// "In the browser"): the page (web/services_layers.js) fetches tileset.json and the pnts contents
// over HTTP, a few at a time; this class chooses the tiles by screen-space error from the
// photographs' cameras (hv/io/tiles3d_select.h, the native reader's rule), parses each tile
// (hv::parsePnts), places the points in the scene frame and writes them as the web scene's
// points.bin (hv/io/web_scene.h), which WebViewer::load then reads like the export's. An
// earth-centred tileset (3D Tiles 1.0's default, EPSG:4978) is placed by the manifest's
// "geocentric" fit (hv/io/web_geocentric.h); a tileset already in the scene CRS as it is.
#include "hv/io/cameras_json.h"
#include "hv/io/tiles3d.h"
#include "hv/io/tiles3d_select.h"
#include "hv/io/web_geocentric.h"
#include "hv/io/web_scene.h"
#include "hv/scene/point_normals.h"
#include "hv/util/diagnostics.h"

#include <emscripten/bind.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace hv::web {

using json = nlohmann::json;

class WebPointTiles {
 public:
  // `manifest`: the web scene's manifest, its text (origin, crs, geocentric); `cameras`:
  // the cameras file there; `crs`: the tileset's CRS ("" : EPSG:4978). Returns "" or the error
  // (the URL, the field and what was expected): then no tile is asked for.
  std::string begin(const std::string& tilesetText, const std::string& url, const std::string& manifest,
                    const std::string& cameras, const std::string& crs, double tolerancePx, double budget) {
    try {
      const std::string manifestName = "scene_web.json";
      const json m = json::parse(manifest);
      const json o = m.value("origin", json::array());
      if (!o.is_array() || o.size() != 3) throw InputError(manifestName + ": origin: expected 3 numbers");
      origin_ = {o[0].get<double>(), o[1].get<double>(), o[2].get<double>()};
      const std::string sceneCrs = m.value("crs", std::string());
      const std::string tilesCrs = crs.empty() ? "EPSG:4978" : crs;
      if (tilesCrs != sceneCrs) {
        if (tilesCrs != "EPSG:4978")
          throw InputError(url + ": points.crs: " + tilesCrs + ": the browser places a tileset in EPSG:4978 or in the " +
                           "scene CRS (" + sceneCrs + ") only");
        if (!m.contains("geocentric"))
          throw InputError(manifestName + ": geocentric: missing (expected the EPSG:4978 fit that web-export writes for a " +
                           "scene with a CRS; export the scene again)");
        fit_ = geocentricFromJson(m["geocentric"], manifestName);
      }
      Diagnostics diag;
      CameraFileOptions co;
      co.requireImages = false;
      co.checkImageFiles = false;
      std::vector<Camera> cams;
      for (const Photo& p : readCameraFile(cameras, co, diag)) cams.push_back(p.camera);
      Tiles3dTileset ts = parseTileset(tilesetText, url);
      tilesInTileset_ = ts.tiles.size();
      notes_ = ts.notes;
      std::function<glm::dvec3(const glm::dvec3&)> toScene;
      if (fit_) toScene = [f = *fit_](const glm::dvec3& p) { return applyGeocentric(f, p); };
      const double cap = std::isfinite(budget) && budget > 0 ? budget : 20e6;
      selection_ = std::make_unique<PointTileSelection>(std::move(ts), std::move(cams), toScene, tolerancePx,
                                                        std::size_t(cap));
      return "";
    } catch (const std::exception& e) {
      selection_.reset();
      return e.what();
    }
  }
  // [{"tile": i, "url": "…/r0.pnts"}, ...]: the contents to fetch next; [] when done.
  std::string next() {
    json a = json::array();
    if (!selection_) return a.dump();
    for (int t : selection_->next()) a.push_back({{"tile", t}, {"url", selection_->tileset().tiles[std::size_t(t)].content}});
    return a.dump();
  }
  // A tile's bytes arrived: parsed (a bad tile is left out, named) and taken into its tile's frame.
  void arrived(int tile, const std::string& bytes) {
    if (!valid(tile)) return;
    const Tiles3dTile& t = selection_->tileset().tiles[std::size_t(tile)];
    try {
      PntsTile p = parsePnts(bytes, t.content);
      PointCloud& c = p.points;
      for (glm::dvec3& q : c.positions) q = glm::dvec3(t.transform * glm::dvec4(q, 1.0));
      if (!c.normals.empty()) {
        const glm::dmat3 turn = glm::inverse(glm::transpose(glm::dmat3(t.transform)));
        for (glm::vec3& n : c.normals) n = unit(turn * glm::dvec3(n));
      }
      bytes_ += bytes.size();
      selection_->arrived(tile, std::move(c));
    } catch (const std::exception& e) {
      selection_->failed(tile, e.what());
    }
  }
  // A tile that could not be fetched: `message` names the URL and the status.
  void failed(int tile, const std::string& message) {
    if (valid(tile)) selection_->failed(tile, message);
  }
  // Writes the chosen points into `pointsPath` (points.bin, relative to the manifest's origin) and
  // returns {"count", "bytes", "tilesRead", "tilesKept", "tilesInTileset", "pntsBytes",
  // "budgetLimited", "maxFitError", "errors": [...], "notes": [...]}.
  std::string finish(const std::string& pointsPath) {
    json r = {{"count", 0}, {"bytes", 0}, {"errors", json::array()}, {"notes", notes_}};
    if (!selection_) return r.dump();
    PointCloud cloud = selection_->points();
    if (fit_) {
      for (std::size_t i = 0; i < cloud.positions.size(); ++i) {
        const glm::dvec3 p = cloud.positions[i];
        if (i < cloud.normals.size()) {
          const glm::dmat3 turn = glm::inverse(glm::transpose(geocentricJacobian(*fit_, p)));
          cloud.normals[i] = unit(turn * glm::dvec3(cloud.normals[i]));
        }
        cloud.positions[i] = applyGeocentric(*fit_, p);
      }
    }
    // Tiles without normals (lidar seldom has them) get them estimated as web-export estimates the
    // export's (hv/scene/point_normals.h: the same estimate whatever the points' order).
    if (!cloud.empty() && cloud.normals.empty()) {
      NormalEstimation ne;
      ne.threads = 0;  // no threads in the browser build
      estimateNormals(cloud, ne);
    }
    std::size_t written = 0;
    if (!cloud.empty()) {
      const std::string bytes = webPointBytes(cloud, origin_);
      std::ofstream(pointsPath, std::ios::binary | std::ios::trunc).write(bytes.data(), std::streamsize(bytes.size()));
      written = bytes.size();
    }
    r["count"] = cloud.size();
    r["bytes"] = written;
    r["tilesRead"] = selection_->tilesRead();
    r["tilesKept"] = selection_->tilesKept();
    r["tilesInTileset"] = tilesInTileset_;
    r["pntsBytes"] = bytes_;
    r["budgetLimited"] = selection_->budgetLimited();
    r["maxFitError"] = fit_ ? fit_->maxError : 0.0;
    r["errors"] = selection_->errors();
    return r.dump();
  }

 private:
  bool valid(int tile) const {
    return selection_ && tile >= 0 && std::size_t(tile) < selection_->tileset().tiles.size();
  }
  static glm::vec3 unit(const glm::dvec3& m) {
    const double len = glm::length(m);
    return len > 0.0 && std::isfinite(len) ? glm::vec3(m / len) : glm::vec3(0, 0, 1);
  }

  std::unique_ptr<PointTileSelection> selection_;
  std::optional<GeocentricFit> fit_;
  glm::dvec3 origin_{0.0};
  std::size_t tilesInTileset_ = 0;
  std::uint64_t bytes_ = 0;
  std::vector<std::string> notes_;
};

EMSCRIPTEN_BINDINGS(histoview_tiles) {
  emscripten::class_<WebPointTiles>("WebPointTiles")
      .constructor<>()
      .function("begin", &WebPointTiles::begin)
      .function("next", &WebPointTiles::next)
      .function("arrived", &WebPointTiles::arrived)
      .function("failed", &WebPointTiles::failed)
      .function("finish", &WebPointTiles::finish);
}

}  // namespace hv::web
