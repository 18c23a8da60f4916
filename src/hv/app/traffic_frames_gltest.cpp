// GL test of the demo's traffic sequence (hv::app::writeTrafficFrames) on the synthetic street: the
// camera follows the one vehicle that drives through the whole sequence, from its own track behind
// it, and every frame shows it where it is at that frame's time on the traffic's clock.
#include "hv/app/traffic_frames.h"

#include "hv/image/image.h"
#include "hv/io/camera_path_json.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

namespace hv::app {
namespace {

using testing::kStreetOrigin;

Trajectory vehicle(const std::string& id, std::vector<TrajectorySample> samples) {
  Trajectory t;
  t.id = id;
  t.type = "passenger";
  t.size = vehicleSizeOf(t.type);
  t.samples = std::move(samples);
  return t;
}

class TrafficFramesGlTest : public testing::GlTest {};

TEST_F(TrafficFramesGlTest, FollowsTheVehicleThatDrivesThroughTheSequence) {
  Scene scene = testing::streetScene();
  const glm::dvec2 o(kStreetOrigin);
  auto traffic = std::make_shared<Trajectories>();
  // "parked" stands still ahead of "late", which drives east from x = -40 at 5 m/s; "late" starts
  // after the sequence's first frame.
  traffic->vehicles.push_back(
      vehicle("parked", {{0.0, o + glm::dvec2(0, 2), 90.0}, {20.0, o + glm::dvec2(0, 2), 90.0}}));
  traffic->vehicles.push_back(
      vehicle("east", {{0.0, o + glm::dvec2(-40, -2), 90.0}, {16.0, o + glm::dvec2(40, -2), 90.0}}));
  traffic->vehicles.push_back(
      vehicle("late", {{4.5, o + glm::dvec2(50, 2), 270.0}, {16.0, o + glm::dvec2(-40, 2), 270.0}}));
  traffic->tEnd = 20.0;
  scene.traffic = traffic;

  TrafficFramesOptions opt;
  opt.frames = 4;
  opt.fps = 2.0;
  opt.start = 4.0;
  opt.width = 96;
  opt.height = 72;
  const MeshTerrainHeight terrain(scene.terrain);
  const TrafficChase chase = trafficChase(*traffic, terrain, opt);
  EXPECT_EQ(chase.vehicle, "east");
  EXPECT_EQ(chase.othersInView, 4);  // "parked", ahead in every frame
  ASSERT_EQ(chase.keys.size(), 4u);

  render::RenderSettings settings;
  settings.depthSize = 256;
  Diagnostics diag;
  render::Renderer renderer(scene, settings, diag);
  const std::string dir = testing::makeTempDir("traffic-frames");
  EXPECT_EQ(writeTrafficFrames(renderer, *traffic, terrain, opt, dir), 4);

  const CameraPath path = readCameraPath(dir + "/path.json", diag);
  ASSERT_EQ(path.keys().size(), 4u);
  render::RenderSettings none = settings;
  none.traffic.enabled = false;
  render::Renderer empty(scene, none, diag);
  for (int i = 0; i < 4; ++i) {
    const PathKey& key = path.keys()[size_t(i)];
    EXPECT_DOUBLE_EQ(key.time, i / opt.fps);
    // "east" at the frame's time, 14 m ahead of the eye on its track, 4.5 m below it.
    const double x = -40.0 + 5.0 * (opt.start + i / opt.fps);
    const glm::dvec3 eye = glm::dvec3(o + glm::dvec2(x - opt.behind, -2.0), kStreetOrigin.z + opt.eyeHeight);
    EXPECT_NEAR(glm::length(key.camera.center - eye), 0.0, 1e-6) << i;
    // The frame shows it there: its body differs from the empty street.
    const Image8 frame = readImage(dir + "/frames/" + frameId(i) + ".png", 3);
    ASSERT_EQ(frame.width, 96);
    const Image8 street = rgbOf(empty.render(key.camera).rgba);
    const Projection p = key.camera.project(glm::dvec3(o + glm::dvec2(x, -2.0), kStreetOrigin.z + 0.8));
    ASSERT_TRUE(p.inImage);
    const size_t at = (size_t(p.pxIdeal.y) * 96 + size_t(p.pxIdeal.x)) * 3;
    int diff = 0;
    for (int k = 0; k < 3; ++k) diff = std::max(diff, std::abs(int(frame.data[at + k]) - int(street.data[at + k])));
    EXPECT_GT(diff, 10) << "frame " << i << ": no vehicle at (" << p.pxIdeal.x << ", " << p.pxIdeal.y << ")";
  }
  EXPECT_TRUE(diag.ok());
}

TEST_F(TrafficFramesGlTest, NoVehicleThroughTheWholeSequenceWritesNothing) {
  Scene scene = testing::streetScene();
  const glm::dvec2 o(kStreetOrigin);
  Trajectories traffic;
  traffic.vehicles.push_back(
      vehicle("short", {{0.0, o + glm::dvec2(-40, -2), 90.0}, {3.0, o + glm::dvec2(-25, -2), 90.0}}));
  TrafficFramesOptions opt;
  opt.frames = 4;
  opt.fps = 1.0;  // 2 to 5 s: "short" is gone at 3 s
  opt.start = 2.0;
  Diagnostics diag;
  render::Renderer renderer(scene, render::RenderSettings{}, diag);
  const std::string dir = testing::makeTempDir("traffic-frames-none");
  EXPECT_EQ(writeTrafficFrames(renderer, traffic, MeshTerrainHeight(scene.terrain), opt, dir), 0);
  EXPECT_FALSE(std::filesystem::exists(dir + "/frames"));
}

}  // namespace
}  // namespace hv::app
