// GL test of `histoview fly` as a library function (hv::app::flyPath): a 3-key path over the
// synthetic street with two photographs, rendered converged and progressively; the progressive
// sequence must start incomplete and, once its depth maps are current, equal the converged frames.
#include "hv/app/fly_command.h"

#include "hv/camera/camera_path.h"
#include "hv/image/image.h"
#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/traffic/trajectories.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

namespace hv::app {
namespace {

using testing::kStreetOrigin;

class FlyGlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::glContext();
    gpu::clearGlErrors();
    dir_ = testing::makeTempDir("fly");
    scene_ = testing::streetScene();
    const glm::dvec3 o = kStreetOrigin;
    addPhoto(testing::lookAt("a", o + glm::dvec3(-4, -12, 2), o + glm::dvec3(0, 30, 8), 96, 72, 80), 1);
    addPhoto(testing::lookAt("b", o + glm::dvec3(5, -10, 1.8), o + glm::dvec3(-2, 32, 6), 96, 72, 80), 2);
    // Three keys walking up the street, turning a little; 1 s then 0.5 s apart.
    path_ = std::make_unique<CameraPath>(std::vector<PathKey>{
        {testing::lookAt("k0", o + glm::dvec3(-2, -14, 2), o + glm::dvec3(0, 30, 8), 64, 48, 52), 0.0},
        {testing::lookAt("k1", o + glm::dvec3(0, -12, 2.2), o + glm::dvec3(2, 30, 9), 64, 48, 56), 1.0},
        {testing::lookAt("k2", o + glm::dvec3(2, -11, 2), o + glm::dvec3(-1, 32, 8), 64, 48, 56), 1.5}});
    settings_.blend.k = 2;
    settings_.blend.sigma = 5.0;
    settings_.depthSize = 256;
    settings_.depthMapsPerFrame = 1;  // two images: the first progressive frame lacks one
    // Decode on the calling thread: poll() then delivers exactly one image per frame, so the
    // progressive sequence is deterministic (worker threads would make it depend on timing).
    settings_.decodeThreads = 0;
  }
  void TearDown() override { EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << "a GL error was left behind"; }

  void addPhoto(const Camera& cam, int seed) {
    Photo p;
    p.camera = cam;
    p.imagePath = dir_ + "/" + cam.id + ".png";
    writePng(p.imagePath, testing::patternImage(cam.width, cam.height, seed));
    scene_.photos.push_back(p);
  }

  std::string dir_;
  Scene scene_;
  std::unique_ptr<CameraPath> path_;
  render::RenderSettings settings_;
};

