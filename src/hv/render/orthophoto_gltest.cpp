// The orthophoto draped on untextured terrain (de Castro & Brédif 2022's terrain texture;
// shaders/ibr_shade.frag), on llvmpipe, against its CPU twin: where no photograph covers the
// terrain, the pixel is hv::sampleOrthophoto at the surface point an exact ray cast finds; the
// buildings and the scene.json mesh stay shaded (render/untextured.h), and so does the terrain off
// the orthophoto and with the setting off.
#include "hv/render/renderer.h"

#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/render/untextured.h"
#include "hv/scene/native/raycast.h"
#include "hv/scene/orthophoto.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>

namespace hv::render {
namespace {

using testing::kStreetOrigin;

class OrthophotoGlTest : public testing::GlTest {};

glm::dvec3 pixelColour(const Image8& img, int x, int y) {
  return glm::dvec3(img.at(x, y, 0), img.at(x, y, 1), img.at(x, y, 2)) / 255.0;
}

// 160 x 120 texels of 0.5 m over x in [o.x - 40, o.x + 40], y in [o.y - 20, o.y + 40]: red grows
// one step a texel eastwards, green one a texel southwards (row 0 the northern edge), so that a
// bilinear lookup is exact and a misplaced sample shows as a wrong value.
std::shared_ptr<Orthophoto> gradientOrthophoto(const glm::dvec3& o) {
  auto p = std::make_shared<Orthophoto>();
  p->path = "gradient";
  p->width = 160;
  p->height = 120;
  p->minX = o.x - 40, p->maxX = o.x + 40, p->minY = o.y - 20, p->maxY = o.y + 40;
  p->rgba.resize(std::size_t(p->width) * p->height * 4);
  for (int y = 0; y < p->height; ++y)
    for (int x = 0; x < p->width; ++x) {
      std::uint8_t* t = &p->rgba[(std::size_t(y) * p->width + x) * 4];
      t[0] = std::uint8_t(40 + x), t[1] = std::uint8_t(10 + y), t[2] = 200, t[3] = 255;
    }
  return p;
}

// What the ray through a pixel's centre hits first: terrain, or something else (a building, the
// mesh), and where; `robust` false when a neighbour ray 1.5 px away hits another kind or nothing.
struct Seen {
  bool hit = false, terrain = false, robust = true;
  glm::dvec3 point{0.0}, normal{0.0, 0.0, 1.0};
};

Seen castPixel(const RayCaster& terrain, const RayCaster& others, const Camera& view, glm::dvec2 px) {
  auto kind = [&](glm::dvec2 p, Seen& s) {
    const glm::dvec3 dir = view.rayDirection(p);
    const auto t = terrain.intersect(view.center, dir, 0.0, 1e9);
    const auto b = others.intersect(view.center, dir, 0.0, 1e9);
    s.hit = t || b;
    s.terrain = t && (!b || t->t < b->t);
    const auto& h = s.terrain ? t : b;
    if (h) {
      s.point = h->position;
      s.normal = glm::dot(h->normal, dir) > 0.0 ? -h->normal : h->normal;
    }
  };
  Seen s;
  kind(px, s);
  for (glm::dvec2 off : {glm::dvec2(1.5, 0), glm::dvec2(-1.5, 0), glm::dvec2(0, 1.5), glm::dvec2(0, -1.5)}) {
    Seen n;
    kind(px + off, n);
    if (n.hit != s.hit || n.terrain != s.terrain || glm::dot(n.normal, s.normal) < 0.999) s.robust = false;
  }
  return s;
}

// 8-bit RMS difference over the channels.
double steps(const glm::dvec3& a, const glm::dvec3& b) { return glm::length(a - b) / std::sqrt(3.0) * 255.0; }

TEST_F(OrthophotoGlTest, UntexturedTerrainShowsTheOrthophotoAndTheRestStaysShaded) {
  Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  // The scene.json mesh: a low box east of the street, which is not terrain.
  Footprint f;
  f.id = "mesh";
  f.rings = {{{o.x + 12, o.y + 0}, {o.x + 18, o.y + 0}, {o.x + 18, o.y + 6}, {o.x + 12, o.y + 6}}};
  scene.mesh = extrudeLod1(f, o.z, o.z + 3);
  // One pure-red photograph of the near building only: covered pixels are the photograph's.
  const std::string dir = testing::makeTempDir("orthophoto");
  Photo p;
  p.camera = testing::lookAt("red", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 10, 6), 64, 64, 200);
  p.imagePath = dir + "/red.png";
  writePng(p.imagePath, testing::solidImage(64, 64, 255, 0, 0));
  scene.photos.push_back(p);
  const std::shared_ptr<Orthophoto> ortho = gradientOrthophoto(o);

  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 256;
  Renderer renderer(scene, settings, diag);
  renderer.setOrthophoto(ortho);
  // From above and south, looking north-down: ground on and off the orthophoto, both buildings,
  // the mesh box.
  const Camera view = testing::lookAt("v", o + glm::dvec3(0, -38, 34), o + glm::dvec3(0, 12, 0), 160, 120, 110);
  const RenderOutput out = renderer.render(view);
  ASSERT_TRUE(diag.ok());
  ASSERT_EQ(out.rgba.width, 160);

