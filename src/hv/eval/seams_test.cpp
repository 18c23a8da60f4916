// Seam misalignment (hv/eval/seams.h) on synthetic rigs where the displacement is known exactly:
// photographs rendered from a textured sphere, then measured with a camera rotated by a known small
// angle (a calibration error) or with the rig's cameras apart (parallax), against displacements
// derived independently from the construction, ray by ray.
#include "hv/eval/seams.h"

#include <gtest/gtest.h>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>

namespace hv::eval {
namespace {

const glm::dvec3 kCentre(652000.0, 6862000.0, 40.0);  // Lambert-93-sized, as the Paris rigs

// Value noise (lattice values from an integer hash, smoothstep-interpolated), two octaves: a
// texture without repeats, so that NCC has one peak.
double latticeValue(int x, int y, int z) {
  std::uint32_t h = std::uint32_t(x) * 73856093u ^ std::uint32_t(y) * 19349663u ^ std::uint32_t(z) * 83492791u;
  h ^= h >> 13;
  h *= 0x5bd1e995u;
  h ^= h >> 15;
  return double(h & 0xffffu) / 65535.0;
}

double valueNoise(const glm::dvec3& p) {
  const glm::dvec3 f = glm::floor(p);
  const glm::dvec3 t = p - f;
  const glm::dvec3 s = t * t * (3.0 - 2.0 * t);
  const int x = int(f.x), y = int(f.y), z = int(f.z);
  double v = 0.0;
  for (int k = 0; k < 8; ++k) {
    const int dx = k & 1, dy = (k >> 1) & 1, dz = (k >> 2) & 1;
    v += latticeValue(x + dx, y + dy, z + dz) * (dx ? s.x : 1 - s.x) * (dy ? s.y : 1 - s.y) * (dz ? s.z : 1 - s.z);
  }
  return v;
}

// The scene: a sphere of `radius` around kCentre, textured with noise of ~`cell` metres.
struct SphereScene {
  double radius = 8.0;
  double cell = 0.1;
  double grey(const glm::dvec3& world) const {
    const glm::dvec3 p = (world - kCentre) / cell;
    return 255.0 * (0.65 * valueNoise(p) + 0.35 * valueNoise(p / 3.7 + 11.0));
  }
  // Where the ray from `origin` (inside the sphere) along `dir` leaves it.
  glm::dvec3 hit(const glm::dvec3& origin, glm::dvec3 dir) const {
    dir = glm::normalize(dir);
    const glm::dvec3 o = origin - kCentre;
    const double b = glm::dot(o, dir), c = glm::dot(o, o) - radius * radius;
    return origin + (-b + std::sqrt(b * b - c)) * dir;
  }
};

// The photograph `truth` takes of the scene (its lens distortion included).
ImageF photograph(const Camera& truth, const SphereScene& scene) {
  ImageF im(truth.width, truth.height, 1);
  for (int y = 0; y < truth.height; ++y)
    for (int x = 0; x < truth.width; ++x) {
      const auto ideal = truth.undistort(glm::dvec2(x + 0.5, y + 0.5));
      EXPECT_TRUE(ideal.has_value());
      im.at(x, y, 0) = float(scene.grey(scene.hit(truth.center, truth.rayDirection(*ideal))));
    }
  return im;
}

// 512 x 512, focal 400 (a 65 deg field), looking horizontally at `azimuthDeg`, with a barrel
// distortion of 2 % at the image's edge.
Camera rigCamera(const std::string& id, const glm::dvec3& center, double azimuthDeg) {
  const double az = glm::radians(azimuthDeg);
  Camera c = lookAtCamera(id, center, center + glm::dvec3(std::cos(az), std::sin(az), 0.0), 512, 512, 400.0);
  LensDistortion d;
  d.center = c.principal + glm::dvec2(3.0, -2.0);
  d.c3 = -3e-7;
  d.fitDomain();
  c.distortion = d;
  return c;
}

glm::dmat3 rotation(double angle, const glm::dvec3& axis) {
  return glm::dmat3(glm::rotate(glm::dmat4(1.0), angle, glm::normalize(axis)));
}

TEST(Seams, CorrectCamerasOnTheirOwnCentreShowNoDisplacement) {
  const SphereScene scene;
  const Camera a = rigCamera("a", kCentre, 0.0), b = rigCamera("b", kCentre, 60.0);
  const ImageF ga = photograph(a, scene), gb = photograph(b, scene);
  for (double radius : {2.0, 1000.0}) {  // cameras at the centre: no parallax at any radius
    SeamSettings s;
    s.sphereRadius = radius;
    const SeamResult r = measureSeam({&a, &ga}, {&b, &gb}, kCentre, s);
    ASSERT_TRUE(r.overlaps);
    // The overlap at the horizon, from the photographs' edges: a's left edge and b's right one
    // (image x runs towards decreasing azimuth) undistorted into rays. The vertical edges are nearly
    // meridians, which the gnomonic patch maps to vertical lines: the width hardly changes along the
    // seam. Expected ~6.3 deg (2 x 33.2 deg of field with the barrel distortion, axes 60 deg apart).
    const auto azimuth = [](const Camera& c, glm::dvec2 px) {
      const glm::dvec3 d = c.rayDirection(*c.undistort(px));
      return std::atan2(d.y, d.x);
    };
    const double overlapRad = azimuth(a, {0.0, 256.0}) - azimuth(b, {512.0, 256.0});
    EXPECT_NEAR(glm::degrees(overlapRad), 6.3, 0.2);
    const SeamPatch patch = seamPatch({&a, &ga}, {&b, &gb}, kCentre, s);
    // The patch's middle row is the horizon (both cameras look horizontally); whole pixels: 1.5 px.
    const int row = int(patch.camera.principal.y);
    int horizonWidth = 0;
    for (int x = 0; x < patch.camera.width; ++x)
      horizonWidth += patch.maskA.at(x, row, 0) && patch.maskB.at(x, row, 0);
    EXPECT_NEAR(horizonWidth, patch.camera.focal.x * overlapRad, 1.5);
    // Away from the horizon the barrel distortion bends the edges outwards: the median row is wider.
    EXPECT_GE(r.overlapWidthPx, horizonWidth);
    EXPECT_LT(r.overlapWidthPx, 1.1 * horizonWidth);
    EXPECT_GT(r.matches.size(), 20u) << r.templates << " templates";
    for (const auto& m : r.matches) EXPECT_LT(glm::length(m.shift), 0.15) << m.patchPx.x << "," << m.patchPx.y;
  }
}

TEST(Seams, RotatedCameraShiftsByTheRotation) {
  const SphereScene scene;
  const Camera a = rigCamera("a", kCentre, 0.0), bTrue = rigCamera("b", kCentre, 60.0);
  const ImageF ga = photograph(a, scene), gb = photograph(bTrue, scene);
  // The calibration gets b wrong by `error` (world frame): the model's ray through a pixel is the
  // true one rotated by error^T, so the content b truly sees in direction c is put at error * c.
  const glm::dmat3 error = rotation(0.012, {0, 0, 1}) * rotation(0.008, {1, 1, 0});
  Camera bModel = bTrue;
  bModel.camFromWorld = bTrue.camFromWorld * glm::transpose(error);
  SeamSettings s;
  const SeamResult r = measureSeam({&a, &ga}, {&bModel, &gb}, kCentre, s);
  ASSERT_TRUE(r.overlaps);
  ASSERT_GT(r.matches.size(), 20u) << r.templates << " templates";
  const SeamPatch patch = seamPatch({&a, &ga}, {&bModel, &gb}, kCentre, s);
  double sumLength = 0.0;
  for (const auto& m : r.matches) {
    const glm::dvec3 content = glm::normalize(patch.camera.rayDirection(m.patchPx));
    const glm::dvec2 expected = patch.camera.project(kCentre + error * content).pxIdeal - m.patchPx;
    // Bilinear resampling twice and a smooth texture: sub-pixel peaks within 0.2 px.
    EXPECT_NEAR(m.shift.x, expected.x, 0.2) << m.patchPx.x << "," << m.patchPx.y;
    EXPECT_NEAR(m.shift.y, expected.y, 0.2) << m.patchPx.x << "," << m.patchPx.y;
    sumLength += glm::length(expected);
  }
  // 0.012 rad about the vertical moves b's content across the seam by ~5 px, 0.008 rad about a
  // horizontal axis moves it along by ~2 px; the photograph's pixels are about the patch's.
  const double meanExpected = sumLength / double(r.matches.size());
  EXPECT_GT(meanExpected, 4.0);
  EXPECT_NEAR(r.medianPx, meanExpected, 0.2 * meanExpected);
  EXPECT_GT(std::abs(r.medianShift.x), 3.0);
}

TEST(Seams, ParallaxVanishesAtTheSceneDepth) {
  // Cameras 0.3 m apart, 4 m from the centre of a 8 m scene sphere: the right radius (8 m) aligns
  // them, a far sphere leaves the parallax (~0.3 / 8 rad, ~15 px at most, depending on direction).
  const SphereScene scene;
  const Camera a = rigCamera("a", kCentre + glm::dvec3(0.0, -0.15, 0.0), 0.0);
  const Camera b = rigCamera("b", kCentre + glm::dvec3(0.0, 0.15, 0.0), 60.0);
  const ImageF ga = photograph(a, scene), gb = photograph(b, scene);
  std::map<double, double> medians;
  for (double radius : {8.0, 1000.0}) {
    SeamSettings s;
    s.sphereRadius = radius;
    const SeamResult r = measureSeam({&a, &ga}, {&b, &gb}, kCentre, s);
    const SeamPatch patch = seamPatch({&a, &ga}, {&b, &gb}, kCentre, s);
    ASSERT_GT(r.matches.size(), 20u) << "radius " << radius;
    for (const auto& m : r.matches) {
      // Independently: the sphere point under the template, the scene point a sees there, the ray
      // from b to that scene point, where it meets the sphere, and that point in the patch.
      const glm::dvec3 onSphere = kCentre + radius * glm::normalize(patch.camera.rayDirection(m.patchPx));
      const glm::dvec3 content = scene.hit(a.center, onSphere - a.center);
      const SphereScene measuring{radius, scene.cell};
      const glm::dvec3 whereB = measuring.hit(b.center, content - b.center);
      const glm::dvec2 expected = patch.camera.project(whereB).pxIdeal - m.patchPx;
      // The parallax changes by up to +-0.5 px over a 15 x 41 px window; the match is about its mean
      // over the window's shared pixels, not its value at the centre, once an edge of a photograph
      // cuts the window: 0.45 px (most are within 0.15 px).
      EXPECT_NEAR(m.shift.x, expected.x, 0.45) << "radius " << radius << " at " << m.patchPx.x << "," << m.patchPx.y;
      EXPECT_NEAR(m.shift.y, expected.y, 0.45) << "radius " << radius << " at " << m.patchPx.x << "," << m.patchPx.y;
    }
    medians[radius] = r.medianPx;
    // Parallax is all along the epipolar direction.
    EXPECT_LT(r.medianOffEpipolarPx, 0.2) << "radius " << radius;
  }
  EXPECT_LT(medians[8.0], 0.2);
  EXPECT_GT(medians[1000.0], 3.0);
}

TEST(Seams, TheOffEpipolarPartIsTheCalibrationErrorAtAnyRadius) {
  // Parallax as above plus a rotation error of b about its own optical axis (which the epipolar
  // direction, mostly across the seam here, does not absorb): the off-epipolar part stays when the
  // radius changes, while |shift| does not.
  const SphereScene scene;
  const Camera a = rigCamera("a", kCentre + glm::dvec3(0.0, -0.15, 0.0), 0.0);
  const Camera bTrue = rigCamera("b", kCentre + glm::dvec3(0.0, 0.15, 0.0), 60.0);
  const ImageF ga = photograph(a, scene), gb = photograph(bTrue, scene);
  Camera bModel = bTrue;
  const glm::dvec3 axisB = glm::transpose(bTrue.camFromWorld)[2];
  bModel.camFromWorld = bTrue.camFromWorld * glm::transpose(rotation(0.006, axisB));
  std::map<double, SeamResult> results;
  for (double radius : {8.0, 1000.0}) {
    SeamSettings s;
    s.sphereRadius = radius;
    results[radius] = measureSeam({&a, &ga}, {&bModel, &gb}, kCentre, s);
    ASSERT_GT(results[radius].matches.size(), 20u) << "radius " << radius;
  }
  // 0.006 rad about b's axis moves the seam, ~270 px from that axis, by ~1.6 px along itself
  // (measured: 1.58 px off-epipolar at 8 m, 1.63 px at 1000 m); the parallax at 1000 m adds ~15 px
  // across it. To first order only: 0.3 px.
  EXPECT_GT(results[8.0].medianOffEpipolarPx, 1.0);
  EXPECT_NEAR(results[1000.0].medianOffEpipolarPx, results[8.0].medianOffEpipolarPx, 0.3);
  EXPECT_GT(results[1000.0].medianPx, results[8.0].medianPx + 5.0);
}

TEST(Seams, OnlyOverlappingPairsAreSeams) {
  const SphereScene scene;
  const Camera a = rigCamera("a", kCentre, 0.0), b = rigCamera("b", kCentre, 60.0),
               opposite = rigCamera("opposite", kCentre, 180.0);
  const ImageF ga = photograph(a, scene), gb = photograph(b, scene), go = photograph(opposite, scene);
  SeamSettings s;
  s.sphereRadius = 10.0;
  const SeamResult none = measureSeam({&a, &ga}, {&opposite, &go}, kCentre, s);
  EXPECT_FALSE(none.overlaps);
  EXPECT_TRUE(none.matches.empty());
  EXPECT_TRUE(std::isnan(none.medianPx));
  // b and the opposite camera are 120 deg apart: no overlap either.
  const std::vector<SeamResult> rig = measureRigSeams({{&a, &ga}, {&b, &gb}, {&opposite, &go}}, kCentre, s);
  ASSERT_EQ(rig.size(), 1u);
  EXPECT_EQ(rig[0].a, "a");
  EXPECT_EQ(rig[0].b, "b");
  const std::string table = formatSeamTable(rig);
  EXPECT_NE(table.find("a | b"), std::string::npos) << table;
  EXPECT_NE(table.find("confident matches"), std::string::npos) << table;
}

TEST(Seams, AnImageOfTheWrongSizeNamesTheCamera) {
  const Camera a = rigCamera("left-cam", kCentre, 0.0), b = rigCamera("right-cam", kCentre, 60.0);
  const ImageF ga(512, 512, 1), small(256, 256, 1);
  try {
    measureSeam({&a, &ga}, {&b, &small}, kCentre, SeamSettings{});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("right-cam"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("256x256x1"), std::string::npos) << e.what();
  }
}

TEST(Seams, GreyImageIsRec601Luma) {
  Image8 rgb(1, 1, 3);
  rgb.data = {200, 100, 50};
  EXPECT_NEAR(greyImage(rgb).data[0], 0.299 * 200 + 0.587 * 100 + 0.114 * 50, 1e-4);
}

}  // namespace
}  // namespace hv::eval
