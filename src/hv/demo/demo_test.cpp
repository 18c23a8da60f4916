#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>

#include "hv/demo/demo_city.h"
#include "hv/demo/vehicle_models.h"
#include "hv/io/native/las_reader.h"
#include "hv/io/native/ply_points.h"
#include "hv/io/native/raster.h"
#include "hv/io/native/scene_loader.h"
#include "hv/io/native/sumo_fcd.h"
#include "hv/scene/native/lod1.h"
#include "hv/traffic/vehicle_model.h"

namespace hv::demo {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

DemoOptions smallOptions() {
  DemoOptions o;
  o.buildings = 8;
  o.photos = 6;
  o.views = 2;
  o.samplesPerAxis = 1;  // one ray through each pixel centre: pixels are shade() values, rounded
  return o;
}

fs::path freshDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("hv_demo_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

json readJson(const fs::path& p) {
  std::ifstream f(p);
  EXPECT_TRUE(f.good()) << p;
  return json::parse(f);
}

std::string readBytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// A camera rebuilt from cameras.json by hand (schema), not through the generator's objects.
Camera cameraFromJson(const json& j) {
  Camera c;
  c.id = j.at("id").get<std::string>();
  c.width = j.at("width").get<int>();
  c.height = j.at("height").get<int>();
  c.center = {j["center"][0].get<double>(), j["center"][1].get<double>(), j["center"][2].get<double>()};
  std::vector<double> r = j.at("rotation").get<std::vector<double>>();
  c.camFromWorld = mat3FromRowMajor(r.data());
  c.focal = {j["focal"][0].get<double>(), j["focal"][1].get<double>()};
  c.principal = {j["principal"][0].get<double>(), j["principal"][1].get<double>()};
  c.skew = j.at("skew").get<double>();
  if (j.contains("distortion")) {
    const json& d = j["distortion"];
    LensDistortion rd;
    rd.center = {d["center"][0].get<double>(), d["center"][1].get<double>()};
    rd.c3 = d.at("c3").get<double>();
    rd.c5 = d.at("c5").get<double>();
    rd.c7 = d.at("c7").get<double>();
    rd.r2max = d.at("r2max").get<double>();
    c.distortion = rd;
  }
  return c;
}

// Pinhole ray through an ideal pixel, from the camera conventions (camera.h) written out:
// d_cam = ((x - cx) / fx, (y - cy) / fy, 1) for zero skew, d_world = R^T d_cam.
glm::dvec3 pinholeRay(const Camera& c, glm::dvec2 px) {
  const glm::dvec3 dCam((px.x - c.principal.x) / c.focal.x, (px.y - c.principal.y) / c.focal.y, 1.0);
  return glm::normalize(glm::transpose(c.camFromWorld) * dCam);
}

bool near8(const std::uint8_t* px, glm::dvec3 expected) {
  for (int k = 0; k < 3; ++k)
    if (std::abs(double(px[k]) - expected[k] * 255.0) > 1.0) return false;  // within 1/255
  return true;
}

class DemoCity : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(freshDir("a"));
    summary_ = new DemoSummary(generate(smallOptions(), dir_->string()));
    world_ = new World(buildWorld(smallOptions()));
    caster_ = new RayCaster(world_->truth.mesh);
    plan_ = new ShotPlan(planShots(*world_, *caster_));
  }
  static void TearDownTestSuite() {
    delete plan_;
    delete caster_;
    delete world_;
    delete summary_;
    fs::remove_all(*dir_);
    delete dir_;
  }
  static json camerasJson() { return readJson(*dir_ / "cameras.json")["cameras"]; }

  static fs::path* dir_;
  static DemoSummary* summary_;
  static World* world_;
  static RayCaster* caster_;
  static ShotPlan* plan_;
};
fs::path* DemoCity::dir_ = nullptr;
DemoSummary* DemoCity::summary_ = nullptr;
World* DemoCity::world_ = nullptr;
RayCaster* DemoCity::caster_ = nullptr;
ShotPlan* DemoCity::plan_ = nullptr;

