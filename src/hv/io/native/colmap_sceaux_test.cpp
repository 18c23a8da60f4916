// The COLMAP reader on a real reconstruction: the ten Sceaux photographs registered by Debian's
// colmap (tools/colmap-sceaux.sh writes the model into the build folder; like the photographs it
// is never part of the repository). Skips, saying why, when the model or the photographs are absent.
//
// Two independent checks of the reader's conventions (quaternion order, world -> camera, pixel
// origin, SIMPLE_RADIAL on normalised coordinates):
//  - every 3D point of points3D.txt, projected by the camera histoview read, lands on the 2D
//    positions images.txt recorded for it, within the reprojection error COLMAP itself states for
//    that point (its ERROR column: the mean over the track);
//  - the poses agree with OpenMVS's reconstruction of the same photographs (sceaux/cameras.json),
//    made by other software in another frame: relative rotations R_i R_j^T and ratios of camera
//    distances do not depend on the frame.
#include "hv/io/native/scene_loader.h"
#include "hv/io/cameras_json.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

// Where tools/colmap-sceaux.sh leaves the model: $HV_COLMAP_SCEAUX, else build/colmap-sceaux/sparse.
std::string colmapModelDir() {
  if (const char* env = std::getenv("HV_COLMAP_SCEAUX"); env && *env) return env;
#ifdef HV_BINARY_DIR
  return std::string(HV_BINARY_DIR) + "/colmap-sceaux/sparse";
#else
  return "build/colmap-sceaux/sparse";
#endif
}

struct Observation {
  std::string image;  // NAME of images.txt
  glm::dvec2 px;
};

struct Point3D {
  glm::dvec3 position;
  double error = 0.0;  // COLMAP's mean reprojection error over the track, pixels
  std::vector<Observation> track;
};

// images.txt and points3D.txt read here, independently of the reader under test.
std::vector<Point3D> readPoints(const std::string& dir) {
  std::map<long, std::string> names;
  std::map<long, std::vector<glm::dvec2>> points2d;
  std::ifstream images(dir + "/images.txt");
  std::string line;
  bool poseLine = true;
  long current = 0;
  while (std::getline(images, line)) {
    if (!line.empty() && line[0] == '#') continue;
    std::istringstream s(line);
    if (poseLine) {
      double q[7];
      long camera = 0;
      std::string name;
      if (!(s >> current >> q[0] >> q[1] >> q[2] >> q[3] >> q[4] >> q[5] >> q[6] >> camera >> name)) continue;
      names[current] = name;
    } else {
      double x = 0, y = 0;
      long id = 0;
      while (s >> x >> y >> id) points2d[current].push_back({x, y});
    }
    poseLine = !poseLine;
  }
  std::vector<Point3D> points;
  std::ifstream in(dir + "/points3D.txt");
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    long id = 0;
    int r = 0, g = 0, b = 0;
    Point3D p;
    if (!(s >> id >> p.position.x >> p.position.y >> p.position.z >> r >> g >> b >> p.error)) continue;
    long image = 0, index = 0;
    while (s >> image >> index) p.track.push_back({names.at(image), points2d.at(image).at(index)});
    points.push_back(std::move(p));
  }
  return points;
}

class ColmapSceaux : public ::testing::Test {
 protected:
  void SetUp() override {
    sceaux_ = testing::dataset("sceaux");
    if (sceaux_.empty()) HV_SKIP_WITHOUT_DATA(std::string("no sceaux/ in ") + testing::dataDir() + " (set HISTOVIEW_DATA)");
    model_ = colmapModelDir();
    // Named explicitly ($HV_COLMAP_SCEAUX, which tools/test.sh sets once it has made the model),
    // the model must be there; the default place may lack it (colmap is an optional package).
    const bool named = std::getenv("HV_COLMAP_SCEAUX") && *std::getenv("HV_COLMAP_SCEAUX");
    if (!fs::exists(model_ + "/images.txt")) {
      ASSERT_FALSE(named) << "HV_COLMAP_SCEAUX names " << model_ << ", which holds no images.txt";
      GTEST_SKIP() << "no COLMAP model in " << model_ << " (make it with tools/colmap-sceaux.sh; needs colmap)";
    }
    // The five-line scene.json a COLMAP user writes.
    tmp_ = fs::temp_directory_path() / ("hv-colmap-sceaux-" + std::to_string(::getpid()));
    fs::create_directories(tmp_);
    const nlohmann::json scene = {
        {"cameras", {{"format", "colmap"}, {"path", model_}, {"images", sceaux_ + "/images"}}}};
    std::ofstream(tmp_ / "scene.json") << scene.dump(1);
    Diagnostics diag;
    scene_ = loadScene((tmp_ / "scene.json").string(), diag);
    for (const auto& m : diag.errors) ADD_FAILURE() << m;
    for (const Photo& p : scene_.photos) photos_[p.camera.id + ".jpg"] = &p;
  }
  void TearDown() override {
    if (!tmp_.empty()) fs::remove_all(tmp_);
  }
  std::string sceaux_, model_;
  fs::path tmp_;
  Scene scene_;
  std::map<std::string, const Photo*> photos_;
};

