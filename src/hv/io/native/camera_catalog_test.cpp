// The camera catalog against a real PostgreSQL 15 + PostGIS server, started for these tests in a
// private cluster (hv/testing/catalog_server.h, tools/catalog.sh) and stopped afterwards.
#include "hv/io/native/camera_catalog.h"

#include "hv/ibr/selection.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/colmap_cameras.h"
#include "hv/io/native/itowns_cameras.h"
#include "hv/io/native/scene_loader.h"
#include "hv/testing/awkward_photos.h"
#include "hv/testing/catalog_server.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

namespace hv {
namespace {

namespace fs = std::filesystem;

class CameraCatalogTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    if (!testing::CatalogServer::available()) return;
    server_ = std::make_unique<testing::CatalogServer>(HV_SOURCE_DIR);
  }
  static void TearDownTestSuite() { server_.reset(); }

  void SetUp() override {
    // PostgreSQL is a dependency of the tests (tools/install-deps.sh): without it they fail.
    if (!server_)
      FAIL() << "PostgreSQL 15 is not installed (postgresql-15, postgresql-15-postgis-3: bash tools/install-deps.sh)";
    ASSERT_FALSE(server_->connection().empty()) << server_->error();
    dir_ = fs::temp_directory_path() / ("hv-catalog-" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    if (!dir_.empty()) fs::remove_all(dir_, ec);
  }
  static const std::string& connection() { return server_->connection(); }

  static std::unique_ptr<testing::CatalogServer> server_;
  fs::path dir_;
};

std::unique_ptr<testing::CatalogServer> CameraCatalogTest::server_;

using testing::awkwardPhoto;
using testing::expectSamePhoto;
using testing::expectSamePhotos;

TEST_F(CameraCatalogTest, EveryFieldOfEveryLensModelRoundTrips) {
  // testing::awkwardPhotos: every lens model, dates, a mask, a colour correction, other scripts.
  std::vector<Photo> photos = testing::awkwardPhotos();
  photos[3].date = "0500-02-28";  // before the Gregorian reform, after year 0

  const CatalogWriteResult w = writeCameraCatalog(photos, "EPSG:2154", connection(), "round_trip");
  EXPECT_EQ(w.rows, photos.size());
  EXPECT_EQ(w.srid, 2154);
  Diagnostics diag;
  const CatalogCameras back = readCameraCatalog(connection(), "round_trip", diag);
  EXPECT_TRUE(diag.errors.empty()) << diag.errors.front();
  EXPECT_EQ(back.crs, "EPSG:2154");
  expectSamePhotos(photos, back.photos);

  // Written again over the same table: replaced, not appended.
  photos.resize(2);
  writeCameraCatalog(photos, "EPSG:2154", connection(), "round_trip");
  EXPECT_EQ(readCameraCatalog(connection(), "round_trip", diag).photos.size(), 2u);
}

TEST_F(CameraCatalogTest, NativeColmapAndITownsFilesRoundTripThroughTheCatalog) {
  // Native cameras.json: every key of the format.
  for (const char* f : {"a.jpg", "b.jpg", "b_mask.png"}) std::ofstream(dir_ / f) << "x";
  std::ofstream(dir_ / "cameras.json") << R"({"cameras": [
    {"id": "a", "image": "a.jpg", "width": 640, "height": 480, "center": [10.1, 20.2, 30.3],
     "rotation": [0.36, 0.48, -0.8, -0.8, 0.6, 0, 0.48, 0.64, 0.6], "focal": [500.5, 501.25],
     "principal": [320.1, 240.2], "skew": 0.5, "date": "1921-07",
     "distortion": {"type": "radial", "center": [321, 239], "c3": 1e-8, "c5": -2e-15, "r2max": 500000}},
    {"id": "b", "image": "b.jpg", "mask": "b_mask.png", "width": 640, "height": 480,
     "center": [11, 21, 31], "rotation": [1, 0, 0, 0, -1, 0, 0, 0, -1], "focal": [400, 400],
     "principal": [320, 240], "distortion": {"type": "opencv", "k1": 0.1, "k2": -0.05, "p1": 0.001, "p2": -0.002}}]})";
  Diagnostics diag;
  const std::vector<Photo> native = readCameraFile((dir_ / "cameras.json").string(), CameraFileOptions{}, diag);
  ASSERT_EQ(native.size(), 2u) << (diag.errors.empty() ? "" : diag.errors.front());
  writeCameraCatalog(native, "", connection(), "native_cameras");
  const CatalogCameras fromNative = readCameraCatalog(connection(), "native_cameras", diag);
  EXPECT_EQ(fromNative.crs, "");  // no CRS: SRID 0
  expectSamePhotos(native, fromNative.photos);

  // COLMAP text model (radial and OpenCV lenses, quaternions).
  fs::create_directories(dir_ / "colmap");
  std::ofstream(dir_ / "colmap" / "cameras.txt") << "1 RADIAL 640 480 500 320 240 0.1 0.01\n"
                                                    "2 OPENCV 640 480 500 490 320 240 0.1 -0.02 0.001 0.002\n";
  std::ofstream(dir_ / "colmap" / "images.txt") << "1 0.9 0.1 -0.3 0.2 1.5 -2.25 5.125 1 a.jpg\n\n"
                                                   "2 0.5 0.5 0.5 0.5 0.1 0.2 0.3 2 b.jpg\n\n";
  const std::vector<Photo> colmap = readColmapModel((dir_ / "colmap").string(), dir_.string(), diag);
  ASSERT_EQ(colmap.size(), 2u) << (diag.errors.empty() ? "" : diag.errors.back());
  writeCameraCatalog(colmap, "", connection(), "colmap_cameras");
  expectSamePhotos(colmap, readCameraCatalog(connection(), "colmap_cameras", diag).photos);

  // iTowns: a rig of two cameras on two panoramas, turned by roll, pitch and heading.
  std::ofstream(dir_ / "calib.json") << R"([
    {"id": 1, "rotation": [1,0,0, 0,0,-1, 0,1,0], "position": [0.1,0.2,0.3],
     "projection": [1000.5,0,512.25, 0,1001.5,384.75, 0,0,1], "size": [1024, 768]},
    {"id": 2, "rotation": [0,0,-1, 1,0,0, 0,-1,0], "position": [-0.1,0.2,0.3],
     "projection": [1000.5,0,512.25, 0,1001.5,384.75, 0,0,1], "size": [1024, 768]}])";
  std::ofstream(dir_ / "poses.geojson") << R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651000.123, 6862000.456, 40.789]},
     "properties": {"id": 7, "roll": 1.234, "pitch": -2.345, "heading": 123.456}},
    {"type": "Feature", "geometry": {"type": "Point", "coordinates": [651003.321, 6862001.654, 40.987]},
     "properties": {"id": 8, "roll": -0.5, "pitch": 0.25, "heading": 301.75}}]})";
  const std::vector<Photo> itowns = readITownsCameras(
      {(dir_ / "poses.geojson").string(), (dir_ / "calib.json").string(), "img/{panoId}-{cameraId}.jpg"}, diag, false);
  ASSERT_EQ(itowns.size(), 4u) << (diag.errors.empty() ? "" : diag.errors.back());
  writeCameraCatalog(itowns, "EPSG:2154", connection(), "itowns_cameras");
  expectSamePhotos(itowns, readCameraCatalog(connection(), "itowns_cameras", diag).photos);
}