TEST_F(DemoCity, FilesExistAndParse) {
  EXPECT_EQ(summary_->photos, 6);
  EXPECT_EQ(summary_->views, 2);
  EXPECT_EQ(summary_->buildings, 8);
  const json scene = readJson(summary_->scenePath);
  EXPECT_EQ(scene["crs"], "EPSG:2154");
  EXPECT_EQ(scene["terrain"]["path"], "dtm.tif");
  EXPECT_EQ(scene["buildings"]["path"], "buildings.geojson");
  EXPECT_EQ(scene["buildings"]["height"], "height");
  EXPECT_EQ(scene["cameras"]["path"], "cameras.json");
  EXPECT_EQ(scene["points"]["path"], "points.las");

  const Heightfield dtm = readHeightfield((*dir_ / "dtm.tif").string());
  ASSERT_FALSE(dtm.empty());
  EXPECT_DOUBLE_EQ(dtm.cellX, 2.0);
  const auto [lo, hi] = std::minmax_element(dtm.z.begin(), dtm.z.end());
  EXPECT_GT(*hi - *lo, 2.0) << "terrain should have a few metres of relief";
  EXPECT_GT(*lo, 25.0);
  EXPECT_LT(*hi, 55.0);

  const json gj = readJson(*dir_ / "buildings.geojson");
  EXPECT_EQ(gj["type"], "FeatureCollection");
  ASSERT_EQ(gj["features"].size(), 8u);
  for (const json& f : gj["features"]) {
    const double h = f["properties"]["height"].get<double>();
    EXPECT_GE(h, 8.0);
    EXPECT_LE(h, 25.0);
    EXPECT_EQ(f["geometry"]["type"], "Polygon");
    for (const json& ring : f["geometry"]["coordinates"]) {
      ASSERT_GE(ring.size(), 5u);
      EXPECT_EQ(ring.front(), ring.back()) << "GeoJSON rings are closed";
      for (const json& p : ring) {
        EXPECT_NEAR(p[0].get<double>(), 651000.0, 1000.0);
        EXPECT_NEAR(p[1].get<double>(), 6862000.0, 1000.0);
      }
    }
  }

  const json cams = camerasJson();
  ASSERT_EQ(cams.size(), 6u);
  int masks = 0, distorted = 0;
  for (const json& j : cams) {
    for (const char* key :
         {"id", "image", "width", "height", "center", "rotation", "focal", "principal", "skew", "date"})
      EXPECT_TRUE(j.contains(key)) << key;
    EXPECT_EQ(j["rotation"].size(), 9u);
    const Camera c = cameraFromJson(j);
    const glm::dmat3 rrt = c.camFromWorld * glm::transpose(c.camFromWorld);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) EXPECT_NEAR(rrt[a][b], a == b ? 1.0 : 0.0, 1e-12);
    EXPECT_NEAR(glm::determinant(c.camFromWorld), 1.0, 1e-12);
    const Image8 img = readImage((*dir_ / j["image"].get<std::string>()).string());
    EXPECT_EQ(img.width, c.width);
    EXPECT_EQ(img.height, c.height);
    const int year = std::stoi(j["date"].get<std::string>().substr(0, 4));
    EXPECT_GE(year, 1890);
    EXPECT_LE(year, 1960);
    if (j.contains("mask")) {
      ++masks;
      const Image8 m = readImage((*dir_ / j["mask"].get<std::string>()).string());
      EXPECT_EQ(m.channels, 1);
      EXPECT_EQ(m.width, c.width);
    }
    if (j.contains("distortion")) {
      ++distorted;
      EXPECT_EQ(j["distortion"]["type"], "radial");
    }
  }
  EXPECT_GE(masks, 1);
  EXPECT_GE(distorted, 1);

  const json views = readJson(summary_->viewsPath)["cameras"];
  ASSERT_EQ(views.size(), 2u);
  for (const json& j : views) {
    EXPECT_FALSE(j.contains("image"));
    EXPECT_FALSE(j.contains("distortion"));
    const std::string id = j["id"].get<std::string>();
    const Image8 truth = readImage((fs::path(summary_->truthDir) / (id + ".png")).string());
    const Image8 cov = readImage((fs::path(summary_->truthDir) / (id + ".coverage.png")).string());
    EXPECT_EQ(truth.width, 320);
    EXPECT_EQ(truth.height, 240);
    ASSERT_EQ(cov.channels, 1);
    size_t covered = 0;
    for (std::uint8_t v : cov.data) {
      EXPECT_TRUE(v == 0 || v == 255);
      covered += v == 255;
    }
    EXPECT_GT(covered, cov.data.size() / 2) << id << " should mostly see the city";
  }
}