TEST_F(FlyGlTest, ProgressiveFramesReachTheConvergedFrames) {
  const std::vector<Camera> frames = pathFrames(*path_, 4.0);
  ASSERT_EQ(frames.size(), 7u);  // floor(1.5 * 4) + 1

  Diagnostics diag;
  std::vector<FlyFrame> batchReports, progressiveReports;
  {
    render::Renderer batch(scene_, settings_, diag);
    const FlyResult r =
        flyPath(batch, frames, dir_ + "/batch", false, [&](const FlyFrame& f) { batchReports.push_back(f); });
    EXPECT_EQ(r.frames, 7);
    EXPECT_EQ(r.convergedFrames, 7);
  }
  {
    render::Renderer progressive(scene_, settings_, diag);
    const FlyResult r = flyPath(progressive, frames, dir_ + "/progressive", true,
                                [&](const FlyFrame& f) { progressiveReports.push_back(f); });
    EXPECT_EQ(r.frames, 7);
  }
  ASSERT_TRUE(diag.ok());
  ASSERT_EQ(batchReports.size(), 7u);
  ASSERT_EQ(progressiveReports.size(), 7u);
  // One depth map per frame and two images: the first frame waits for one, later ones do not.
  EXPECT_FALSE(progressiveReports[0].converged);
  EXPECT_EQ(progressiveReports[0].imagesWaiting, 1);
  int firstConverged = -1;
  for (size_t i = 0; i < frames.size(); ++i) {
    EXPECT_EQ(batchReports[i].file, dir_ + "/batch/" + frames[i].id + ".png");
    EXPECT_EQ(progressiveReports[i].index, int(i));
    EXPECT_EQ(progressiveReports[i].total, 7);
    ASSERT_TRUE(std::filesystem::is_regular_file(batchReports[i].file)) << batchReports[i].file;
    ASSERT_TRUE(std::filesystem::is_regular_file(progressiveReports[i].file)) << progressiveReports[i].file;
    if (firstConverged < 0 && progressiveReports[i].converged) firstConverged = int(i);
  }
  ASSERT_EQ(firstConverged, 1);
  for (size_t i = 0; i < frames.size(); ++i) {
    const Image8 b = readImage(batchReports[i].file);
    const Image8 p = readImage(progressiveReports[i].file);
    ASSERT_EQ(b.width, 64);
    ASSERT_EQ(b.height, 48);
    ASSERT_EQ(b.channels, 3);
    // Converged progressive frames are the batch frames, byte for byte; the first one, textured by
    // a single image, is not.
    if (int(i) >= firstConverged)
      EXPECT_EQ(p.data, b.data) << frames[i].id;
    else
      EXPECT_NE(p.data, b.data) << frames[i].id;
  }
  // The street is textured: most pixels of the converged frames are not background.
  const Image8 last = readImage(batchReports.back().file);
  int textured = 0;
  for (int y = 0; y < last.height; ++y)
    for (int x = 0; x < last.width; ++x)
      textured += last.at(x, y, 0) + last.at(x, y, 1) + last.at(x, y, 2) > 0;
  EXPECT_GT(textured, last.width * last.height / 2);
}

// A frame the renderer refuses (a view beyond MAX_TEXTURE_SIZE) is named and left out; the path
// goes on. Failures in a row end it.
TEST_F(FlyGlTest, AFailedFrameIsNamedAndThePathGoesOn) {
  const std::vector<Camera> frames = pathFrames(*path_, 4.0);
  Diagnostics diag;
  render::Renderer renderer(scene_, settings_, diag);
  auto huge = [&](int i) {
    Camera c = frames[size_t(i)];
    return c.resized(40000, 30000);
  };
  const FlyResult r = flyPath(
      renderer, int(frames.size()), [&](int i) { return i == 2 ? huge(i) : frames[size_t(i)]; }, dir_ + "/gap",
      false);
  EXPECT_EQ(r.frames, 6);
  ASSERT_EQ(r.failures.size(), 1u);
  EXPECT_NE(r.failures[0].find("frame '" + frames[2].id + "'"), std::string::npos) << r.failures[0];
  EXPECT_FALSE(r.gaveUp);
  EXPECT_FALSE(std::filesystem::exists(dir_ + "/gap/" + frames[2].id + ".png"));
  EXPECT_TRUE(std::filesystem::is_regular_file(dir_ + "/gap/" + frames[3].id + ".png"));

  const int count = kMaxConsecutiveFlyFailures + 3;
  const FlyResult all = flyPath(renderer, count, [&](int) { return huge(0); }, dir_ + "/none", false);
  EXPECT_EQ(all.frames, 0);
  EXPECT_EQ(int(all.failures.size()), kMaxConsecutiveFlyFailures);
  EXPECT_TRUE(all.gaveUp);
}

TEST(FlyCommand, ProgressLineAndFfmpegArguments) {
  FlyFrame f;
  f.index = 11;
  f.total = 100;
  f.elapsedMs = 12 * 85.0;
  const std::string line = progressLine(f);
  EXPECT_EQ(line.front(), '\r');
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_NE(line.find("frame 12/100"), std::string::npos) << line;
  EXPECT_NE(line.find(" 12%"), std::string::npos) << line;
  EXPECT_NE(line.find("85 ms/frame"), std::string::npos) << line;
  EXPECT_NE(line.find("ETA 0:07"), std::string::npos) << line;  // 88 frames * 85 ms = 7.48 s

  const auto args = ffmpegArguments("ffmpeg", "out", 25, 51, "fly.mp4");
  const std::vector<std::string> expected{"ffmpeg",
                                          "-hide_banner",
                                          "-loglevel",
                                          "error",
                                          "-y",
                                          "-framerate",
                                          "25",
                                          "-i",
                                          "out/f%05d.png",
                                          "-frames:v",
                                          "51",
                                          "-vf",
                                          "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                                          "-pix_fmt",
                                          "yuv420p",
                                          "fly.mp4"};
  EXPECT_EQ(args, expected);
  EXPECT_FALSE(findOnPath("sh").empty());
  EXPECT_TRUE(findOnPath("histoview-no-such-program").empty());
}

