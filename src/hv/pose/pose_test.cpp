#include "hv/pose/pose.h"

#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace hv::pose {
namespace {

double angleDegrees(const glm::dmat3& a, const glm::dmat3& b) {
  const glm::dmat3 d = a * glm::transpose(b);
  const double c = std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

glm::dmat3 rotationAbout(glm::dvec3 axis, double degrees) {
  axis = glm::normalize(axis);
  const double t = degrees * M_PI / 180.0, c = std::cos(t), s = std::sin(t);
  glm::dmat3 K(0.0);
  K[1][0] = axis.z, K[2][0] = -axis.y, K[0][1] = -axis.z, K[2][1] = axis.x, K[0][2] = axis.y, K[1][2] = -axis.x;
  return glm::dmat3(1.0) + s * K + (1.0 - c) * K * K;
}

// A photograph of a street: 1600x1200, focal 1400, the principal point off centre, in a
// projected CRS (coordinates in the hundreds of thousands of metres).
Camera truthCamera() {
  const glm::dvec3 o(651000.0, 6862000.0, 40.0);
  Camera c = lookAtCamera("p1", o + glm::dvec3(12.0, -45.0, 8.0), o + glm::dvec3(0.0, 0.0, 6.0), 1600, 1200, 1400.0);
  c.principal = {812.0, 590.0};
  return c;
}

// Points on façades and the ground in front of the camera, seen inside the photograph.
std::vector<ControlPoint> controlPoints(const Camera& cam, int count, double noisePx, bool ground, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(-25.0, 25.0), uy(-10.0, 25.0), uz(0.0, 22.0);
  std::normal_distribution<double> noise(0.0, noisePx);
  const glm::dvec3 o(651000.0, 6862000.0, 40.0);
  std::vector<ControlPoint> pts;
  while (int(pts.size()) < count) {
    const glm::dvec3 X = o + glm::dvec3(ux(rng), uy(rng), ground ? 0.0 : uz(rng));
    const Projection p = cam.project(X);
    if (!p.inImage) continue;
    ControlPoint cp;
    cp.world = X;
    cp.pixel = p.pxDistorted + glm::dvec2(noise(rng), noise(rng));
    pts.push_back(cp);
  }
  return pts;
}

// The first guess: metres and degrees away, the focal 10 % off.
Camera roughGuess(const Camera& truth, double focalFactor) {
  Camera g = truth;
  g.center += glm::dvec3(4.0, -3.0, 2.0);
  g.camFromWorld = rotationAbout({0.3, 1.0, 0.2}, 4.0) * truth.camFromWorld;
  g.focal *= focalFactor;
  return g;
}

void expectClose(const PoseResult& r, const Camera& truth) {
  EXPECT_LT(glm::length(r.camera.center - truth.center), 0.1);
  EXPECT_LT(angleDegrees(r.camera.camFromWorld, truth.camFromWorld), 0.1);
  EXPECT_LT(std::abs(r.camera.focal.x / truth.focal.x - 1.0), 0.005);
}

TEST(P3P, OneOfTheSolutionsIsTheCamera) {
  const Camera cam = truthCamera();
  const auto pts = controlPoints(cam, 3, 0.0, false, 7);
  std::array<glm::dvec3, 3> f, X;
  for (int i = 0; i < 3; ++i) {
    f[size_t(i)] = glm::normalize(cam.camFromPix() * glm::dvec3(pts[size_t(i)].pixel, 1.0));
    X[size_t(i)] = pts[size_t(i)].world;
  }
  const auto poses = solveP3P(f, X);
  ASSERT_FALSE(poses.empty());
  double bestC = 1e30, bestR = 1e30;
  for (const auto& [R, C] : poses) {
    if (glm::length(C - cam.center) < bestC) bestC = glm::length(C - cam.center), bestR = angleDegrees(R, cam.camFromWorld);
  }
  EXPECT_LT(bestC, 1e-5);
  EXPECT_LT(bestR, 1e-6);
}

TEST(Dlt, ExactPointsGiveTheCameraAndItsIntrinsics) {
  const Camera cam = truthCamera();
  const auto pts = controlPoints(cam, 8, 0.0, false, 3);
  std::vector<glm::dvec2> px;
  std::vector<glm::dvec3> X;
  for (const auto& p : pts) px.push_back(p.pixel), X.push_back(p.world);
  DltCamera d;
  ASSERT_TRUE(solveDlt(px, X, d));
  EXPECT_LT(glm::length(d.pose.second - cam.center), 1e-4);
  EXPECT_LT(angleDegrees(d.pose.first, cam.camFromWorld), 1e-5);
  EXPECT_NEAR(d.focal, 1400.0, 1e-3);
  EXPECT_NEAR(d.principal.x, 812.0, 1e-3);
  EXPECT_NEAR(d.principal.y, 590.0, 1e-3);
}

TEST(Pose, NoisyPointsAndARoughGuessGiveTheCamera) {
  const Camera truth = truthCamera();
  const auto pts = controlPoints(truth, 30, 0.5, false, 11);
  const PoseResult r = solvePose(pts, roughGuess(truth, 1.1), true, PoseOptions{});
  expectClose(r, truth);
  EXPECT_EQ(r.inlierCount, 30);
  EXPECT_LT(r.rmsPixels, 1.0);
  // The centre's standard deviation says how well it is known: a fraction of the error bound.
  EXPECT_GT(r.centerSigma.x, 0.0);
  EXPECT_LT(glm::length(r.centerSigma), 0.1);
}

TEST(Pose, TwentyPercentOutliersAreFoundWithoutAFirstPose) {
  const Camera truth = truthCamera();
  auto pts = controlPoints(truth, 30, 0.5, false, 5);
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> u(0.0, 1600.0), v(0.0, 1200.0);
  for (int i = 0; i < 6; ++i) pts[size_t(i * 5)].pixel = {u(rng), v(rng)};
  Camera intrinsicsOnly = roughGuess(truth, 1.1);
  const PoseResult r = solvePose(pts, intrinsicsOnly, false, PoseOptions{});
  expectClose(r, truth);
  for (int i = 0; i < 30; ++i) EXPECT_EQ(r.inliers[size_t(i)], i % 5 != 0) << i;
}

TEST(Pose, GroundPointsWithAKnownFocal) {
  const Camera truth = truthCamera();
  const auto pts = controlPoints(truth, 12, 0.5, true, 21);
  PoseOptions o;
  o.refine = parseRefine("none");
  const PoseResult r = solvePose(pts, roughGuess(truth, 1.0), false, o);
  expectClose(r, truth);
  ASSERT_FALSE(r.notes.empty());
  EXPECT_NE(r.notes[0].find("plane"), std::string::npos);
}

TEST(Pose, RadialDistortionIsSolvedOnRequest) {
  Camera truth = truthCamera();
  LensDistortion d;
  d.center = truth.principal;
  d.scale = truth.focal;
  d.c3 = -0.08;
  d.c5 = 0.01;
  truth.distortion = d;
  const auto pts = controlPoints(truth, 60, 0.5, false, 13);
  Camera guess = roughGuess(truth, 1.05);
  guess.distortion.reset();
  PoseOptions o;
  o.refine = parseRefine("focal,radial");
  const PoseResult r = solvePose(pts, guess, true, o);
  expectClose(r, truth);
  ASSERT_TRUE(r.camera.distortion);
  EXPECT_NEAR(r.camera.distortion->c3, -0.08, 0.01);
  // Without the radial terms the same points leave residuals of pixels.
  o.refine = parseRefine("focal");
  EXPECT_GT(solvePose(pts, guess, true, o).rmsPixels, 2.0 * r.rmsPixels);
}

TEST(Pose, InputThatCannotDetermineTheCameraIsRefusedSayingWhatToAdd) {
  const Camera truth = truthCamera();
  auto five = controlPoints(truth, 5, 0.5, false, 1);
  try {
    solvePose(five, truth, true, PoseOptions{});
    FAIL() << "5 points accepted for a free focal";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("at least 6"), std::string::npos) << e.what();
  }
  PoseOptions fixed;
  fixed.refine = parseRefine("none");
  EXPECT_NO_THROW(solvePose(five, truth, true, fixed));

  std::vector<ControlPoint> line;
  for (int i = 0; i < 8; ++i) {
    ControlPoint p;
    p.world = truth.center + glm::dvec3(0.0, 40.0 + i, 0.0) + glm::dvec3(1.0, 0.0, 0.0) * double(i);
    p.pixel = truth.project(p.world).pxDistorted;
    line.push_back(p);
  }
  try {
    solvePose(line, truth, true, PoseOptions{});
    FAIL() << "collinear points accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("line"), std::string::npos) << e.what();
  }

  Camera noFocal = truth;
  noFocal.focal = glm::dvec2(0.0);
  try {
    solvePose(controlPoints(truth, 10, 0.5, true, 4), noFocal, false, PoseOptions{});
    FAIL() << "a plane with an unknown focal accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plane"), std::string::npos) << e.what();
  }

  EXPECT_THROW(parseRefine("focal,skew"), InputError);
}