TEST(DemoWorld, DefaultCityHasCourtyardConcaveFootprintsAndLod1Roofs) {
  const World w = buildWorld(DemoOptions{});
  ASSERT_EQ(w.footprints.size(), 40u);
  int holes = 0, concave = 0;
  for (const Footprint& f : w.footprints) {
    holes += f.rings.size() >= 2;
    concave += f.rings[0].size() > 4;
  }
  EXPECT_GE(holes, 1) << "at least one courtyard";
  EXPECT_GE(concave, 20);
  // Ground-truth roofs lie at the LOD1 roof height the renderer builds from the same inputs.
  Diagnostics diag;
  const Mesh lod1 = buildLod1(w.footprints, &w.dtm, diag);
  ASSERT_TRUE(diag.ok());
  const RayCaster truth(w.truth.mesh), model(lod1);
  for (const Building& b : w.buildings) {
    // A point just inside the first outer edge, off its middle.
    const glm::dvec2 a = b.rings[0][0], c = b.rings[0][1];
    const glm::dvec2 d = glm::normalize(c - a), inward(-d.y, d.x);  // outer ring is counter-clockwise
    const glm::dvec2 p = 0.5 * (a + c) + 0.5 * inward;
    const auto ht = truth.intersect({p, 200.0}, {0, 0, -1});
    const auto hm = model.intersect({p, 200.0}, {0, 0, -1});
    ASSERT_TRUE(ht && hm) << b.id;
    EXPECT_NEAR(ht->position.z, hm->position.z, 1e-3) << b.id;
    EXPECT_EQ(Material(w.truth.mesh.triangleTags[ht->triangle]) == Material::RoofGravel ||
                  Material(w.truth.mesh.triangleTags[ht->triangle]) == Material::RoofTiles,
              true);
  }
  // Transients are in their own layers only.
  for (std::uint32_t t : w.truth.mesh.triangleTags) {
    EXPECT_NE(Material(t), Material::TreeCrown);
    EXPECT_NE(Material(t), Material::CarBody);
  }
  EXPECT_FALSE(w.trees.mesh.empty());
  EXPECT_FALSE(w.parkedCars.mesh.empty());
}

TEST(DemoWorld, DefaultPlanHasTheRequiredVariety) {
  const World w = buildWorld(DemoOptions{});
  const RayCaster caster(w.truth.mesh);
  const ShotPlan plan = planShots(w, caster);
  ASSERT_EQ(plan.photos.size(), 36u);
  ASSERT_EQ(plan.views.size(), 8u);
  int distorted = 0, masked = 0, cast = 0, elevated = 0, cars = 0;
  std::set<std::pair<int, int>> sizes;
  for (const Shot& s : plan.photos) {
    distorted += bool(s.camera.distortion);
    masked += s.masked;
    cast += s.cast != EraCast::None;
    elevated += s.elevated;
    cars += !s.cars.mesh.empty();
    sizes.insert({s.camera.width, s.camera.height});
    const double above = s.camera.center.z - w.groundZ(s.camera.center.x, s.camera.center.y);
    if (s.elevated) {
      EXPECT_GE(above, 15.0);
      EXPECT_LE(above, 40.0);
    } else {
      EXPECT_GE(above, 1.6);
      EXPECT_LE(above, 2.0);
    }
    EXPECT_FALSE(w.insideBuilding(s.camera.center.x, s.camera.center.y));
    if (s.masked) EXPECT_FALSE(s.cars.mesh.empty());
  }
  EXPECT_GE(distorted, 3);
  EXPECT_GE(masked, 3);
  EXPECT_GE(cast, 4);
  EXPECT_GE(elevated, 3);
  EXPECT_GE(cars, 6);
  EXPECT_GE(sizes.size(), 3u);
  for (const Shot& v : plan.views) {
    EXPECT_FALSE(v.camera.distortion);
    EXPECT_TRUE(v.cars.mesh.empty());
    EXPECT_EQ(v.camera.width, 320);
    EXPECT_EQ(v.camera.height, 240);
    // Between photographs: some photograph within 15 m.
    double nearest = 1e30;
    for (const Shot& s : plan.photos)
      nearest = std::min(nearest, glm::length(s.camera.center - v.camera.center));
    EXPECT_LT(nearest, 15.0);
  }
}

