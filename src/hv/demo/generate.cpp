// Writes the demo scene to disk: the renderer's inputs (scene.json, dtm.tif, buildings.geojson,
// points.las/.ply,
// cameras.json, images/, masks/) and the evaluation ground truth (views.json, truth/).
#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>

#include "hv/demo/city_files.h"
#include "hv/demo/demo_city.h"
#include "hv/demo/demo_internal.h"
#include "hv/demo/vehicle_models.h"
#include "hv/image/native/png_write.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/las_writer.h"
#include "hv/io/native/orthophoto_reader.h"
#include "hv/io/native/ply_points.h"
#include "hv/io/native/raster.h"

namespace hv::demo {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The orthophoto's longer side, pixels.
constexpr int kDemoOrthophotoSide = 384;

// nlohmann::json prints doubles in their shortest round-trip form (up to 17 significant digits),
// so cameras and footprints are written without loss.
void writeText(const fs::path& path, const std::string& text) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  f << text << '\n';
  if (!f) throw std::runtime_error("cannot write " + path.string());
}

void writeJson(const fs::path& path, const json& j) { writeText(path, j.dump(1)); }

json vec(glm::dvec2 v) { return json::array({v.x, v.y}); }

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
    m << "demo city: " << world.buildings.size() << " buildings" << (options.blocks > 0 ? " with ground truth" : "")
      << ", " << world.truth.mesh.triangles.size() << " ground-truth triangles, " << world.trees.mesh.triangles.size()
      << " tree triangles";
    say(m.str());
  }
  const bool large = options.blocks > 0;
  std::size_t footprints = world.footprints.size();
  if (!large) {
    writeGeoTiff((dir / "dtm.tif").string(), world.dtm, "EPSG:2154");
    writeJson(dir / "buildings.geojson", buildingsGeoJson(world));
  } else {
    const auto tFiles = std::chrono::steady_clock::now();
    detail::writeCog((dir / "dtm.tif").string(), world.dtm, "EPSG:2154");
    {
      std::ostringstream m;
      m << "demo city: DTM " << world.dtm.cols << " x " << world.dtm.rows << " cells of " << world.dtm.cellX
        << " m (Cloud-Optimized GeoTIFF)";
      say(m.str());
    }
    detail::GeoPackageWriter gpkg((dir / "buildings.gpkg").string(), "EPSG:2154");
    int reported = 0;
    forEachFootprint(
        options, [&](const Footprint& fp) { gpkg.add(fp); },
        [&](int done, int rows) {
          // A line per tenth of the rows, whatever the size.
          if (done * 10 / rows == reported) return;
          reported = done * 10 / rows;
          say("demo city: footprints, block row " + std::to_string(done) + "/" + std::to_string(rows) + " (" +
              std::to_string(gpkg.count()) + " buildings)");
        });
    gpkg.close();
    footprints = gpkg.count();
    std::ostringstream m;
    m << "demo city: " << footprints << " footprints (GeoPackage), DTM and footprints written in "
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - tFiles).count() << " s";
    say(m.str());
  }
  const auto tScan = std::chrono::steady_clock::now();
  const PointCloud scan = simulateLidar(world);
  writeLas((dir / "points.las").string(), scan);        // LAS 1.2, format 3 (RGB)
  writePlyPoints((dir / "points.ply").string(), scan);  // the same points with their normals
  {
    const auto h = scan.classHistogram();
    std::ostringstream m;
    m << "demo city: lidar scan, " << scan.size() << " points (ground " << h[2] << ", building " << h[6]
      << ", vegetation " << h[5] << ", cars " << h[1] << ") in "
      << std::chrono::duration<double>(std::chrono::steady_clock::now() - tScan).count() << " s";
    say(m.str());
  }
  // The orthophoto draped where no photograph reaches: the ground truth from above, a few hundred
  // pixels a side (cheap: one ray per pixel), as a cloud-optimised GeoTIFF.
  const RayCaster caster(world.truth.mesh);
  {
    const auto tOrtho = std::chrono::steady_clock::now();
    const Orthophoto ortho = detail::orthophotoFromAbove(world, caster, kDemoOrthophotoSide);
    writeOrthophotoCog((dir / "orthophoto.tif").string(), ortho, "EPSG:2154");
    std::ostringstream m;
    m << "demo city: orthophoto " << ortho.width << " x " << ortho.height << " px of " << ortho.metresPerPixelX()
      << " m in " << std::chrono::duration<double>(std::chrono::steady_clock::now() - tOrtho).count() << " s";
    say(m.str());
  }
  json sceneJson = {{"crs", "EPSG:2154"},
                    {"terrain", {{"path", "dtm.tif"}}},
                    {"orthophoto", {{"path", "orthophoto.tif"}}},
                    {"buildings", {{"path", large ? "buildings.gpkg" : "buildings.geojson"}, {"height", "height"}}},
                    {"points", {{"path", "points.las"}}},
                    {"cameras", {{"path", "cameras.json"}}}};
  TrafficResult traffic;
  if (options.traffic.enabled) {
    traffic = simulateTraffic(world, options.traffic, dir.string());
    if (traffic.ok) {
      sceneJson["traffic"] = {{"fcd", "fcd.xml"}, {"offset", {traffic.offset.x, traffic.offset.y}}};
      // The vehicles' models (docs/traffic.md): a car, a bus and a truck made by code.
      json models = json::object();
      for (const std::string& name : writeVehicleModels((dir / "vehicles").string()))
        models[name.substr(0, name.size() - 5)] = "vehicles/" + name;
      sceneJson["traffic"]["models"] = models;
    }
    say("demo city: traffic: " + traffic.message + (traffic.ok ? "" : " (the scene has no traffic)"));
  }
  writeJson(dir / "scene.json", sceneJson);

  const ShotPlan plan = planShots(world, caster);
  say("demo city: cameras placed (" + std::to_string(plan.photos.size()) + " photographs, " +
      std::to_string(plan.views.size()) + " views)");

  std::vector<Photo> photos;
  for (size_t k = 0; k < plan.photos.size(); ++k) {
    const Shot& shot = plan.photos[k];
    const Rendered r = renderShot(world, caster, shot, options.samplesPerAxis);
    Photo& photo = photos.emplace_back();
    photo.camera = shot.camera;
    photo.imagePath = (dir / "images" / (shot.camera.id + ".png")).string();
    writePng(photo.imagePath, r.color);
    if (shot.masked) {
      photo.maskPath = (dir / "masks" / (shot.camera.id + ".png")).string();
      writePng(photo.maskPath, r.mask);
    }
    photo.date = shot.date;
    say("demo city: photograph " + std::to_string(k + 1) + "/" + std::to_string(plan.photos.size()));
  }
  writeText(dir / "cameras.json", cameraJson(photos, dir.string()));

  std::vector<Photo> views;
  for (size_t k = 0; k < plan.views.size(); ++k) {
    const Shot& shot = plan.views[k];
    const Rendered r = renderShot(world, caster, shot, options.samplesPerAxis);
    writePng((dir / "truth" / (shot.camera.id + ".png")).string(), r.color);
    writePng((dir / "truth" / (shot.camera.id + ".coverage.png")).string(), r.coverage);
    views.emplace_back().camera = shot.camera;
    say("demo city: view " + std::to_string(k + 1) + "/" + std::to_string(plan.views.size()));
  }
  writeText(dir / "views.json", cameraJson(views, dir.string()));

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
  summary.buildings = int(footprints);
  summary.traffic = traffic;
  summary.points = scan.size();
  return summary;
}

}  // namespace hv::demo