TEST_F(CameraCatalogTest, SceneJsonRendersFromTheCatalogAsFromTheFile) {
  for (const char* f : {"a.jpg", "b.jpg"}) std::ofstream(dir_ / f) << "x";
  std::ofstream(dir_ / "cameras.json") << R"({"cameras": [
    {"id": "a", "image": "a.jpg", "width": 64, "height": 48, "center": [651000.5, 6861000.25, 40],
     "rotation": [1, 0, 0, 0, 0, -1, 0, 1, 0], "focal": [50, 50], "principal": [32, 24], "date": "1910"},
    {"id": "b", "image": "b.jpg", "width": 64, "height": 48, "center": [651010.5, 6861000.25, 40],
     "rotation": [1, 0, 0, 0, 0, -1, 0, 1, 0], "focal": [50, 50], "principal": [32, 24]}]})";
  std::ofstream(dir_ / "files.json") << R"({"crs": "EPSG:2154", "terrain": {"height": 30},
    "cameras": {"path": "cameras.json"}})";
  Diagnostics diag;
  const Scene fromFiles = loadScene((dir_ / "files.json").string(), diag);
  ASSERT_EQ(fromFiles.photos.size(), 2u);
  writeCameraCatalog(fromFiles.photos, fromFiles.crs, connection(), "paris_1910.scene_cameras");

  std::ofstream(dir_ / "catalog.json") << R"({"crs": "EPSG:2154", "terrain": {"height": 30},
    "cameras": {"postgis": ")" << connection()
                                       << R"(", "table": "paris_1910.scene_cameras"}})";
  Diagnostics catalogDiag;
  const Scene fromCatalog = loadScene((dir_ / "catalog.json").string(), catalogDiag);
  EXPECT_TRUE(catalogDiag.errors.empty()) << catalogDiag.errors.front();
  expectSamePhotos(fromFiles.photos, fromCatalog.photos);
  EXPECT_EQ(fromFiles.origin, fromCatalog.origin);
  // The catalog's CRS is the cameras' CRS: without a scene CRS the scene takes it.
  std::ofstream(dir_ / "no_crs.json") << R"({"cameras": {"postgis": ")" << connection()
                                      << R"(", "table": "paris_1910.scene_cameras"}})";
  const Scene noCrs = loadScene((dir_ / "no_crs.json").string(), catalogDiag);
  EXPECT_EQ(noCrs.crs, "EPSG:2154");
  expectSamePhotos(fromFiles.photos, noCrs.photos);
}

