#include "hv/io/native/sumo_fcd.h"

#include "hv/io/native/scene_loader.h"
#include "hv/traffic/trajectories.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

// Two steps of a passenger car (SUMO's default: 5 m long) driving east, then a bus heading north.
const char* kFcd = R"(<?xml version="1.0" encoding="UTF-8"?>
<fcd-export xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance">
    <timestep time="0.00">
        <vehicle id="0" x="102.50" y="50.00" angle="90.00" type="DEFAULT_VEHTYPE" speed="0.00" pos="5.10" lane="a_0" slope="0.00"/>
    </timestep>
    <timestep time="1.00">
        <vehicle id="0" x="112.50" y="50.00" angle="90.00" type="DEFAULT_VEHTYPE" speed="10.00" pos="15.10" lane="a_0" slope="0.00"/>
        <vehicle id="bus1" x="0.00" y="20.00" angle="0.00" type="bus" speed="5.00" pos="12.00" lane="b_0" slope="0.00"/>
        <person id="p" x="1" y="2" angle="0"/>
    </timestep>
</fcd-export>
)";

TEST(SumoFcd, FrontBumperBecomesTheCentre) {
  Diagnostics diag;
  const Trajectories t = parseSumoFcd(kFcd, "fcd.xml", diag);
  EXPECT_TRUE(diag.warnings.empty());
  ASSERT_EQ(t.vehicles.size(), 2u);
  const Trajectory& car = t.vehicles[0];
  EXPECT_EQ(car.id, "0");
  ASSERT_EQ(car.samples.size(), 2u);
  // Heading east (90 degrees), 5 m long: the centre is 2.5 m west of the front bumper.
  EXPECT_NEAR(car.samples[0].xy.x, 100.0, 1e-9);
  EXPECT_NEAR(car.samples[0].xy.y, 50.0, 1e-9);
  EXPECT_NEAR(car.samples[1].xy.x, 110.0, 1e-9);
  EXPECT_EQ(car.samples[1].angleDeg, 90.0);
  // The 12 m bus heading north: 6 m south of its bumper.
  const Trajectory& bus = t.vehicles[1];
  EXPECT_NEAR(bus.samples[0].xy.x, 0.0, 1e-9);
  EXPECT_NEAR(bus.samples[0].xy.y, 14.0, 1e-9);
  EXPECT_EQ(bus.size.length, 12.0);
  EXPECT_EQ(t.tBegin, 0.0);
  EXPECT_EQ(t.tEnd, 1.0);
}

