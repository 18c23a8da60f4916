// Writes the demo scene to disk: the renderer's inputs (scene.json, dtm.tif, buildings.geojson,
// points.las/.ply,
// cameras.json, images/, masks/) and the evaluation ground truth (views.json, truth/).
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "hv/demo/demo_city.h"
#include "hv/io/las_writer.h"
#include "hv/io/ply_points.h"
#include "hv/io/raster.h"

namespace hv::demo {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// nlohmann::json prints doubles in their shortest round-trip form (up to 17 significant digits),
// so cameras and footprints are written without loss.
void writeJson(const fs::path& path, const json& j) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  f << j.dump(1) << '\n';
  if (!f) throw std::runtime_error("cannot write " + path.string());
}

json vec(glm::dvec2 v) { return json::array({v.x, v.y}); }
json vec(glm::dvec3 v) { return json::array({v.x, v.y, v.z}); }

json cameraJson(const Camera& c) {
  double r[9];
  mat3ToRowMajor(c.camFromWorld, r);
  json j;
  j["id"] = c.id;
  j["width"] = c.width;
  j["height"] = c.height;
  j["center"] = vec(c.center);
  j["rotation"] = json(std::vector<double>(r, r + 9));
  j["focal"] = vec(c.focal);
  j["principal"] = vec(c.principal);
  j["skew"] = c.skew;
  if (c.distortion) {
    const RadialDistortion& d = *c.distortion;
    j["distortion"] = {{"type", "radial"}, {"center", vec(d.center)}, {"c3", d.c3}, {"c5", d.c5},
                       {"c7", d.c7},       {"r2max", d.r2max}};
  }
  return j;
}

json buildingsGeoJson(const World& w) {
  json features = json::array();
  for (const Footprint& fp : w.footprints) {
    json rings = json::array();
    for (const auto& ring : fp.rings) {
      json r = json::array();
      for (glm::dvec2 p : ring) r.push_back(vec(p));
      r.push_back(vec(ring.front()));  // GeoJSON rings are closed
      rings.push_back(r);
    }
    features.push_back({{"type", "Feature"},
                        {"id", fp.id},
                        {"properties", {{"id", fp.id}, {"height", fp.height.value_or(0.0)}}},
                        {"geometry", {{"type", "Polygon"}, {"coordinates", rings}}}});
  }
  // The pre-RFC 7946 "crs" member: OGR honours it, so the layer reads as Lambert-93.
  return {{"type", "FeatureCollection"},
          {"name", "buildings"},
          {"crs", {{"type", "name"}, {"properties", {{"name", "urn:ogc:def:crs:EPSG::2154"}}}}},
          {"features", features}};
}

}  // namespace

DemoSummary generate(const DemoOptions& options, const std::string& outDir,
                     std::function<void(const std::string&)> progress) {
  auto say = [&](const std::string& m) {
    if (progress) progress(m);
  };
  const auto t0 = std::chrono::steady_clock::now();
  const fs::path dir(outDir);
  for (const char* sub : {"images", "masks", "truth"}) fs::create_directories(dir / sub);

  World world = buildWorld(options);
  {
    std::ostringstream m;
    m << "demo city: " << world.buildings.size() << " buildings, " << world.truth.mesh.triangles.size()
      << " ground-truth triangles, " << world.trees.mesh.triangles.size() << " tree triangles";
    say(m.str());
  }
  writeGeoTiff((dir / "dtm.tif").string(), world.dtm, "EPSG:2154");
  writeJson(dir / "buildings.geojson", buildingsGeoJson(world));
  const auto tScan = std::chrono::steady_clock::now();
  const PointCloud scan = simulateLidar(world);
  writeLas((dir / "points.las").string(), scan);  // LAS 1.2, format 3 (RGB)
  writePlyPoints((dir / "points.ply").string(), scan);  // the same points with their normals
  {
    const auto h = scan.classHistogram();
    std::ostringstream m;
    m << "demo city: lidar scan, " << scan.size() << " points (ground " << h[2] << ", building " << h[6]
      << ", vegetation " << h[5] << ", cars " << h[1] << ") in "
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - tScan).count() << " s";
    say(m.str());
  }
  writeJson(dir / "scene.json", {{"crs", "EPSG:2154"},
                                 {"terrain", {{"path", "dtm.tif"}}},
                                 {"buildings", {{"path", "buildings.geojson"}, {"height", "height"}}},
                                 {"points", {{"path", "points.las"}}},
                                 {"cameras", {{"path", "cameras.json"}}}});

  const RayCaster caster(world.truth.mesh);
  const ShotPlan plan = planShots(world, caster);
  say("demo city: cameras placed (" + std::to_string(plan.photos.size()) + " photographs, " +
      std::to_string(plan.views.size()) + " views)");

  json cams = json::array();
  for (size_t k = 0; k < plan.photos.size(); ++k) {
    const Shot& shot = plan.photos[k];
    const Rendered r = renderShot(world, caster, shot, options.samplesPerAxis);
    const std::string image = "images/" + shot.camera.id + ".png";
    writePng((dir / image).string(), r.color);
    json j = cameraJson(shot.camera);
    j["image"] = image;
    if (shot.masked) {
      const std::string mask = "masks/" + shot.camera.id + ".png";
      writePng((dir / mask).string(), r.mask);
      j["mask"] = mask;
    }
    j["date"] = shot.date;
    cams.push_back(j);
    say("demo city: photograph " + std::to_string(k + 1) + "/" + std::to_string(plan.photos.size()));
  }
  writeJson(dir / "cameras.json", {{"cameras", cams}});

  json views = json::array();
  for (size_t k = 0; k < plan.views.size(); ++k) {
    const Shot& shot = plan.views[k];
    const Rendered r = renderShot(world, caster, shot, options.samplesPerAxis);
    writePng((dir / "truth" / (shot.camera.id + ".png")).string(), r.color);
    writePng((dir / "truth" / (shot.camera.id + ".coverage.png")).string(), r.coverage);
    views.push_back(cameraJson(shot.camera));
    say("demo city: view " + std::to_string(k + 1) + "/" + std::to_string(plan.views.size()));
  }
  writeJson(dir / "views.json", {{"cameras", views}});

  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::ostringstream m;
  m << "demo city written to " << dir.string() << " in " << seconds << " s";
  say(m.str());

  DemoSummary summary;
  summary.scenePath = (dir / "scene.json").string();
  summary.viewsPath = (dir / "views.json").string();
  summary.truthDir = (dir / "truth").string();
  summary.photos = int(plan.photos.size());
  summary.views = int(plan.views.size());
  summary.buildings = int(world.buildings.size());
  summary.points = scan.size();
  return summary;
}

}  // namespace hv::demo