TEST_F(DemoCity, Deterministic) {
  const fs::path b = freshDir("b");
  generate(smallOptions(), b.string());
  EXPECT_EQ(readBytes(*dir_ / "cameras.json"), readBytes(b / "cameras.json"));
  EXPECT_EQ(readBytes(*dir_ / "buildings.geojson"), readBytes(b / "buildings.geojson"));
  EXPECT_EQ(readBytes(*dir_ / "images" / "p0001.png"), readBytes(b / "images" / "p0001.png"));
  EXPECT_EQ(readBytes(*dir_ / "truth" / "v001.png"), readBytes(b / "truth" / "v001.png"));
  EXPECT_EQ(readBytes(*dir_ / "points.las"), readBytes(b / "points.las"));
  EXPECT_EQ(readBytes(*dir_ / "points.ply"), readBytes(b / "points.ply"));
  EXPECT_FALSE(readBytes(b / "images" / "p0001.png").empty());
  // SUMO's output carries the date it was written: the trajectories are what must agree.
  Diagnostics diag;
  const Trajectories ta = readSumoFcd((*dir_ / "fcd.xml").string(), diag),
                     tb = readSumoFcd((b / "fcd.xml").string(), diag);
  ASSERT_EQ(ta.vehicles.size(), tb.vehicles.size());
  for (size_t i = 0; i < ta.vehicles.size(); ++i) {
    ASSERT_EQ(ta.vehicles[i].samples.size(), tb.vehicles[i].samples.size());
    EXPECT_EQ(ta.vehicles[i].samples.back().xy, tb.vehicles[i].samples.back().xy);
  }
  fs::remove_all(b);
}

// The traffic: SUMO ran on the city's street grid (netconvert, randomTrips.py, sumo), scene.json
// names its FCD, and the trajectories read back put the vehicles on the carriageway, in the
// right-hand lane, heading along the street.
TEST_F(DemoCity, TrafficSimulatedOnTheStreetsAndReadBack) {
  ASSERT_TRUE(summary_->traffic.ok) << summary_->traffic.message;
  std::ifstream sceneFile(*dir_ / "scene.json");
  const nlohmann::json scene = nlohmann::json::parse(sceneFile);
  ASSERT_TRUE(scene.contains("traffic"));
  EXPECT_EQ(scene["traffic"]["fcd"], "fcd.xml");
  // The vehicles' models made by code, named by scene.json and loaded with the scene, no error.
  for (const VehicleClass c : generatedVehicleClasses()) {
    const std::string name = vehicleClassName(c);
    EXPECT_EQ(scene["traffic"]["models"][name], "vehicles/" + name + ".gltf");
  }
  {
    Diagnostics loaded;
    const Scene s = loadScene((*dir_ / "scene.json").string(), loaded);
    ASSERT_NE(s.traffic, nullptr);
    ASSERT_NE(s.traffic->models, nullptr);
    EXPECT_TRUE(loaded.errors.empty()) << loaded.errors.front();
    EXPECT_EQ(s.traffic->models->of(VehicleClass::Bus).source, (*dir_ / "vehicles" / "bus.gltf").string());
  }
  const glm::dvec2 offset(scene["traffic"]["offset"][0].get<double>(), scene["traffic"]["offset"][1].get<double>());
  Diagnostics diag;
  const Trajectories t = readSumoFcd((*dir_ / "fcd.xml").string(), diag);
  EXPECT_TRUE(diag.warnings.empty()) << diag.warnings.front();
  EXPECT_GE(t.vehicles.size(), 10u);
  EXPECT_GT(t.tEnd, 20.0);
  std::size_t samples = 0, onRoad = 0, alongStreet = 0, rightLane = 0;
  for (const Trajectory& v : t.vehicles)
    for (const TrajectorySample& s : v.samples) {
      const glm::dvec2 p = s.xy + offset;
      ++samples;
      if (world_->onRoad(p.x, p.y)) ++onRoad;
      // Along a street: the heading a multiple of 90 degrees (the grid), and then the vehicle on
      // the right of the street's centre line.
      const double a = std::fmod(s.angleDeg + 360.0, 90.0);
      if (std::min(a, 90.0 - a) > 1.0) continue;
      ++alongStreet;
      const glm::dvec2 f = forwardFromSumoAngle(s.angleDeg), right(f.y, -f.x);
      for (const Street& st : world_->streets) {
        const double offCentre = st.alongX ? p.y - st.centre : p.x - st.centre;
        if (std::abs(offCentre) > 0.5 * world_->roadWidth) continue;
        if ((st.alongX ? std::abs(f.x) : std::abs(f.y)) < 0.9) continue;  // crossing it, not along it
        const double side = st.alongX ? offCentre * right.y : offCentre * right.x;
        if (side > 0.5) ++rightLane;
        break;
      }
    }
  ASSERT_GT(samples, 200u);
  EXPECT_GT(double(onRoad) / double(samples), 0.98);
  EXPECT_GT(double(rightLane) / double(alongStreet), 0.95);
}

