// GL test of geometry culling (render/geometry_tiles.h) on the demo city: the view and the depth
// maps drawn from the tiles their frustum may see equal, bit for bit, those drawn from every tile,
// and culling draws fewer tiles.
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

namespace hv::render {
namespace {

using testing::DemoCity;
using testing::demoCity;

class GeometryCullingGlTest : public testing::GlTest {};

TEST_F(GeometryCullingGlTest, CulledFramesAndDepthMapsEqualTheWholeOnes) {
  const DemoCity& city = demoCity();
  ASSERT_GE(city.views.size(), 2u);
  RenderSettings settings;
  settings.blend.k = 4;
  settings.depthSize = 256;
  settings.decodeThreads = 0;
  Diagnostics diag;
  RenderSettings whole = settings;
  whole.geometryCulling = false;
  Renderer culled(city.scene, settings, diag);
  Renderer all(city.scene, whole, diag);
  ASSERT_GT(culled.stats().geometryTiles, 4) << "the demo city should be cut into several tiles";

  for (size_t v = 0; v < 2; ++v) {
    const Camera view = city.views[v].camera.resized(320, 240);
    const RenderOutput a = culled.render(view);
    const RenderOutput b = all.render(view);
    ASSERT_EQ(a.rgba.data.size(), b.rgba.data.size());
    EXPECT_TRUE(a.rgba.data == b.rgba.data) << "view " << city.views[v].camera.id;
    // A street view sees part of the city: fewer tiles, for the view and for the depth maps.
    EXPECT_LT(culled.stats().tilesDrawn, all.stats().tilesDrawn) << city.views[v].camera.id;
    EXPECT_EQ(all.stats().tilesDrawn, all.stats().geometryTiles);
    EXPECT_GT(culled.stats().depthMapsThisFrame, 0);
    EXPECT_LT(culled.stats().depthMapTilesThisFrame, all.stats().depthMapTilesThisFrame);
  }

  // Each photograph's depth map, through the depth-map debug view (16-bit depths per pixel).
  for (size_t p : {size_t(0), city.scene.photos.size() / 2, city.scene.photos.size() - 1}) {
    RenderSettings s = settings;
    s.debug = {DebugView::DepthMap, int(p)};
    RenderSettings w = whole;
    w.debug = s.debug;
    Renderer rc(city.scene, s, diag), rw(city.scene, w, diag);
    const Camera view = city.views[0].camera.resized(256, 192);
    const RenderOutput a = rc.render(view);
    const RenderOutput b = rw.render(view);
    ASSERT_FALSE(a.debugValues.data.empty());
    EXPECT_TRUE(a.debugValues.data == b.debugValues.data) << "depth map of " << city.scene.photos[p].camera.id;
    int covered = 0;
    for (std::uint16_t d : a.debugValues.data) covered += d != 65535;
    EXPECT_GT(covered, int(a.debugValues.data.size() / 8)) << "the depth map shows geometry";
  }
  EXPECT_TRUE(diag.ok());
}

}  // namespace
}  // namespace hv::render
