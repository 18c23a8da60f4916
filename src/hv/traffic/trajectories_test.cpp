#include "hv/traffic/trajectories.h"

#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv {
namespace {

TEST(TrajectoriesCsv, ReadsVehiclesSortedByTime) {
  Diagnostics diag;
  const Trajectories t = parseTrajectoriesCsv(
      "t,id,x,y,angle,type\n"
      "1.0,a,10,20,90,passenger\n"
      "0.0,a,0,20,90,passenger\n"
      "0.5,b,5,5,0,bus\n",
      "traj.csv", diag);
  ASSERT_EQ(t.vehicles.size(), 2u);
  EXPECT_EQ(t.vehicles[0].id, "a");
  ASSERT_EQ(t.vehicles[0].samples.size(), 2u);
  EXPECT_EQ(t.vehicles[0].samples[0].t, 0.0);
  EXPECT_EQ(t.vehicles[0].samples[1].xy, glm::dvec2(10, 20));
  EXPECT_EQ(t.vehicles[1].size.length, 12.0);  // a bus
  EXPECT_EQ(t.tBegin, 0.0);
  EXPECT_EQ(t.tEnd, 1.0);
  EXPECT_TRUE(diag.warnings.empty());
}

TEST(TrajectoriesCsv, ColumnsInAnyOrderAndUnknownTypeIsTheDefaultCarWithANote) {
  Diagnostics diag;
  const Trajectories t = parseTrajectoriesCsv("id,type,angle,y,x,t\nv,hovercraft,0,2,1,3\n", "traj.csv", diag);
  ASSERT_EQ(t.vehicles.size(), 1u);
  EXPECT_EQ(t.vehicles[0].samples[0].xy, glm::dvec2(1, 2));
  EXPECT_EQ(t.vehicles[0].samples[0].t, 3.0);
  EXPECT_EQ(t.vehicles[0].size.length, 4.5);
  EXPECT_EQ(t.vehicles[0].size.width, 1.8);
  EXPECT_EQ(t.vehicles[0].size.height, 1.5);
  ASSERT_EQ(diag.warnings.size(), 1u);
  EXPECT_NE(diag.warnings[0].find("hovercraft"), std::string::npos);
}

TEST(TrajectoriesCsv, BrokenFilesNameFileLineAndField) {
  Diagnostics diag;
  const auto message = [&](const char* text) {
    try {
      parseTrajectoriesCsv(text, "traj.csv", diag);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string badX = message("t,id,x,y,angle\n0,a,1,2,3\n0.5,a,oops,2,3\n");
  EXPECT_NE(badX.find("traj.csv: line 3: column 'x'"), std::string::npos) << badX;
  EXPECT_NE(badX.find("oops"), std::string::npos) << badX;
  const std::string noAngle = message("t,id,x,y\n0,a,1,2\n");
  EXPECT_NE(noAngle.find("traj.csv: line 1: the header has no column 'angle'"), std::string::npos) << noAngle;
  const std::string shortRow = message("t,id,x,y,angle\n0,a,1,2\n");
  EXPECT_NE(shortRow.find("traj.csv: line 2: 4 fields where the header has 5"), std::string::npos) << shortRow;
  const std::string nan = message("t,id,x,y,angle\nnan,a,1,2,0\n");
  EXPECT_NE(nan.find("line 2: column 't'"), std::string::npos) << nan;
  EXPECT_NE(message("").find("traj.csv: empty"), std::string::npos);
}

TEST(Trajectory, ShownOnlyBetweenFirstAndLastSample) {
  Trajectory v;
  v.samples = {{10.0, {0, 0}, 90.0}, {12.0, {20, 0}, 90.0}};
  EXPECT_FALSE(sampleTrajectory(v, 9.999).has_value());
  EXPECT_FALSE(sampleTrajectory(v, 12.001).has_value());
  ASSERT_TRUE(sampleTrajectory(v, 10.0).has_value());
  ASSERT_TRUE(sampleTrajectory(v, 12.0).has_value());
  EXPECT_EQ(sampleTrajectory(v, 12.0)->xy, glm::dvec2(20, 0));
}

TEST(Trajectory, InterpolatesPositionLinearly) {
  Trajectory v;
  v.samples = {{0.0, {0, 0}, 0.0}, {1.0, {10, 4}, 0.0}, {3.0, {10, 24}, 0.0}};
  const auto a = sampleTrajectory(v, 0.25);
  ASSERT_TRUE(a.has_value());
  EXPECT_NEAR(a->xy.x, 2.5, 1e-12);
  EXPECT_NEAR(a->xy.y, 1.0, 1e-12);
  const auto b = sampleTrajectory(v, 2.0);  // halfway through the second step
  ASSERT_TRUE(b.has_value());
  EXPECT_NEAR(b->xy.x, 10.0, 1e-12);
  EXPECT_NEAR(b->xy.y, 14.0, 1e-12);
}

TEST(Trajectory, HeadingTakesTheShortArc) {
  Trajectory v;
  v.samples = {{0.0, {0, 0}, 350.0}, {1.0, {0, 0}, 10.0}, {2.0, {0, 0}, 100.0}};
  EXPECT_NEAR(sampleTrajectory(v, 0.5)->angleDeg, 0.0, 1e-9);  // through north, not south
  EXPECT_NEAR(sampleTrajectory(v, 0.25)->angleDeg, 355.0, 1e-9);
  EXPECT_NEAR(sampleTrajectory(v, 0.75)->angleDeg, 5.0, 1e-9);
  EXPECT_NEAR(sampleTrajectory(v, 1.5)->angleDeg, 55.0, 1e-9);
  Trajectory w;
  w.samples = {{0.0, {0, 0}, 10.0}, {1.0, {0, 0}, -170.0}};  // 190 = -170: half-turn, either way
  EXPECT_NEAR(
      std::abs(sampleTrajectory(w, 0.5)->angleDeg - 100.0) * std::abs(sampleTrajectory(w, 0.5)->angleDeg - 280.0), 0.0,
      1e-6);
}

TEST(Trajectory, SumoAngleIsClockwiseFromNorth) {
  const glm::dvec2 north = forwardFromSumoAngle(0.0), east = forwardFromSumoAngle(90.0);
  const glm::dvec2 south = forwardFromSumoAngle(180.0), west = forwardFromSumoAngle(270.0);
  EXPECT_NEAR(north.x, 0.0, 1e-12);
  EXPECT_NEAR(north.y, 1.0, 1e-12);
  EXPECT_NEAR(east.x, 1.0, 1e-12);
  EXPECT_NEAR(east.y, 0.0, 1e-12);
  EXPECT_NEAR(south.y, -1.0, 1e-12);
  EXPECT_NEAR(west.x, -1.0, 1e-12);
  const glm::dvec2 ne = forwardFromSumoAngle(45.0);
  EXPECT_NEAR(ne.x, std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(ne.y, std::sqrt(0.5), 1e-12);
}

}  // namespace
}  // namespace hv