TEST(ControlPointsCsv, ColumnsInAnyOrderLabelsAndComments) {
  const auto pts = parseControlPoints("# from the archive\nid,x,y,z,u,v\nspire,651000.5,6862000,95,812.25,101\n\n"
                                      "door,651010,6862003.5,1.5,900,1100\n",
                                      "gcp.csv");
  ASSERT_EQ(pts.size(), 2u);
  EXPECT_EQ(pts[0].label, "spire");
  EXPECT_DOUBLE_EQ(pts[0].pixel.x, 812.25);
  EXPECT_DOUBLE_EQ(pts[0].world.x, 651000.5);
  EXPECT_DOUBLE_EQ(pts[1].world.y, 6862003.5);
}

TEST(ControlPointsCsv, ErrorsNameTheLineTheColumnAndWhatWasExpected) {
  auto message = [](const std::string& text) {
    try {
      parseControlPoints(text, "gcp.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("u,v,x,y\n1,2,3,4\n").find("no column 'z'"), std::string::npos);
  const std::string bad = message("u,v,x,y,z\n1,2,3,4,5\n1,2,abc,4,5\n");
  EXPECT_NE(bad.find("gcp.csv: line 3: column 'x'"), std::string::npos) << bad;
  EXPECT_NE(bad.find("finite number"), std::string::npos) << bad;
  EXPECT_NE(message("u,v,x,y,z\n1,2,3,4\n").find("4 fields where the header has 5"), std::string::npos);
  EXPECT_NE(message("u,v,x,y,z\n1,2,nan,4,5\n").find("column 'x'"), std::string::npos);
  EXPECT_NE(message("").find("empty"), std::string::npos);
}

}  // namespace
}  // namespace hv::pose