// fly with the traffic's clock: a car driving up the street, the camera standing still on a
// two-key path flown at 1 fps. Frame i is rendered at --time + time-scale * i / fps (here 2 s and
// 5 s): each frame is the picture rendered directly at its time, and the car has moved between
// the two.
TEST_F(FlyGlTest, VehiclesMoveWithThePathsClock) {
  const glm::dvec3 o = kStreetOrigin;
  auto traffic = std::make_shared<Trajectories>();
  Trajectory car;
  car.id = "car0";
  car.type = "passenger";
  car.size = vehicleSizeOf("passenger");
  car.samples = {{0.0, glm::dvec2(o) + glm::dvec2(1.5, -4.0), 0.0}, {10.0, glm::dvec2(o) + glm::dvec2(1.5, 8.0), 0.0}};
  traffic->vehicles.push_back(car);
  traffic->tEnd = 10.0;
  scene_.traffic = traffic;
  const Camera cam = testing::lookAt("k", o + glm::dvec3(-3, -16, 4), o + glm::dvec3(1, 10, 0), 64, 48, 52);
  const CameraPath still(std::vector<PathKey>{{cam, 0.0}, {cam, 1.0}});
  const std::vector<Camera> frames = pathFrames(still, 1.0);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_DOUBLE_EQ(flyTrafficTime(1, 1.0, 2.0, 3.0), 5.0);
  EXPECT_DOUBLE_EQ(flyTrafficTime(4, 2.0, 2.0, 0.0), 2.0);

  Diagnostics diag;
  render::Renderer renderer(scene_, settings_, diag);
  const FlyResult r = flyPath(
      renderer, 2, [&](int i) { return frames[size_t(i)]; }, dir_ + "/traffic", false, {},
      [](int i) { return flyTrafficTime(i, 1.0, 2.0, 3.0); });
  ASSERT_EQ(r.frames, 2);
  const Image8 f0 = readImage(dir_ + "/traffic/" + frames[0].id + ".png");
  const Image8 f1 = readImage(dir_ + "/traffic/" + frames[1].id + ".png");
  // The same pictures rendered directly at 2 s and 5 s, and the empty street.
  auto at = [&](double t, bool enabled) {
    render::Renderer direct(scene_, settings_, diag);
    direct.settings().traffic.time = t;
    direct.settings().traffic.enabled = enabled;
    return rgbOf(direct.render(cam).rgba);
  };
  const Image8 at2 = at(2.0, true), at5 = at(5.0, true), empty = at(2.0, false);
  EXPECT_EQ(f0.data, at2.data);
  EXPECT_EQ(f1.data, at5.data);
  // The car is in both frames, and not in the same place: pixels where one frame shows it and the
  // other the empty street.
  int onlyIn0 = 0, onlyIn1 = 0;
  for (std::size_t k = 0; k < f0.data.size(); k += 3) {
    const bool car0 =
        f0.data[k] != empty.data[k] || f0.data[k + 1] != empty.data[k + 1] || f0.data[k + 2] != empty.data[k + 2];
    const bool car1 =
        f1.data[k] != empty.data[k] || f1.data[k + 1] != empty.data[k + 1] || f1.data[k + 2] != empty.data[k + 2];
    onlyIn0 += car0 && !car1;
    onlyIn1 += car1 && !car0;
  }
  EXPECT_GT(onlyIn0, 10);
  EXPECT_GT(onlyIn1, 10);
}

}  // namespace
}  // namespace hv::app
