#include "hv/scene/point_normals.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>

namespace hv {
namespace {

// A deterministic jittered grid (no std:: distributions: the same points everywhere).
double jitter(std::uint64_t i) {
  i = (i ^ (i >> 30)) * 0xbf58476d1ce4e5b9ull;
  i = (i ^ (i >> 27)) * 0x94d049bb133111ebull;
  return double((i ^ (i >> 31)) >> 11) / double(1ull << 53) - 0.5;
}

TEST(PointNormals, PlaneAtAnAngleGivesItsNormal) {
  // A tilted plane through (651000, 6862000, 40) (Lambert-93 sized coordinates): its normal is
  // known exactly; the estimate must be parallel to it.
  const glm::dvec3 n = glm::normalize(glm::dvec3(0.3, -0.5, 0.8));
  const glm::dvec3 u = glm::normalize(glm::cross(n, glm::dvec3(1, 0, 0)));
  const glm::dvec3 v = glm::cross(n, u);
  PointCloud c;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j)
      c.positions.push_back(glm::dvec3(651000, 6862000, 40) + (i + 0.4 * jitter(i * 40 + j)) * 0.1 * u +
                            (j + 0.4 * jitter(9999 + i * 40 + j)) * 0.1 * v);
  estimateNormals(c);
  ASSERT_EQ(c.normals.size(), c.size());
  for (const glm::vec3& e : c.normals) {
    EXPECT_NEAR(std::abs(glm::dot(glm::dvec3(e), n)), 1.0, 1e-6);
    EXPECT_GE(e.z, 0.0f);  // turned upwards
  }
}

TEST(PointNormals, SphereNormalsAreRadial) {
  // Points on a sphere of radius 10 (Fibonacci lattice, ~0.5 units apart): the estimated normal
  // is the radial direction, up to the curvature over the neighbourhood (< 2 degrees here).
  PointCloud c;
  const int n = 4000;
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / n, r = std::sqrt(1.0 - z * z);
    c.positions.push_back(10.0 * glm::dvec3(r * std::cos(golden * i), r * std::sin(golden * i), z));
  }
  NormalEstimation st;
  st.threads = 2;
  estimateNormals(c, st);
  double worst = 0.0;
  for (size_t i = 0; i < c.size(); ++i) {
    const double cosA = std::abs(glm::dot(glm::dvec3(c.normals[i]), glm::normalize(c.positions[i])));
    worst = std::max(worst, std::acos(std::min(cosA, 1.0)) * 180.0 / M_PI);
  }
  EXPECT_LT(worst, 2.0);
}

TEST(PointNormals, CollinearOrTooFewPointsGetNoNormal) {
  PointCloud line;
  for (int i = 0; i < 20; ++i) line.positions.push_back({i * 0.1, 2.0 * i * 0.1, 5.0});
  estimateNormals(line);
  for (const glm::vec3& e : line.normals) EXPECT_EQ(e, glm::vec3(0.0f));
  PointCloud two;
  two.positions = {{0, 0, 0}, {1, 0, 0}};
  estimateNormals(two);
  EXPECT_EQ(two.normals[0], glm::vec3(0.0f));
  PointCloud none;
  estimateNormals(none);
  EXPECT_TRUE(none.normals.empty());
}


TEST(PointNormals, DuplicatePointsStayFast) {
  // 100k copies of one point (a scanner standing still): a kd-tree search among equal points
  // visits all of them, which made this quadratic (hours for a million). Distinct positions are
  // searched once each: no plane, so no normal, within a few seconds even unoptimised.
  PointCloud same;
  same.positions.assign(100000, glm::dvec3(651000.0, 6862000.0, 35.0));
  const auto t0 = std::chrono::steady_clock::now();
  estimateNormals(same);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_LT(s, 3.0);
  ASSERT_EQ(same.normals.size(), same.size());
  for (const glm::vec3& e : same.normals) EXPECT_EQ(e, glm::vec3(0.0f));
}

TEST(PointNormals, DuplicatesGetTheNormalOfTheirPosition) {
  // A horizontal grid, every point present three times, plus 50k copies of one of them: each copy
  // gets the plane's normal, as the grid without duplicates does.
  PointCloud c;
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j)
      for (int r = 0; r < 3; ++r) c.positions.push_back({i * 0.2 + 0.05 * jitter(i * 30 + j), j * 0.2, 12.0});
  c.positions.insert(c.positions.end(), 50000, c.positions[100]);
  const auto t0 = std::chrono::steady_clock::now();
  estimateNormals(c);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 3.0);
  ASSERT_EQ(c.normals.size(), c.size());
  for (const glm::vec3& e : c.normals) EXPECT_NEAR(e.z, 1.0f, 1e-5f);
}

}  // namespace
}  // namespace hv
