#include "hv/viewer/view_state.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace hv::viewer {
namespace {

TEST(ViewState, PoseRoundTripProjectsPointsWhereTheCameraDid) {
  // A camera in Lambert-93 coordinates (millions of metres), looking down a street.
  const glm::dvec3 eye(651234.5678, 6862345.1234, 41.7), target(651260.0, 6862400.0, 35.0);
  const double focal = 270.0 / std::tan(30.0 * M_PI / 180.0);  // a 60 degree vertical field of view at 540 px
  const Camera cam = lookAtCamera("v", eye, target, 960, 540, focal);
  const CameraPose pose = poseOf(cam);
  EXPECT_NEAR(pose.fovYDeg, 60.0, 1e-9);

  const ViewState in{pose, {{"from", "1900"}, {"to", "1920-06"}, {"time", "12.5"}, {"k", "4"}}};
  const std::string query = encodeViewState(in);
  const ViewState out = decodeViewState("?" + query);
  ASSERT_TRUE(out.pose);
  EXPECT_EQ(out.params, in.params);

  const Camera back = cameraAt(*out.pose, 960, 540);
  EXPECT_NEAR(glm::distance(back.center, eye), 0.0, 1e-4);  // 0.1 mm in the link
  EXPECT_NEAR(back.focal.y, focal, 1e-4);
  for (const glm::dvec3& p : {target, glm::dvec3(651240.0, 6862380.0, 30.0), glm::dvec3(651300.0, 6862500.0, 60.0)}) {
    const auto a = cam.project(p), b = back.project(p);
    EXPECT_NEAR(a.pxIdeal.x, b.pxIdeal.x, 0.01) << "the same world point lands on the same pixel";
    EXPECT_NEAR(a.pxIdeal.y, b.pxIdeal.y, 0.01);
  }
  // At another window size the view keeps its field of view: the principal point at the new centre.
  const Camera half = cameraAt(*out.pose, 480, 270);
  EXPECT_NEAR(half.focal.y, focal / 2.0, 1e-4);
  EXPECT_NEAR(half.project(target).pxIdeal.x, cam.project(target).pxIdeal.x / 2.0, 0.01);
}

TEST(ViewState, KnownTextAndEscapes) {
  CameraPose p;
  p.center = {1.0, -2.5, 3.0};
  p.fovYDeg = 45.0;
  EXPECT_EQ(formatPose(p), "1.0000,-2.5000,3.0000,1.00000000,0.00000000,0.00000000,0.00000000,45.000000");
  ViewState s{p, {{"exclude", "a b&c=d"}, {"from", "1900"}}};
  EXPECT_EQ(encodeViewState(s),
            "pose=1.0000,-2.5000,3.0000,1.00000000,0.00000000,0.00000000,0.00000000,45.000000"
            "&exclude=a%20b%26c%3Dd&from=1900");
  const ViewState d = decodeViewState("from=1900&&exclude=a+b%26c%3dd&flag&from=1910");
  EXPECT_FALSE(d.pose);
  ASSERT_EQ(d.params.size(), 3u);
  EXPECT_EQ(d.params[0], (std::pair<std::string, std::string>("from", "1910")));  // the last of a repeated name
  EXPECT_EQ(d.params[1].second, "a b&c=d");
  EXPECT_EQ(d.params[2], (std::pair<std::string, std::string>("flag", "")));
  EXPECT_TRUE(decodeViewState("").params.empty());
}

TEST(ViewState, BadPosesAndEscapesAreNamed) {
  auto message = [](const std::string& q) {
    try {
      decodeViewState(q);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("pose=1,2,3").find("pose: expected eight numbers"), std::string::npos);
  EXPECT_NE(message("pose=1,2,3,1,0,0,0,north").find("got '1,2,3,1,0,0,0,north'"), std::string::npos);
  EXPECT_NE(message("pose=1,2,3,0,0,0,0,60").find("quaternion is zero"), std::string::npos);
  EXPECT_NE(message("pose=1,2,3,1,0,0,0,180").find("field of view"), std::string::npos);
  EXPECT_NE(message("pose=1,2,3,1,0,0,0,60,7").find("expected eight numbers"), std::string::npos);
  EXPECT_NE(message("from=19%2").find("from: expected two hexadecimal digits"), std::string::npos);
  EXPECT_NE(message("pose=nan,2,3,1,0,0,0,60").find("expected eight numbers"), std::string::npos);
}

}  // namespace
}  // namespace hv::viewer
