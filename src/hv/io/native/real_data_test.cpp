// Loading real data that nobody here made (../shared/data, see its README): Delft's BGT
// footprints on an AHN3-derived DTM, and the Stereopolis street images with their cameras.
#include "hv/io/cameras_json.h"
#include "hv/io/native/footprints.h"
#include "hv/io/native/georef.h"
#include "hv/io/native/raster.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/scene_scale.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

namespace hv {
namespace {

TEST(RealData, DelftFootprintsBecomeClosedLod1BuildingsOnTheDtm) {
  const std::string dir = testing::dataset("delft");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no delft/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  Diagnostics diag;
  const Scene scene = loadScene(dir + "/scene.json", diag);
  EXPECT_TRUE(diag.ok());
  EXPECT_TRUE(diag.warnings.empty());
  EXPECT_EQ(scene.points.size(), 848942u);  // the lidar (counts and classes: hv/scene/chunks_test.cpp)
  EXPECT_EQ(scene.crs, "EPSG:28992");
  // 160 BGT footprints (README), all valid: every one is built.
  std::set<std::uint32_t> buildings(scene.buildings.triangleTags.begin(), scene.buildings.triangleTags.end());
  EXPECT_EQ(buildings.size(), 160u);
  EXPECT_GT(scene.buildings.signedVolume(), 0.0);
  // DTM: 265 x 230 cells of 1 m, z from -0.47 to 2.28 m NAP (README): the terrain mesh spans it.
  const Aabb t = scene.terrain.bounds();
  EXPECT_NEAR(t.hi.x - t.lo.x, 264.0, 1e-6);  // sample centres: 265 - 1 cells apart
  EXPECT_NEAR(t.hi.y - t.lo.y, 229.0, 1e-6);
  EXPECT_NEAR(t.lo.z, -0.47, 0.01);
  EXPECT_NEAR(t.hi.z, 2.28, 0.01);
  // Roofs: base (lowest DTM under the footprint) + height, so tops lie within the data's range
  // of heights (2.39-13.63 m) above the DTM's range.
  const Aabb b = scene.buildings.bounds();
  EXPECT_GT(b.hi.z, 13.63 - 0.5);
  EXPECT_LT(b.hi.z, 13.63 + 2.3);
  // The render origin defaults to the centre of the data, so render-frame floats stay small.
  EXPECT_LT(glm::length(glm::dvec2(scene.origin) - glm::dvec2(84940.0, 447527.0)), 50.0);
}

TEST(RealData, DelftAbsoluteBaseAndTopAttributes) {
  const std::string dir = testing::dataset("delft");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no delft/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  // The same footprints with 3dfier's absolute levels (z_base, z_top) instead of the DTM.
  const auto tmp = std::filesystem::temp_directory_path() / ("hv-delft-" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  const nlohmann::json scene = {
      {"crs", "EPSG:28992"},
      {"buildings", {{"path", dir + "/buildings.geojson"}, {"height", "height"}, {"base", "z_base"}, {"top", "z_top"}}}};
  std::ofstream(tmp / "scene.json") << scene.dump();
  Diagnostics diag;
  const Scene s = loadScene((tmp / "scene.json").string(), diag);
  EXPECT_TRUE(diag.ok());
  // Compare each building's roof with its z_top attribute, read independently from the GeoJSON.
  std::ifstream in(dir + "/buildings.geojson");
  const nlohmann::json fc = nlohmann::json::parse(in);
  std::vector<double> tops;
  for (const auto& f : fc["features"]) tops.push_back(f["properties"]["z_top"].get<double>());
  std::map<std::uint32_t, double> roof;
  for (size_t i = 0; i < s.buildings.triangles.size(); ++i) {
    const auto& tri = s.buildings.triangles[i];
    double& r = roof[s.buildings.triangleTags[i]];
    for (int k = 0; k < 3; ++k) r = std::max(r, s.buildings.positions[tri[k]].z);
  }
  ASSERT_EQ(roof.size(), tops.size());
  for (const auto& [tag, z] : roof) EXPECT_NEAR(z, tops[tag], 1e-6) << "building " << tag;
  std::filesystem::remove_all(tmp);
}

// Delft (EPSG:28992, Amersfoort / RD New) brought into UTM 31N (EPSG:32631, WGS 84): the DTM is
// warped by GDAL, the footprints go vertex by vertex through PROJ. Both must still meet: the
// terrain under each footprint's centroid, and each building's base (the lowest terrain under
// it), agree with the load in the data's own CRS.
TEST(RealData, DelftInUtm31KeepsItsFootprintsOnTheTerrain) {
  const std::string dir = testing::dataset("delft");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no delft/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  const auto t0 = std::chrono::steady_clock::now();
  const auto tmp = std::filesystem::temp_directory_path() / ("hv-delft-utm-" + std::to_string(::getpid()));
  std::filesystem::create_directories(tmp);
  Scene scenes[2];
  const char* crs[2] = {"EPSG:28992", "EPSG:32631"};
  for (int k = 0; k < 2; ++k) {  // terrain and buildings only: the lidar is not what is checked
    const nlohmann::json doc = {{"crs", crs[k]},
                                {"terrain", {{"path", dir + "/dtm.tif"}}},
                                {"buildings", {{"path", dir + "/buildings.geojson"}, {"height", "height"}}}};
    std::ofstream(tmp / "scene.json") << doc.dump();
    Diagnostics diag;
    scenes[k] = loadScene((tmp / "scene.json").string(), diag);
    EXPECT_TRUE(diag.ok()) << crs[k];
    for (const auto& w : diag.warnings) std::printf("  %s: warning: %s\n", crs[k], w.c_str());
  }
  std::filesystem::remove_all(tmp);
  ASSERT_EQ(scenes[1].sourceCrs.size(), 2u);
  EXPECT_EQ(scenes[1].sourceCrs[0].crs, "EPSG:28992");  // the DTM's own, read by GDAL
  EXPECT_EQ(scenes[1].sourceCrs[1].crs, "EPSG:28992");  // the GeoJSON's `crs` member
  // UTM 31N around Delft (4.36 E, 52.01 N): easting ~ 594 km, northing ~ 5763 km.
  EXPECT_NEAR(scenes[1].terrain.bounds().center().x, 594500.0, 2000.0);
  EXPECT_NEAR(scenes[1].terrain.bounds().center().y, 5763000.0, 2000.0);

  // Building bases: the lowest DTM sample or vertex under the footprint, per building tag.
  std::map<std::uint32_t, double> base[2];
  for (int k = 0; k < 2; ++k) {
    const Mesh& b = scenes[k].buildings;
    for (size_t i = 0; i < b.triangles.size(); ++i)
      for (int v = 0; v < 3; ++v) {
        auto [it, fresh] = base[k].try_emplace(b.triangleTags[i], b.positions[b.triangles[i][v]].z);
        it->second = std::min(it->second, b.positions[b.triangles[i][v]].z);
      }
  }
  ASSERT_EQ(base[0].size(), 160u);
  ASSERT_EQ(base[1].size(), 160u);
  double worstBase = 0.0;
  for (const auto& [tag, z] : base[0]) worstBase = std::max(worstBase, std::abs(base[1].at(tag) - z));

  // The terrain under each footprint's centroid (vertex mean), in both frames.
  Diagnostics diag;
  const Heightfield dtm = readHeightfield(dir + "/dtm.tif");
  const GeoreferencedHeightfield warped =
      readHeightfield(dir + "/dtm.tif", {"", "EPSG:32631", "scene.json: terrain.crs"}, diag);
  const auto native = readFootprints(dir + "/buildings.geojson", FootprintFields{}, diag);
  const SourceGeoref intoUtm{"", "EPSG:32631", "scene.json: buildings.crs"};
  const auto moved = readFootprints(dir + "/buildings.geojson", FootprintFields{}, intoUtm, diag);
  ASSERT_EQ(native.size(), moved.footprints.size());
  auto centroid = [](const Footprint& f) {
    glm::dvec2 c(0.0);
    for (const glm::dvec2& p : f.rings[0]) c += p / double(f.rings[0].size());
    return c;
  };
  double worstCentroid = 0.0, sumCentroid = 0.0;
  int compared = 0;
  for (size_t k = 0; k < native.size(); ++k) {
    const glm::dvec2 a = centroid(native[k]), b = centroid(moved.footprints[k]);
    const auto za = dtm.elevation(a.x, a.y), zb = warped.field.elevation(b.x, b.y);
    if (!za) continue;  // a centroid outside the DTM
    ASSERT_TRUE(zb) << native[k].id;
    worstCentroid = std::max(worstCentroid, std::abs(*za - *zb));
    sumCentroid += std::abs(*za - *zb);
    ++compared;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("  DTM %dx%d cells of 1 m -> %dx%d cells of %.3f m; %d centroids: terrain differs by %.3f m at "
              "worst, %.3f m on average; building bases by %.3f m at worst; %.1f s\n",
              dtm.cols, dtm.rows, warped.field.cols, warped.field.rows, std::abs(warped.field.cellX), compared,
              worstCentroid, sumCentroid / std::max(compared, 1), worstBase, seconds);
  EXPECT_GT(compared, 150);
  EXPECT_LT(worstCentroid, 0.5);
  EXPECT_LT(worstBase, 0.5);
}

TEST(RealData, StereopolisCamerasLoadWithTheirImages) {
  const std::string dir = testing::dataset("paris-stereopolis");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no paris-stereopolis/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  Diagnostics diag;
  const auto photos = readCameraFile(dir + "/cameras.json", CameraFileOptions{}, diag);
  EXPECT_TRUE(diag.ok());
  ASSERT_EQ(photos.size(), 30u);  // 6 panoramas x cameras 300-304 (README)
  int distorted = 0;
  for (const auto& p : photos) {
    EXPECT_EQ(p.camera.width, 2048);
    EXPECT_EQ(p.camera.height, 2048);
    distorted += p.camera.distortion.has_value();
    // Lambert-93 around Paris, street level (35-42 m, README).
    EXPECT_NEAR(p.camera.center.x, 651000.0, 5000.0);
    EXPECT_NEAR(p.camera.center.z, 40.0, 10.0);
    EXPECT_TRUE(std::filesystem::is_regular_file(p.imagePath)) << p.imagePath;
  }
  EXPECT_EQ(distorted, 30);
}

// The scale and the up axis on the real scenes (../shared/data/README.md): Sceaux's SfM frame has up
// about -z (the README's mean camera up (0.03, 0.18, -0.98)), its cameras ~1.1 units apart facing a
// façade ~8 units wide; the Stereopolis panoramas are a kilometre apart with no geometry, their
// rig cameras 0.12 m apart (the old spacing).
TEST(RealData, SceauxUpAndScaleComeFromTheCamerasAndTheMesh) {
  const std::string dir = testing::dataset("sceaux");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no sceaux/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  Diagnostics diag;
  const Scene scene = loadScene(dir + "/scene.json", diag);
  EXPECT_NEAR(glm::length(scene.up - glm::normalize(glm::dvec3(0.03, 0.18, -0.98))), 0.0, 0.01);
  const SceneScale s = sceneScale(scene);
  EXPECT_TRUE(s.outlying.empty());
  EXPECT_NE(s.source.find("camera-to-surface"), std::string::npos) << s.source;
  EXPECT_GT(s.scale, 2.0);   // more than the cameras' spacing: they stand back from the façade
  EXPECT_LT(s.scale, 20.0);  // and within twice the mesh's extent
}

TEST(RealData, StereopolisScaleIsNotTheRigSpacing) {
  const std::string dir = testing::dataset("paris-stereopolis");
  if (dir.empty())
    HV_SKIP_WITHOUT_DATA(std::string("no paris-stereopolis/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
  Diagnostics diag;
  const Scene scene = loadScene(dir + "/scene.json", diag);
  ASSERT_EQ(scene.photos.size(), 30u);
  EXPECT_LT(scene.cameraSpacing(), 0.2);
  const SceneScale s = sceneScale(scene);
  EXPECT_GT(s.spacing, 500.0);  // panoramas across Paris
  EXPECT_EQ(s.scale, kMetricSpacingScale[1]);
  EXPECT_TRUE(s.outlying.empty());
}

}  // namespace
}  // namespace hv