// The lidar scan: the LAS and PLY files hold the same points; every class is there in plausible
// shares; trees and parked cars are scanned where they stand; each point lies on the surface its
// normal belongs to.
TEST_F(DemoCity, LidarScanHasPlausibleClassesOnTheSurfaces) {
  const PointCloud las = readLas((*dir_ / "points.las").string());
  const PointCloud ply = readPlyPoints((*dir_ / "points.ply").string());
  ASSERT_EQ(las.size(), ply.size());
  ASSERT_GT(las.size(), 10000u);
  EXPECT_EQ(las.crs, "EPSG:2154");
  EXPECT_EQ(ply.crs, "EPSG:2154");
  ASSERT_TRUE(ply.fields().normals && ply.fields().rgb && las.fields().rgb);
  for (std::size_t i = 0; i < las.size(); i += 97) {
    EXPECT_LT(glm::length(las.positions[i] - ply.positions[i]), 1e-3);  // LAS quantises to mm
    EXPECT_EQ(las.rgb[i], ply.rgb[i]);
    EXPECT_EQ(las.classification[i], ply.classification[i]);
  }
  const auto h = las.classHistogram();
  const double n = double(las.size());
  std::printf("[ lidar ] %zu points: ground %zu, building %zu, vegetation %zu, cars %zu\n", las.size(), h[2], h[6],
              h[5], h[1]);
  EXPECT_EQ(h[1] + h[2] + h[5] + h[6], las.size()) << "only the classes of asprsClass()";
  EXPECT_GT(h[2] / n, 0.2);
  EXPECT_GT(h[6] / n, 0.1);
  EXPECT_GT(h[5], 500u) << "trees are scanned";
  EXPECT_GT(h[1], 100u) << "parked cars are scanned";
  const Aabb trees = world_->trees.mesh.bounds(), cars = world_->parkedCars.mesh.bounds();
  Layer scanned = world_->truth;
  scanned.append(world_->trees);
  scanned.append(world_->parkedCars);
  const RayCaster caster(scanned.mesh);
  // A point on a triangle's edge (a car's or a crown's silhouette) may be missed by the float
  // ray cast back: allow 1 % of the sample.
  std::size_t sampled = 0, onSurface = 0;
  for (std::size_t i = 0; i < ply.size(); i += 37) {
    const glm::dvec3 p = ply.positions[i];
    if (ply.classification[i] == 5) EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, trees.lo - 1e-6)));
    if (ply.classification[i] == 1) EXPECT_TRUE(glm::all(glm::lessThanEqual(p, cars.hi + 1e-6)));
    const glm::dvec3 normal(ply.normals[i]);
    EXPECT_NEAR(glm::length(normal), 1.0, 1e-5);
    const auto back = caster.intersect(p + 0.05 * normal, -normal, 0.0, 0.1);
    ++sampled;
    onSurface += back && std::abs(back->t - 0.05) < 1e-3;
  }
  EXPECT_GT(double(onSurface), 0.99 * double(sampled)) << onSurface << " of " << sampled << " on their surface";
}