TEST_F(CameraCatalogTest, NearestCamerasAgreeWithTheInMemorySelection) {
  // 2,000 cameras over a 1 km x 1 km block, heights over 30 m; 1,000 random view positions.
  std::mt19937_64 rng(20160916);
  std::uniform_real_distribution<double> ux(650000.0, 651000.0), uy(6860000.0, 6861000.0), uz(30.0, 60.0);
  std::vector<Photo> photos;
  std::vector<glm::dvec3> centres;
  for (int i = 0; i < 2000; ++i) {
    const glm::dvec3 c(ux(rng), uy(rng), uz(rng));
    Photo p;
    p.camera = lookAtCamera("p" + std::to_string(i), c, c + glm::dvec3(1.0, 0.0, 0.0), 64, 48, 50.0);
    p.imagePath = "/photos/p" + std::to_string(i) + ".jpg";
    photos.push_back(p);
    centres.push_back(c);
  }
  // Two cameras at one place (a rig re-shot): a tie, which both break by rank.
  photos.back().camera.center = centres.back() = centres.front();
  writeCameraCatalog(photos, "EPSG:2154", connection(), "knn");
  const CameraCatalog catalog(connection(), "knn");
  EXPECT_EQ(catalog.size(), photos.size());
  EXPECT_EQ(catalog.srid(), 2154);
  const ibr::CameraIndex index(centres);
  constexpr std::size_t k = 9;  // K + 1 with the default K of 8
  std::vector<glm::dvec3> views(1000);
  for (glm::dvec3& v : views) v = {ux(rng), uy(rng), uz(rng) - 20.0};
  // All the positions in one query too (the path a prefetch would ask for).
  const std::vector<std::vector<CameraCatalog::Neighbour>> batch = catalog.nearestCameras(views, k);
  ASSERT_EQ(batch.size(), views.size());
  int compared = 0;
  for (int q = 0; q < 1000; ++q) {
    const glm::dvec3& view = views[q];
    const std::vector<ibr::Candidate> memory = index.nearest(view, k);
    const std::vector<CameraCatalog::Neighbour> sql = catalog.nearestCameras(view, k);
    ASSERT_EQ(sql.size(), memory.size()) << "query " << q;
    for (std::size_t i = 0; i < k; ++i) {
      ASSERT_EQ(sql[i].fid - 1, memory[i].photo) << "query " << q << ", rank " << i;
      EXPECT_EQ(sql[i].id, photos[memory[i].photo].camera.id);
      EXPECT_NEAR(sql[i].distance, memory[i].distance, 1e-9 * memory[i].distance);
      ASSERT_EQ(batch[q].size(), k) << "query " << q;
      EXPECT_EQ(batch[q][i].fid, sql[i].fid) << "query " << q << ", rank " << i;
      EXPECT_EQ(batch[q][i].distance, sql[i].distance) << "query " << q << ", rank " << i;
    }
    ++compared;
  }
  EXPECT_EQ(compared, 1000);
  const auto tie = catalog.nearestCameras(centres.front() + glm::dvec3(0.0, 0.0, 1.0), 2);
  ASSERT_EQ(tie.size(), 2u);
  EXPECT_EQ(tie[0].fid, 1);
  EXPECT_EQ(tie[1].fid, 2000);
  EXPECT_EQ(tie[0].distance, 1.0);
  EXPECT_EQ(index.nearest(centres.front() + glm::dvec3(0.0, 0.0, 1.0), 2)[1].photo, 1999);
  EXPECT_TRUE(catalog.nearestCameras(glm::dvec3(0.0), 0).empty());
  EXPECT_EQ(catalog.nearestCameras(glm::dvec3(0.0), 5000).size(), photos.size());
}

