// web-export writes the demo city as a web scene; the portable reader (hv/io/web_scene.h) reads
// it back to the same geometry, points and cameras as the native scene loader. A broken mesh or
// point file is reported, naming the file and the field, and left out.
#include "hv/app/web_export_command.h"
#include "hv/demo/demo_city.h"
#include "hv/image/image.h"
#include "hv/io/native/ply_points.h"
#include "hv/io/native/scene_loader.h"
#include "hv/io/web_scene.h"
#include "hv/scene/point_normals.h"
#include "hv/traffic/trajectories.h"
#include "hv/traffic/vehicle_model.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <unistd.h>

namespace hv::app {
namespace {

namespace fs = std::filesystem;

TEST(WebExport, DemoCityRoundTrip) {
  const fs::path dir = fs::temp_directory_path() / ("hv_web_export_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  demo::DemoOptions small;
  small.buildings = 8;
  small.photos = 6;
  small.views = 2;
  small.samplesPerAxis = 1;
  const demo::DemoSummary city = demo::generate(small, (dir / "city").string());

  WebExportOptions o;
  o.scenePath = city.scenePath;
  o.out = (dir / "web").string();
  o.viewsPath = city.viewsPath;
  o.pageDir = (dir / "no-page").string();  // the page is not under test here
  o.wasmDir = (dir / "no-wasm").string();
  ASSERT_EQ(runWebExport(o), 0);

  Diagnostics nativeDiag, webDiag;
  Scene native = loadScene(city.scenePath, nativeDiag);
  resolveNormals(native.points);  // estimated when first needed: the export estimated them
  const Scene web = readWebScene((dir / "web" / kWebSceneManifest).string(), {}, webDiag);
  EXPECT_TRUE(webDiag.ok()) << (webDiag.errors.empty() ? "" : webDiag.errors[0]);
  EXPECT_EQ(web.crs, native.crs);
  EXPECT_EQ(web.origin, native.origin);
  EXPECT_EQ(web.up, native.up);
  EXPECT_EQ(web.terrain.triangles, native.terrain.triangles);
  EXPECT_EQ(web.buildings.triangles, native.buildings.triangles);
  EXPECT_EQ(web.buildings.triangleTags, native.buildings.triangleTags);
  EXPECT_EQ(web.buildingValidity, native.buildingValidity);
  ASSERT_FALSE(web.terrain.empty());
  ASSERT_FALSE(web.buildings.empty());
  // Positions are float32 relative to the origin: the demo city spans a few hundred metres, so
  // the round trip is exact to well under a millimetre. The bounds include the lidar scan.
  ASSERT_FALSE(native.points.empty());
  EXPECT_EQ(web.points.size(), native.points.size());
  EXPECT_EQ(web.points.fields().describe(), native.points.fields().describe());
  EXPECT_FALSE(web.points.chunks.empty());
  const Aabb a = native.bounds(), b = web.bounds();
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(a.lo[i], b.lo[i], 1e-4);
    EXPECT_NEAR(a.hi[i], b.hi[i], 1e-4);
  }
  for (size_t i = 0; i < native.terrain.positions.size(); ++i)
    ASSERT_LT(glm::distance(native.terrain.positions[i], web.terrain.positions[i]), 1e-4);

  ASSERT_EQ(web.photos.size(), native.photos.size());
  for (size_t i = 0; i < web.photos.size(); ++i) {
    const Camera &n = native.photos[i].camera, &w = web.photos[i].camera;
    EXPECT_EQ(w.id, n.id);
    EXPECT_EQ(w.width, n.width);
    EXPECT_EQ(w.height, n.height);
    EXPECT_LT(glm::distance(w.center, n.center), 1e-9);
    EXPECT_EQ(w.focal, n.focal);
    EXPECT_EQ(w.principal, n.principal);
    EXPECT_EQ(w.distortion.has_value(), n.distortion.has_value());
    EXPECT_EQ(web.photos[i].date, native.photos[i].date);
    EXPECT_EQ(web.photos[i].maskPath.empty(), native.photos[i].maskPath.empty());
    // Every photograph is a JPEG the browser build's decoder reads, at the photograph's size.
    const Image8 img = readImage(web.photos[i].imagePath);
    EXPECT_EQ(img.width, n.width);
    EXPECT_EQ(img.height, n.height);
    EXPECT_EQ(fs::path(web.photos[i].imagePath).extension(), ".jpg");
  }
  EXPECT_TRUE(fs::exists(dir / "web" / "views.json"));
  fs::remove_all(dir);
}

// A small cloud at Lambert-93 coordinates, every field, through scene.json (PLY) -> web-export ->
// the portable reader. The intensity numbers the points, so each read-back point finds its source
// whatever order the chunking left them in.
TEST(WebExport, PointCloudRoundTrip) {
  const fs::path dir = fs::temp_directory_path() / ("hv_web_points_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  PointCloud cloud;
  cloud.resize(3000, {.intensity = true, .classification = true, .rgb = true, .normals = true});
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    const double u = double(i % 60), v = double(i / 60);
    cloud.positions[i] = {651234.567 + 0.37 * u, 6862345.678 + 0.29 * v, 35.2 + 0.013 * double(i % 17)};
    const glm::vec3 n(std::sin(0.1f * float(i)), std::cos(0.3f * float(i)), float(i % 5) - 2.0f);
    cloud.normals[i] = i % 10 == 3 ? glm::vec3(0.0f) : glm::normalize(n);  // some without a normal
    cloud.rgb[i] = {std::uint16_t(i * 37 % 65536), std::uint16_t(65535 - i), std::uint16_t(i * 257 % 65536)};
    cloud.classification[i] = std::uint8_t(i % 7 == 0 ? 6 : i % 3);
    cloud.intensity[i] = std::uint16_t(i);
  }
  writePlyPoints((dir / "cloud.ply").string(), cloud);
  std::ofstream(dir / "scene.json") << R"({"crs": "EPSG:2154", "points": {"path": "cloud.ply"}})";
  WebExportOptions o;
  o.scenePath = (dir / "scene.json").string();
  o.out = (dir / "web").string();
  o.pageDir = (dir / "no-page").string();
  o.wasmDir = (dir / "no-wasm").string();
  ASSERT_EQ(runWebExport(o), 0);

  Diagnostics nativeDiag, webDiag;
  const Scene native = loadScene(o.scenePath, nativeDiag);
  const Scene web = readWebScene((dir / "web" / kWebSceneManifest).string(), {}, webDiag);
  EXPECT_TRUE(webDiag.ok()) << (webDiag.errors.empty() ? "" : webDiag.errors[0]);
  ASSERT_EQ(native.points.size(), cloud.size());
  ASSERT_EQ(web.points.size(), cloud.size());
  ASSERT_TRUE(web.points.consistent());
  ASSERT_EQ(web.points.fields().describe(), "xyz intensity classification rgb normals");
  EXPECT_FALSE(web.points.chunks.empty());
  EXPECT_EQ(web.origin, native.origin);
  std::map<std::uint16_t, std::size_t> nativeIndex;
  for (std::size_t i = 0; i < native.points.size(); ++i) nativeIndex[native.points.intensity[i]] = i;
  ASSERT_EQ(nativeIndex.size(), cloud.size());
  for (std::size_t i = 0; i < web.points.size(); ++i) {
    SCOPED_TRACE("point " + std::to_string(web.points.intensity[i]));
    const std::size_t k = nativeIndex.at(web.points.intensity[i]);
    // Positions: float32 relative to the origin, exactly what the native point pass uploads.
    const glm::dvec3 nativeOffset = native.points.positions[k] - native.origin;
    const glm::dvec3 webOffset = web.points.positions[i] - web.origin;
    ASSERT_EQ(glm::vec3(webOffset), glm::vec3(nativeOffset));
    ASSERT_LT(glm::distance(web.points.positions[i], native.points.positions[k]), 1e-4);
    // Normals: snorm16, within half a step (1 / 32767) of the source; none stays none.
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(web.points.normals[i][c], native.points.normals[k][c], 0.5 / 32767 + 1e-6);
    ASSERT_EQ(web.points.normals[i] == glm::vec3(0.0f), native.points.normals[k] == glm::vec3(0.0f));
    // Colours: the 8 bits the point pass shows (value / 257), back as value * 257.
    ASSERT_EQ(web.points.rgb[i], (native.points.rgb[k] / std::uint16_t(257)) * std::uint16_t(257));
    ASSERT_EQ(web.points.classification[i], native.points.classification[k]);
  }
  // The manifest names the file, its count and size.
  std::ifstream manifestFile(dir / "web" / kWebSceneManifest);
  const auto manifest = nlohmann::json::parse(manifestFile);
  EXPECT_EQ(manifest.at("points").at("count").get<std::size_t>(), cloud.size());
  EXPECT_EQ(manifest.at("points").at("bytes").get<std::uintmax_t>(), fs::file_size(dir / "web" / kWebPointsFile));

  // --max-points: a subsample of the same points.
  o.maxPoints = 1000;
  o.out = (dir / "web-1000").string();
  ASSERT_EQ(runWebExport(o), 0);
  const Scene sub = readWebScene((dir / "web-1000" / kWebSceneManifest).string(), {}, webDiag);
  ASSERT_EQ(sub.points.size(), 1000u);
  for (std::size_t i = 0; i < sub.points.size(); ++i) {
    const std::size_t k = nativeIndex.at(sub.points.intensity[i]);
    ASSERT_LT(glm::distance(sub.points.positions[i], native.points.positions[k]), 1e-4);
  }
  fs::remove_all(dir);
}

TEST(WebScene, BrokenPointFilesAreReportedAndLeftOut) {
  const fs::path dir = fs::temp_directory_path() / ("hv_web_points_broken_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  PointCloud cloud;
  cloud.resize(10, {.classification = true, .rgb = true, .normals = true});
  for (std::size_t i = 0; i < cloud.size(); ++i) cloud.positions[i] = {651000.0 + double(i), 6862000.0, 30.0};
  const std::string good = webPointBytes(cloud, {651000.0, 6862000.0, 0.0});
  ASSERT_EQ(good.size(), 24u + 10u * (12 + 6 + 3 + 1));
  // A terrain that loads, so that the rest of the scene is seen to survive a bad point file.
  std::string terrain;
  const float tri[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  const std::uint32_t idx[3] = {0, 1, 2};
  terrain.append(reinterpret_cast<const char*>(tri), sizeof(tri));
  terrain.append(reinterpret_cast<const char*>(idx), sizeof(idx));
  std::ofstream(dir / "terrain.bin", std::ios::binary) << terrain;
  std::ofstream(dir / "cameras.json") << R"({"cameras": []})";
  auto load = [&](const std::string& bytes, const std::string& pointsEntry) {
    std::ofstream(dir / "points.bin", std::ios::binary | std::ios::trunc) << bytes;
    std::ofstream(dir / "scene_web.json") << R"({"format": "histoview-web", "version": 1,
      "origin": [651000, 6862000, 0],
      "meshes": [{"name": "terrain", "path": "terrain.bin", "vertices": 3, "triangles": 1}],
      "points": )" << pointsEntry << R"(, "cameras": "cameras.json"})";
    Diagnostics diag;
    const Scene s = readWebScene((dir / "scene_web.json").string(), {}, diag);
    EXPECT_FALSE(s.terrain.empty());
    return std::make_pair(s.points.size(), diag.errors);
  };
  const std::string entry = R"({"path": "points.bin", "count": 10, "bytes": )" + std::to_string(good.size()) + "}";
  {
    const auto [n, errors] = load(good, entry);
    EXPECT_EQ(n, 10u);
    EXPECT_TRUE(errors.empty()) << errors[0];
  }
  std::string badMagic = good, badVersion = good, badFields = good, hugeCount = good;
  badMagic[0] = 'X';
  badVersion[8] = 2;
  badFields[12] = char(0xff);
  hugeCount[20] = 1;  // 2^32 + 10 points
  std::string notFinite = good;
  const float inf = std::numeric_limits<float>::infinity();
  std::memcpy(notFinite.data() + 24 + 12 * 4 + 4, &inf, 4);  // point 4's y
  struct Case {
    std::string bytes, entry, expect;
  };
  const std::string any = R"({"path": "points.bin"})";
  const Case cases[] = {
      {good.substr(0, 10), any, "header"},
      {badMagic, any, "magic"},
      {badVersion, any, "version"},
      {badFields, any, "fields"},
      {hugeCount, any, "count"},
      {good.substr(0, 24 + 12 * 10 - 1), any, "positions"},
      {good.substr(0, 24 + 12 * 10 + 5), any, "normals"},
      {good.substr(0, good.size() - 11), any, "rgb"},
      {good.substr(0, good.size() - 1), any, "classification"},
      {good + "xx", any, "trailing bytes"},
      {notFinite, any, "positions: point 4 is not finite"},
      {good, R"({"path": "points.bin", "count": 11})", "count"},
      {good, R"({"path": "points.bin", "bytes": 5})", "points.bytes"},
      {good, R"({"path": "missing.bin"})", "missing.bin"},
      {good, R"("points.bin")", "expected"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.expect);
    const auto [n, errors] = load(c.bytes, c.entry);
    EXPECT_EQ(n, 0u);
    ASSERT_EQ(errors.size(), 1u);
    EXPECT_NE(errors[0].find(c.expect), std::string::npos) << errors[0];
    EXPECT_NE(errors[0].find("points left out"), std::string::npos) << errors[0];
    if (c.entry == any)
      EXPECT_NE(errors[0].find("points.bin: " + c.expect), std::string::npos) << errors[0];  // the file, then the field
  }
  fs::remove_all(dir);
}

TEST(WebScene, RejectsBrokenFiles) {
  const fs::path dir = fs::temp_directory_path() / ("hv_web_scene_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "scene_web.json") << R"({"format": "histoview-web", "version": 1, "origin": [0, 0, 0],
    "meshes": [{"name": "terrain", "path": "terrain.bin", "vertices": 3, "triangles": 1}], "cameras": "cameras.json"})";
  std::ofstream(dir / "terrain.bin") << "short";
  std::ofstream(dir / "cameras.json") << R"({"cameras": []})";
  Diagnostics diag;
  const Scene s = readWebScene((dir / "scene_web.json").string(), {}, diag);
  EXPECT_TRUE(s.terrain.empty());
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("terrain.bin"), std::string::npos) << diag.errors[0];

  std::ofstream(dir / "bad.json") << R"({"format": "something else"})";
  EXPECT_THROW(readWebScene((dir / "bad.json").string(), {}, diag), InputError);
  fs::remove_all(dir);
}

// The traffic travels as traffic.csv (vehicle centres in the scene frame) and vehicles.json (the
// models as read): read back, the same vehicles at the same places, the same model triangles.
TEST(WebScene, TrafficRoundTrip) {
  const fs::path dir = fs::temp_directory_path() / ("hv_web_traffic_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  Diagnostics diag;
  TrajectoryBuilder b;
  b.add("bus_1", "bus", {0.0, {651000.25, 6862000.5}, 90.0});
  b.add("bus_1", "bus", {10.0, {651100.25, 6862000.5}, 90.0});
  b.add("car,2", "passenger", {5.0, {651010.0, 6862010.0}, 350.0});
  b.add("car,2", "passenger", {6.5, {651010.0, 6862020.0}, 10.0});
  auto traffic = std::make_shared<Trajectories>(b.finish("test", diag));
  auto models = std::make_shared<VehicleModels>();
  auto car = std::make_shared<VehicleModel>(boxWithWheelsModel());
  car->vertices.resize(6);
  car->vertices[4].paint = 1.0f;
  car->vertices[2].colour = {0.25f, 0.5f, 0.75f};
  car->source = "/somewhere/car.gltf";
  models->byClass[std::size_t(VehicleClass::Car)] = car;
  traffic->models = models;
  Scene scene;
  scene.origin = {651000.0, 6862000.0, 0.0};
  scene.traffic = traffic;
  writeWebScene(scene, {}, dir.string());
  ASSERT_TRUE(fs::exists(dir / kWebTrafficFile));
  ASSERT_TRUE(fs::exists(dir / kWebVehiclesFile));

  Diagnostics readDiag;
  const Scene back = readWebScene((dir / kWebSceneManifest).string(), {}, readDiag);
  EXPECT_TRUE(readDiag.errors.empty()) << readDiag.errors.front();
  ASSERT_TRUE(back.traffic);
  ASSERT_EQ(back.traffic->vehicles.size(), 2u);
  EXPECT_DOUBLE_EQ(back.traffic->tBegin, 0.0);
  EXPECT_DOUBLE_EQ(back.traffic->tEnd, 10.0);
  const Trajectory* bus = nullptr;
  for (const auto& v : back.traffic->vehicles)
    if (v.id == "bus_1") bus = &v;
  ASSERT_NE(bus, nullptr);
  EXPECT_EQ(bus->type, "bus");
  EXPECT_DOUBLE_EQ(bus->size.length, vehicleSizeOf("bus").length);
  const auto mid = sampleTrajectory(*bus, 5.0);
  ASSERT_TRUE(mid);
  EXPECT_NEAR(mid->xy.x, 651050.25, 1e-4);
  EXPECT_NEAR(mid->xy.y, 6862000.5, 1e-4);
  EXPECT_NEAR(mid->angleDeg, 90.0, 1e-6);
  bool renamed = false;  // a comma in an id would split the CSV's row
  for (const auto& v : back.traffic->vehicles) renamed |= v.id == "car_2";
  EXPECT_TRUE(renamed);
  ASSERT_TRUE(back.traffic->models);
  const VehicleModel& m = back.traffic->models->of(VehicleClass::Car);
  ASSERT_EQ(m.vertices.size(), 6u);
  EXPECT_EQ(m.vertices[4].paint, 1.0f);
  EXPECT_EQ(m.vertices[2].colour, glm::vec3(0.25f, 0.5f, 0.75f));
  EXPECT_EQ(m.vertices[1].local, car->vertices[1].local);
  EXPECT_EQ(m.vertices[1].normal, car->vertices[1].normal);
  EXPECT_EQ(&back.traffic->models->of(VehicleClass::Bus), &boxWithWheelsModel());  // no model: the box

  // A broken models file: reported by name, and the traffic left out.
  std::ofstream(dir / kWebVehiclesFile) << R"({"car": {"vertices": [1, 2, 3]}})";
  Diagnostics badDiag;
  const Scene bad = readWebScene((dir / kWebSceneManifest).string(), {}, badDiag);
  EXPECT_FALSE(bad.traffic);
  ASSERT_EQ(badDiag.errors.size(), 1u);
  EXPECT_NE(badDiag.errors[0].find("vehicles.json: car: vertices: 3 numbers"), std::string::npos) << badDiag.errors[0];
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hv::app