TEST_F(DemoCity, PhotoPixelsAreTheGroundTruthShade) {
  // Photograph 1 of the plan has no cars, no cast and no distortion.
  ASSERT_TRUE(plan_->photos[0].cars.mesh.empty());
  ASSERT_EQ(plan_->photos[0].cast, EraCast::None);
  const json j = camerasJson()[0];
  ASSERT_FALSE(j.contains("distortion"));
  const Camera cam = cameraFromJson(j);
  const Image8 img = readImage((*dir_ / j["image"].get<std::string>()).string(), 3);
  const glm::dvec3 sky = world_->options.city.skyColor;
  int checked = 0, hits = 0, bad = 0;
  for (int y = 0; y < cam.height; y += 3)
    for (int x = 0; x < cam.width; x += 3) {
      const auto hit = caster_->intersect(cam.center, pinholeRay(cam, {x + 0.5, y + 0.5}));
      const glm::dvec3 expected = hit ? shade(*world_, *hit) : sky;
      ++checked;
      hits += bool(hit);
      bad += !near8(img.px(x, y), expected);
    }
  EXPECT_GT(hits, checked / 2);
  // Tolerance: the generator builds the same ray through Camera::rayDirection (K^-1 from a matrix
  // inverse), which differs from this one by ~1e-16; only a ray grazing an edge could change its
  // hit. Allow 0.2 % such pixels.
  EXPECT_LE(bad, checked / 500) << bad << " of " << checked << " pixels differ from shade()";
}

TEST_F(DemoCity, TreesAppearInNoPhotograph) {
  const RayCaster trees(world_->trees.mesh);
  for (std::uint32_t t : world_->trees.mesh.triangleTags)
    EXPECT_TRUE(Material(t) == Material::TreeTrunk || Material(t) == Material::TreeCrown);
  const json cams = camerasJson();
  int treeInFront = 0, bad = 0;
  for (size_t k = 0; k < cams.size(); ++k) {
    const Shot& shot = plan_->photos[k];
    if (!shot.cars.mesh.empty()) continue;  // cars may cover the place a tree would be
    const Camera cam = cameraFromJson(cams[k]);
    const Image8 img = readImage((*dir_ / cams[k]["image"].get<std::string>()).string(), 3);
    for (int y = 0; y < cam.height; y += 2)
      for (int x = 0; x < cam.width; x += 2) {
        const auto dir = sampleRay(cam, {x + 0.5, y + 0.5});
        ASSERT_TRUE(dir);
        const auto tree = trees.intersect(cam.center, *dir);
        const auto hit = caster_->intersect(cam.center, *dir);
        if (!tree || (hit && hit->t < tree->t)) continue;
        ++treeInFront;  // a tree stands in front of whatever this pixel shows
        const glm::dvec3 expected =
            applyCast(shot.cast, hit ? shade(*world_, *hit) : world_->options.city.skyColor);
        bad += !near8(img.px(x, y), expected);
      }
  }
  EXPECT_GT(treeInFront, 50) << "the test needs photographs whose line of sight crosses trees";
  EXPECT_LE(bad, treeInFront / 100) << "pixels behind trees must show what is behind them";
}

TEST_F(DemoCity, MaskIsZeroExactlyAroundCarPixels) {
  const json cams = camerasJson();
  int maskedPhotos = 0;
  for (size_t k = 0; k < cams.size(); ++k) {
    if (!cams[k].contains("mask")) continue;
    ++maskedPhotos;
    const Shot& shot = plan_->photos[k];
    ASSERT_TRUE(shot.masked);
    ASSERT_FALSE(shot.cars.mesh.empty());
    const Camera cam = cameraFromJson(cams[k]);
    const Image8 mask = readImage((*dir_ / cams[k]["mask"].get<std::string>()).string(), 1);
    const RayCaster cars(shot.cars.mesh);
    std::vector<int> car(size_t(cam.width) * cam.height, 0);
    int carPixels = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        const auto dir = sampleRay(cam, {x + 0.5, y + 0.5});
        const auto c = cars.intersect(cam.center, *dir);
        const auto t = caster_->intersect(cam.center, *dir);
        car[size_t(y) * cam.width + x] = c && (!t || c->t < t->t);
        carPixels += car[size_t(y) * cam.width + x];
      }
    EXPECT_GT(carPixels, 10) << cam.id << ": its cars should be visible";
    int zeros = 0;
    for (int y = 0; y < cam.height; ++y)
      for (int x = 0; x < cam.width; ++x) {
        bool nearCar = false;  // a car pixel within 2 px (Chebyshev), the documented dilation
        for (int dy = -2; dy <= 2; ++dy)
          for (int dx = -2; dx <= 2; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx >= 0 && yy >= 0 && xx < cam.width && yy < cam.height && car[size_t(yy) * cam.width + xx])
              nearCar = true;
          }
        const int m = mask.at(x, y, 0);
        ASSERT_TRUE(m == 0 || m == 255);
        EXPECT_EQ(m == 0, nearCar) << cam.id << " pixel " << x << "," << y;
        zeros += m == 0;
      }
    EXPECT_GT(zeros, carPixels);
  }
  EXPECT_GE(maskedPhotos, 1);
}