TEST_F(CameraCatalogTest, BadConnectionsTablesAndRowsAreNamed) {
  // A file path is not a database.
  try {
    Diagnostics diag;
    readCameraCatalog("/tmp/cameras.json", "cameras", diag);
    ADD_FAILURE() << "a file path was taken for a connection";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("postgresql://"), std::string::npos) << e.what();
  }
  // Nobody listens there; the password is not printed.
  try {
    Diagnostics diag;
    readCameraCatalog("postgresql://postgres:s3cret@127.0.0.1:1/postgres", "cameras", diag);
    ADD_FAILURE() << "connected to port 1";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find("s3cret"), std::string::npos) << m;
    EXPECT_NE(m.find("127.0.0.1:1"), std::string::npos) << m;
  }
  // A table name that would be SQL.
  EXPECT_THROW(writeCameraCatalog({}, "", connection(), "x; DROP TABLE y"), InputError);
  // A missing table.
  try {
    Diagnostics diag;
    readCameraCatalog(connection(), "no_such_table", diag);
    ADD_FAILURE() << "read a missing table";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_table"), std::string::npos) << e.what();
  }
}

TEST_F(CameraCatalogTest, ARowWithABadFieldIsNamedAndTheOthersLoad) {
  std::vector<Photo> photos;
  for (int i = 0; i < 4; ++i) photos.push_back(awkwardPhoto(i));
  writeCameraCatalog(photos, "EPSG:2154", connection(), "broken");
  // Broken by hand, as another program writing the table might: a rotation of 2 numbers, a
  // reflection, an unknown lens model.
  const std::string sql =
      "UPDATE broken SET cam_from_world = '{1,2}' WHERE fid = 2; "
      "UPDATE broken SET cam_from_world = '{1,0,0,0,1,0,0,0,-1}' WHERE fid = 3; "
      "UPDATE broken SET distortion_model = 'zoom' WHERE fid = 4";
  ASSERT_EQ(std::system(("psql -X -q -v ON_ERROR_STOP=1 '" + connection() + "' -c \"" + sql + "\"").c_str()), 0);
  Diagnostics diag;
  const CatalogCameras back = readCameraCatalog(connection(), "broken", diag);
  ASSERT_EQ(back.photos.size(), 1u);
  expectSamePhoto(photos[0], back.photos[0]);
  ASSERT_EQ(diag.errors.size(), 3u);
  EXPECT_NE(diag.errors[0].find("table broken: fid 2 (camera 'cam1'): cam_from_world: expected 9 numbers"),
            std::string::npos)
      << diag.errors[0];
  EXPECT_NE(diag.errors[1].find("fid 3 (camera 'cam2')"), std::string::npos) << diag.errors[1];
  EXPECT_NE(diag.errors[1].find("reflection"), std::string::npos) << diag.errors[1];
  EXPECT_NE(diag.errors[2].find("distortion_model: expected"), std::string::npos) << diag.errors[2];
  EXPECT_EQ(diag.errors[0].find("***"), std::string::npos);  // no password to hide here
}

TEST(CameraCatalogNames, ConnectionsAndTablesAreCheckedWithoutAServer) {
  EXPECT_EQ(catalogConnection("postgresql://u@h:5/db"), "postgresql://u@h:5/db");
  EXPECT_EQ(catalogConnection("postgres://u@h/db"), "postgresql://u@h/db");
  EXPECT_EQ(catalogConnection("PG:dbname=x"), "PG:dbname=x");
  EXPECT_THROW(catalogConnection("cameras.json"), InputError);
  EXPECT_EQ(redactConnection("postgresql://me:pw@host/db"), "postgresql://me:***@host/db");
  EXPECT_EQ(redactConnection("PG:dbname=x password=pw user=me"), "PG:dbname=x password=*** user=me");
  EXPECT_EQ(redactConnection("postgresql://me@host/db"), "postgresql://me@host/db");
  EXPECT_NO_THROW(checkCatalogTableName("cameras", "t"));
  EXPECT_NO_THROW(checkCatalogTableName("paris_1900.cameras_2", "t"));
  EXPECT_THROW(checkCatalogTableName("2cameras", "t"), InputError);
  EXPECT_THROW(checkCatalogTableName("a.b.c", "t"), InputError);
  EXPECT_THROW(checkCatalogTableName("cameras\"; --", "t"), InputError);
  EXPECT_THROW(checkCatalogTableName("", "t"), InputError);
}

}  // namespace
}  // namespace hv