  const RayCaster terrainCaster(scene.terrain);
  Mesh othersMesh = scene.buildings;
  othersMesh.append(scene.mesh);
  const RayCaster others(othersMesh);

  int draped = 0, shadedOff = 0, shadedOther = 0, covered = 0;
  double maxDraped = 0.0, maxShaded = 0.0;
  for (int y = 0; y < view.height; y += 2)
    for (int x = 0; x < view.width; x += 2) {
      if (out.rgba.at(x, y, 3) > 0) {
        ++covered;  // the red photograph's
        continue;
      }
      const Seen s = castPixel(terrainCaster, others, view, {x + 0.5, y + 0.5});
      if (!s.hit || !s.robust) continue;
      const glm::dvec3 got = pixelColour(out.rgba, x, y);
      const glm::dvec2 uv = orthophotoTexCoord(*ortho, s.point.x, s.point.y);
      // A texel from the orthophoto's edge: inside, and away from the clamped border.
      const double margin = 2.0 / ortho->width;
      const bool inside = uv.x > margin && uv.x < 1.0 - margin && uv.y > margin && uv.y < 1.0 - margin;
      const bool outside = uv.x < -margin || uv.x > 1.0 + margin || uv.y < -margin || uv.y > 1.0 + margin;
      if (s.terrain && inside) {
        const glm::dvec3 want = glm::dvec3(sampleOrthophoto(*ortho, uv));
        const double e = steps(got, want);
        // Tolerance: 8-bit rounding plus the point rebuilt from the float view depth (a few
        // millimetres at this range, hundredths of a texel on a gradient of a step per texel).
        EXPECT_LT(e, 1.5) << "terrain pixel " << x << "," << y << ": got " << got.r * 255 << "," << got.g * 255 << ","
                          << got.b * 255 << " want " << want.r * 255 << "," << want.g * 255 << "," << want.b * 255;
        maxDraped = std::max(maxDraped, e);
        ++draped;
      } else if (!s.terrain || outside) {
        const glm::dvec3 want = shadeUntextured(s.normal, scene.up, settings.untextured);
        const double e = steps(got, want);
        EXPECT_LT(e, 1.5) << (s.terrain ? "terrain off the orthophoto" : "building or mesh") << " pixel " << x << ","
                          << y;
        maxShaded = std::max(maxShaded, e);
        ++(s.terrain ? shadedOff : shadedOther);
      }
    }
  std::cout << "[ orthophoto ] " << draped << " draped terrain pixels (largest error " << maxDraped << " steps), "
            << shadedOff << " terrain pixels off it and " << shadedOther
            << " building or mesh pixels shaded (largest error " << maxShaded << "), " << covered
            << " covered by the photograph\n";
  EXPECT_GT(draped, 1000);
  EXPECT_GT(shadedOff, 50);
  EXPECT_GT(shadedOther, 100);
  EXPECT_GT(covered, 20);

  // A known texel at a known world point: texel (100, 30)'s centre is world (o.x + 10.25,
  // o.y + 24.75) on the ground; where it lands in the view, the render shows that texel's colour.
  const glm::dvec3 world(o.x - 40 + 100.5 * 0.5, o.y + 40 - 30.5 * 0.5, o.z);
  const Projection px = view.project(world);
  ASSERT_TRUE(px.inImage);
  const int qx = int(std::floor(px.pxDistorted.x)), qy = int(std::floor(px.pxDistorted.y));
  ASSERT_TRUE(qx >= 0 && qx < view.width && qy >= 0 && qy < view.height);
  EXPECT_NEAR(out.rgba.at(qx, qy, 0), 140, 1);  // 40 + 100
  EXPECT_NEAR(out.rgba.at(qx, qy, 1), 40, 1);   // 10 + 30
  EXPECT_EQ(out.rgba.at(qx, qy, 2), 200);
  EXPECT_EQ(out.rgba.at(qx, qy, 3), 0);  // not coverage: no photograph there

  // Live: the setting off, the same pixel is the shaded ground again.
  renderer.settings().untextured.orthophoto = false;
  const RenderOutput off = renderer.render(view);
  const glm::dvec3 shaded = shadeUntextured(scene.up, scene.up, settings.untextured);
  EXPECT_LT(steps(pixelColour(off.rgba, qx, qy), shaded), 1.5);
}

}  // namespace
}  // namespace hv::render