TEST_F(ColmapSceaux, PointsProjectOntoTheirObservationsWithinColmapsError) {
  ASSERT_EQ(scene_.photos.size(), 10u) << "all ten photographs registered";
  const std::vector<Point3D> points = readPoints(model_);
  ASSERT_GT(points.size(), 1000u);
  std::size_t observations = 0, worse = 0;
  double sum = 0.0, worstGap = 0.0;
  for (const Point3D& p : points) {
    double pointSum = 0.0;
    for (const Observation& o : p.track) {
      const Photo* photo = photos_.at(o.image);
      const Projection proj = photo->camera.project(p.position);
      ASSERT_TRUE(proj.inFront) << o.image;
      const double e = glm::length(proj.pxDistorted - o.px);
      pointSum += e;
      sum += e;
      ++observations;
    }
    // COLMAP's ERROR is the mean over the track of the same distance; the text model rounds the
    // 2D positions to float (~1e-4 px here), so the two agree to well under a hundredth of a pixel
    // when every convention is right (a half-pixel origin shift alone moves it by ~0.5 px).
    const double gap = std::abs(pointSum / double(p.track.size()) - p.error);
    worstGap = std::max(worstGap, gap);
    if (gap > 0.01) ++worse;
  }
  const double mean = sum / double(observations);
  std::printf("COLMAP Sceaux: %zu points, %zu observations, mean reprojection error %.3f px, "
              "largest gap to COLMAP's own per-point error %.2e px\n",
              points.size(), observations, mean, worstGap);
  EXPECT_LT(mean, 1.0);
  EXPECT_EQ(worse, 0u) << "points whose recomputed error differs from COLMAP's by more than 0.01 px";
}

TEST_F(ColmapSceaux, PosesAgreeWithOpenMvsUpToASimilarity) {
  Diagnostics diag;
  const auto openMvs = readCameraFile(sceaux_ + "/cameras.json", CameraFileOptions{}, diag);
  std::map<std::string, const Camera*> other;
  for (const Photo& p : openMvs) other[p.camera.id + ".jpg"] = &p.camera;
  std::vector<const Camera*> a, b;
  for (const auto& [name, photo] : photos_) {
    if (!other.count(name)) continue;
    a.push_back(&photo->camera);
    b.push_back(other.at(name));
  }
  ASSERT_GE(a.size(), 9u);
  // Relative rotations R_i R_j^T do not depend on the world frame. Their axes do depend on the
  // intrinsics: COLMAP keeps the principal point at the image centre (its default), OpenMVS moved
  // it by (36, 61) px, so every COLMAP camera is turned by the same ~1.2 degrees Q, which conjugates
  // R_i R_j^T (Q R_i R_j^T Q^T). Its angle is invariant under that, and is compared here.
  auto angleDeg = [](const glm::dmat3& r) {
    return std::acos(std::clamp((r[0][0] + r[1][1] + r[2][2] - 1.0) / 2.0, -1.0, 1.0)) * 180.0 / M_PI;
  };
  double worstDeg = 0.0, largestDeg = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    for (size_t j = i + 1; j < a.size(); ++j) {
      const double ra = angleDeg(a[i]->camFromWorld * glm::transpose(a[j]->camFromWorld));
      const double rb = angleDeg(b[i]->camFromWorld * glm::transpose(b[j]->camFromWorld));
      worstDeg = std::max(worstDeg, std::abs(ra - rb));
      largestDeg = std::max(largestDeg, rb);
    }
  }
  // Distances between camera centres, each set divided by its mean: the same up to scale.
  auto normalised = [](const std::vector<const Camera*>& cams) {
    std::vector<double> d;
    for (size_t i = 0; i < cams.size(); ++i)
      for (size_t j = i + 1; j < cams.size(); ++j) d.push_back(glm::length(cams[i]->center - cams[j]->center));
    double mean = 0.0;
    for (double x : d) mean += x;
    mean /= double(d.size());
    for (double& x : d) x /= mean;
    return d;
  };
  const auto da = normalised(a), db = normalised(b);
  double worstRatio = 0.0;
  for (size_t k = 0; k < da.size(); ++k) worstRatio = std::max(worstRatio, std::abs(da[k] - db[k]));
  const double focalGap = std::abs(a[0]->focal.x - b[0]->focal.x) / b[0]->focal.x;
  std::printf("COLMAP vs OpenMVS on Sceaux: relative rotation angles (up to %.1f deg) differ by at most "
              "%.3f deg, normalised centre distances by %.4f, focal by %.2f %%\n",
              largestDeg, worstDeg, worstRatio, 100.0 * focalGap);
  // Two independent reconstructions of one set: a tenth of a degree and a percent are generous;
  // a transposed rotation, a swapped quaternion order or a mirrored frame is off by degrees.
  EXPECT_LT(worstDeg, 0.2);
  EXPECT_LT(worstRatio, 0.01);
  EXPECT_LT(focalGap, 0.01);
}

}  // namespace
}  // namespace hv