TEST_F(DemoCity, DistortedPhotosAreRenderedThroughUndistort) {
  const json cams = camerasJson();
  int distortedPhotos = 0;
  for (size_t k = 0; k < cams.size(); ++k) {
    if (!cams[k].contains("distortion")) continue;
    ++distortedPhotos;
    const Shot& shot = plan_->photos[k];
    const Camera cam = cameraFromJson(cams[k]);
    const LensDistortion& d = *cam.distortion;
    // The distortion is visible: several pixels at the far corner, and invertible everywhere.
    double cornerShift = 0.0;
    for (glm::dvec2 corner : {glm::dvec2(0, 0), glm::dvec2(cam.width, 0), glm::dvec2(0, cam.height),
                              glm::dvec2(cam.width, cam.height)}) {
      const auto ideal = cam.undistort(corner);
      ASSERT_TRUE(ideal) << cam.id;
      cornerShift = std::max(cornerShift, glm::length(*ideal - corner));
    }
    EXPECT_GE(cornerShift, 5.0);
    EXPECT_LE(cornerShift, 20.0);
    const Image8 img = readImage((*dir_ / cams[k]["image"].get<std::string>()).string(), 3);
    int checked = 0, bad = 0, naiveDiffers = 0;
    for (int y = 0; y < cam.height; y += 3)
      for (int x = 0; x < cam.width; x += 3) {
        const glm::dvec2 pd(x + 0.5, y + 0.5);
        const auto dir = sampleRay(cam, pd);
        ASSERT_TRUE(dir);
        const auto hit = caster_->intersect(cam.center, *dir);
        if (!hit) continue;
        // The hit point projects (pinhole, then the file's polynomial) back onto the pixel centre.
        const Projection pr = cam.project(hit->position);
        ASSERT_TRUE(pr.inImage);
        EXPECT_NEAR(pr.pxDistorted.x, pd.x, 1e-6);
        EXPECT_NEAR(pr.pxDistorted.y, pd.y, 1e-6);
        // Independently: p_d = p + r (c3 r^2 + c5 r^4 + c7 r^6) of the ideal projection.
        const glm::dvec2 r = pr.pxIdeal - d.center;
        const double r2 = glm::dot(r, r);
        const glm::dvec2 again = pr.pxIdeal + r * (d.c3 * r2 + d.c5 * r2 * r2 + d.c7 * r2 * r2 * r2);
        EXPECT_NEAR(again.x, pd.x, 1e-6);
        EXPECT_NEAR(again.y, pd.y, 1e-6);
        ++checked;
        const glm::dvec3 expected = applyCast(shot.cast, shade(*world_, *hit));
        bad += !near8(img.px(x, y), expected);
        const auto naive = caster_->intersect(cam.center, pinholeRay(cam, pd));
        if (!naive || !near8(img.px(x, y), applyCast(shot.cast, shade(*world_, *naive)))) ++naiveDiffers;
      }
    EXPECT_GT(checked, 100);
    EXPECT_LE(bad, checked / 500 + 1) << cam.id;
    EXPECT_GT(naiveDiffers, checked / 20) << cam.id << ": without the warp the image would differ";
  }
  EXPECT_GE(distortedPhotos, 1);
}

}  // namespace
}  // namespace hv::demo
