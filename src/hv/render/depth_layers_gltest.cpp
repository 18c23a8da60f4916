// The depth-map array allocated lazily (render/gl/gl_backend.h): a renderer over 64 photographs
// whose first view needs 4 of them allocates a few layers, grows as more slots are drawn, and
// gives the same pictures, frame by frame, as one whose array is allocated whole at start. The
// frame is run as Renderer::render runs it, so that the backend's layers can be read.
#include "hv/image/native/png_write.h"
#include "hv/render/frame_builder.h"
#include "hv/render/gl/gl_backend.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace hv::render {
namespace {

constexpr int kSide = 8;  // 8 x 8 patches of 1 m on a wall: 64 photographs, one per patch

Scene wallScene(const std::string& dir) {
  const glm::dvec3 o = testing::kStreetOrigin;
  Scene scene;
  scene.origin = o;
  scene.buildings.positions = {o + glm::dvec3(0, 10, 0), o + glm::dvec3(kSide, 10, 0), o + glm::dvec3(kSide, 10, kSide),
                               o + glm::dvec3(0, 10, kSide)};
  scene.buildings.triangles = {{0, 2, 1}, {0, 3, 2}};
  for (int i = 0; i < kSide * kSide; ++i) {
    const glm::dvec3 c = o + glm::dvec3(i % kSide + 0.5, 10, i / kSide + 0.5);
    Photo p;
    // 1 m in front of its patch, seeing 0.8 m of it.
    p.camera = testing::lookAt("p" + std::to_string(i), c - glm::dvec3(0, 1, 0), c, 4, 4, 5.0);
    p.imagePath = dir + "/" + p.camera.id + ".png";
    writePng(p.imagePath, testing::solidImage(4, 4, std::uint8_t(20 + 3 * i), std::uint8_t(250 - 3 * i), 90));
    scene.photos.push_back(p);
  }
  return scene;
}

// Renderer::render's frame, on a backend whose depth-map layers the test reads.
struct Rig {
  gl::GlBackend backend;
  FrameBuilder builder;
  Rig(const Scene& scene, const RenderSettings& settings, Diagnostics& diag)
      : backend(diag), builder(scene, settings, diag, backend) {}
  RenderOutput render(const Camera& view, FrameMode mode = FrameMode::Batch) {
    const Frame frame = builder.build(view, mode, false);
    ViewPassStats passStats;
    RenderOutput out = backend.runViewPasses(frame, passStats);
    builder.viewPassesDone(frame, passStats);
    return out;
  }
  int layers() const { return backend.depthLayers(); }
};

TEST(DepthLayersGlTest, AllocatedAsSlotsAreFirstDrawnWithTheSamePictures) {
  testing::glContext();
  gpu::clearGlErrors();
  const glm::dvec3 o = testing::kStreetOrigin;
  const Scene scene = wallScene(testing::makeTempDir("depth-layers"));
  RenderSettings s;
  s.blend.k = 64;
  s.blend.sigma = 100.0;
  s.depthSize = 16;
  s.maxSlices = 64;
  s.depthMapsPerFrame = 12;
  RenderSettings eagerSettings = s;
  // Per slot: the 4 x 4 slice's mip chain (16 + 4 + 1 texels) and a 16 x 16 depth map. A budget
  // that holds the 64 slots but not a growth's second array: the depth maps are allocated whole.
  const std::size_t perSlot = (16 + 4 + 1) * 4 + 16 * 16 * 4;
  eagerSettings.memoryBudgetBytes = 64 * perSlot;
  Diagnostics diag;
  Rig lazy(scene, s, diag), eager(scene, eagerSettings, diag);
  ASSERT_EQ(lazy.builder.slotCount(), 64);
  ASSERT_EQ(eager.builder.slotCount(), 64);
  EXPECT_EQ(lazy.layers(), 8);
  EXPECT_EQ(eager.layers(), 64);
  EXPECT_EQ(lazy.builder.stats().sliceBytes, 64 * perSlot);  // what they may come to, within the budget

  // A view of the 2 x 2 patches at the wall's corner (sees 1.9 m of them from 2 m): 4 photographs.
  const Camera corner =
      testing::lookAt("corner", o + glm::dvec3(1, 8, 1), o + glm::dvec3(1, 10, 1), 64, 64, 64.0 * 2.0 / 1.9);
  // The whole wall from 10 m: every photograph.
  const Camera whole = testing::lookAt("whole", o + glm::dvec3(4, 0, 4), o + glm::dvec3(4, 10, 4), 96, 96, 96.0);

  // Progressive frames until converged on the corner, then on the whole wall: the maps drawn for
  // the corner are copied each time the array grows, and the converged pictures equal the eager
  // one's. (Frames before convergence depend on when the decodes end, not compared.)
  int frames = 0;
  auto converge = [&](const Camera& view) {
    RenderOutput a, b;
    for (int i = 0; i < 200 && !(i > 0 && lazy.builder.converged()); ++i, ++frames)
      a = lazy.render(view, FrameMode::Progressive);
    for (int i = 0; i < 200 && !(i > 0 && eager.builder.converged()); ++i)
      b = eager.render(view, FrameMode::Progressive);
    EXPECT_TRUE(lazy.builder.converged() && eager.builder.converged()) << view.id;
    EXPECT_EQ(a.rgba.data, b.rgba.data) << view.id << ": converged pictures differ";
    return a.rgba.data;
  };
  const std::vector<std::uint8_t> cornerPicture = converge(corner);
  EXPECT_EQ(lazy.builder.lastPlan().images.size(), 4u);
  EXPECT_EQ(lazy.layers(), 8) << "4 maps drawn: no growth";
  // The corner is textured: 4 photographs of distinct colours.
  int covered = 0;
  for (std::size_t i = 3; i < cornerPicture.size(); i += 4) covered += cornerPicture[i] == 255;
  EXPECT_GT(covered, 64 * 64 / 2);

  converge(whole);
  EXPECT_EQ(lazy.builder.lastPlan().images.size(), 64u);
  EXPECT_EQ(lazy.layers(), 64);
  // Back to the corner: its maps (copied three times) are still current and still right.
  EXPECT_EQ(converge(corner), cornerPicture);

  // A batch frame of a fresh lazy renderer on the whole wall: grown within one frame.
  Rig fresh(scene, s, diag);
  EXPECT_EQ(fresh.render(whole).rgba.data, eager.render(whole).rgba.data);
  EXPECT_EQ(fresh.layers(), 64);
  EXPECT_GT(frames, 4);
  EXPECT_TRUE(diag.ok());
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

}  // namespace
}  // namespace hv::render