TEST(SumoFcd, BrokenFilesNameFileLineAndAttribute) {
  Diagnostics diag;
  const auto message = [&](const std::string& text) {
    try {
      parseSumoFcd(text, "fcd.xml", diag);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const std::string badY = message(
      "<fcd-export>\n<timestep time=\"0\">\n<vehicle id=\"v\" x=\"1\" y=\"north\" angle=\"0\"/>\n"
      "</timestep></fcd-export>");
  EXPECT_NE(badY.find("fcd.xml: line 3: vehicle 'v': attribute 'y': expected a finite number, got 'north'"),
            std::string::npos)
      << badY;
  const std::string noAngle =
      message("<fcd-export><timestep time=\"0\"><vehicle id=\"v\" x=\"1\" y=\"2\"/></timestep></fcd-export>");
  EXPECT_NE(noAngle.find("fcd.xml: line 1: vehicle 'v': attribute 'angle': missing"), std::string::npos) << noAngle;
  const std::string noTime = message("<fcd-export>\n\n<timestep/></fcd-export>");
  EXPECT_NE(noTime.find("fcd.xml: line 3: timestep: attribute 'time': missing"), std::string::npos) << noTime;
  const std::string root = message("<routes/>");
  EXPECT_NE(root.find("fcd.xml: expected SUMO floating car data"), std::string::npos) << root;
  const std::string truncated = message("<fcd-export>\n<timestep time=\"0\">\n<vehicle id=");
  EXPECT_NE(truncated.find("fcd.xml: line 3: not well-formed XML"), std::string::npos) << truncated;
}

class TrafficScene : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_traffic_scene_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream((dir_ / name).string()) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

// scene.json "traffic": the FCD's network coordinates moved by `offset` into the scene frame.
TEST_F(TrafficScene, FcdWithAnOffset) {
  write("fcd.xml", kFcd);
  Diagnostics diag;
  const Scene s = loadScene(
      write("scene.json", R"({"terrain": {"height": 0}, "traffic": {"fcd": "fcd.xml", "offset": [651000, 6862000]}})"),
      diag);
  ASSERT_TRUE(diag.ok()) << diag.errors.front();
  ASSERT_NE(s.traffic, nullptr);
  ASSERT_EQ(s.traffic->vehicles.size(), 2u);
  EXPECT_NEAR(s.traffic->vehicles[0].samples[0].xy.x, 651100.0, 1e-6);
  EXPECT_NEAR(s.traffic->vehicles[0].samples[0].xy.y, 6862050.0, 1e-6);
  EXPECT_EQ(s.trafficPath, (dir_ / "fcd.xml").string());
}

// CSV trajectories in WGS 84 into a Lambert-93 scene: positions through PROJ, and the heading of a
// car driving north along a meridian turns by the meridian convergence (Lambert-93's grid north
// is not true north away from its central meridian, 3 degrees east).
TEST_F(TrafficScene, CsvInAnotherCrsIsGeoreferenced) {
  write("t.csv", "t,id,x,y,angle,type\n0,a,2.0,48.8,0,car\n1,a,2.0,48.8001,0,car\n");
  Diagnostics diag;
  const Scene s =
      loadScene(write("scene.json", R"({"crs": "EPSG:2154", "traffic": {"csv": "t.csv", "crs": "OGC:CRS84"}})"), diag);
  ASSERT_NE(s.traffic, nullptr) << (diag.errors.empty() ? "" : diag.errors.front());
  const Trajectory& a = s.traffic->vehicles[0];
  // Lambert-93 (conformal conic, GRS 80, parallels 44 and 49 N, origin 46.5 N 3 E, false origin
  // 700 000, 6 600 000) by Snyder's formulas (1987, eq. 15-1 to 15-10), computed apart.
  EXPECT_NEAR(a.samples[0].xy.x, 626548.519, 0.01);
  EXPECT_NEAR(a.samples[0].xy.y, 6856011.920, 0.01);
  // True north at 2 E is -n (lambda - lambda0) = +0.7256 degrees clockwise from grid north.
  EXPECT_NEAR(a.samples[0].angleDeg, 0.7256, 0.001);
  // And the heading agrees with the direction between the two projected samples.
  const glm::dvec2 d = a.samples[1].xy - a.samples[0].xy;
  EXPECT_NEAR(std::atan2(d.x, d.y) * 180.0 / M_PI, a.samples[0].angleDeg, 0.001);
}

TEST_F(TrafficScene, BrokenTrafficIsLeftOutWithAMessage) {
  Diagnostics diag;
  const Scene s = loadScene(write("scene.json", R"({"traffic": {"fcd": "fcd.xml", "csv": "t.csv"}})"), diag);
  EXPECT_EQ(s.traffic, nullptr);
  ASSERT_FALSE(diag.ok());
  EXPECT_NE(diag.errors[0].find("traffic: expected exactly one of"), std::string::npos) << diag.errors[0];
  Diagnostics diag2;
  loadScene(write("scene.json", R"({"traffic": {"fcd": "fcd.xml", "offset": [1]}})"), diag2);
  ASSERT_FALSE(diag2.ok());
  EXPECT_NE(diag2.errors[0].find("traffic.offset: expected [dx, dy]"), std::string::npos) << diag2.errors[0];
}

}  // namespace
}  // namespace hv
