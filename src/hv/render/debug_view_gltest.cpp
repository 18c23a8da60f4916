// GL tests of the viewer's live switches and debug views on llvmpipe: the colour ramp's
// GLSL twin, the weight view against the CPU reference shares (hv::ibr::referenceBlend), the
// depth-map view against ray casts from the photograph, frusta over the picture, and the geometry
// layers, lens distortion, masks and points switched between frames (with what each invalidates).
#include "hv/camera/frustum_outline.h"
#include "hv/gpu/shader_sources.h"
#include "hv/ibr/reference_blend.h"
#include "hv/ibr/slice_image.h"
#include "hv/image/colormap.h"
#include "hv/image/native/png_write.h"
#include "hv/scene/chunks.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/scene/native/lod1.h"
#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv::render {
namespace {

using testing::kStreetOrigin;

class DebugViewGlTest : public testing::PhotoGlTest {
 protected:
};

// A box building of the street scene's kind (hv::extrudeLod1 on a rectangle, metres from the origin).
Mesh box(double x0, double x1, double y0, double y1, double height) {
  const glm::dvec3 o = kStreetOrigin;
  Footprint f;
  f.id = "box";
  f.rings = {{{o.x + x0, o.y + y0}, {o.x + x1, o.y + y0}, {o.x + x1, o.y + y1}, {o.x + x0, o.y + y1}}};
  return extrudeLod1(f, o.z, o.z + height);
}

int differingPixels(const Image8& a, const Image8& b) {
  int n = 0;
  for (size_t i = 0; i < a.data.size(); i += 4)
    n += a.data[i] != b.data[i] || a.data[i + 1] != b.data[i + 1] || a.data[i + 2] != b.data[i + 2] ||
         a.data[i + 3] != b.data[i + 3];
  return n;
}

TEST_F(DebugViewGlTest, ColorRampMatchesItsCppTwin) {
  // Each fragment x of a 256 x 1 target writes hv_colorRamp(x / 255).
  const char* probe = R"(#version 300 es
precision highp float;
precision highp int;
#include "colormap.glsl"
out vec4 o_color;
void main() { o_color = vec4(hv_colorRamp(floor(gl_FragCoord.x) / 255.0), 1.0); }
)";
  gpu::Program program(gpu::ShaderText{"fullscreen.vert", *gpu::findShaderSource("fullscreen.vert")},
                       gpu::ShaderText{"ramp_probe.frag", probe});
  gpu::Texture target = gpu::makeTexture();
  glBindTexture(GL_TEXTURE_2D, target.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 256, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  gpu::Framebuffer fbo = gpu::makeFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target.id(), 0);
  gpu::checkFramebuffer("ramp probe");
  gpu::VertexArray vao = gpu::makeVertexArray();
  glBindVertexArray(vao.id());
  glViewport(0, 0, 256, 1);
  program.use();
  glDrawArrays(GL_TRIANGLES, 0, 3);
  std::vector<std::uint8_t> rgba(256 * 4);
  glReadPixels(0, 0, 256, 1, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  for (int x = 0; x < 256; ++x) {
    const glm::dvec3 cpu = colorRamp(x / 255.0);
    // One step of 8-bit rounding either way (float vs double on the control-point boundaries).
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(rgba[size_t(4 * x + c)], 255.0 * cpu[c], 1.0) << "t = " << x << "/255";
  }
}

// Three photographs of the street, no occlusion test (so the reference needs no visibility and
// every flat pixel is comparable): the weight view's raw share of each photograph equals
// w_i a_i / sum_j w_j a_j of the CPU reference, its colour is hv::colorRamp of it, and the shares
// of the three sum to 1 where the pixel is covered.
TEST_F(DebugViewGlTest, WeightViewMatchesCpuReferenceShares) {
  Scene scene = testing::streetScene();
  addStreetPhotos(scene, "abc", 160.0);
  // A mask on "c" makes a_i vary inside the image.
  Image8 mask(120, 120, 1, 255);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 40; ++x) mask.at(x, y, 0) = 0;
  writePng(dir_ + "/c.mask.png", mask);
  scene.photos[2].maskPath = dir_ + "/c.mask.png";

  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 3;
  settings.blend.sigma = 5.0;
  settings.blend.occlusion = false;
  settings.blend.featherPx = 0.0;  // the CPU shares below are the papers' eq. 2, hard-edged
  settings.depthSize = 256;
  Renderer renderer(scene, settings, diag);
  const Camera view = testing::streetView();
  std::vector<Image16> shares;
  std::vector<Image8> pictures;
  for (int photo = 0; photo < 3; ++photo) {
    renderer.settings().debug = {DebugView::Weight, photo};
    const RenderOutput out = renderer.render(view);
    ASSERT_EQ(out.debugValues.width, view.width);
    EXPECT_GE(renderer.stats().debugImage, 0);
    shares.push_back(out.debugValues);
    pictures.push_back(out.rgba);
  }
  ASSERT_TRUE(diag.ok());
  const auto& params = renderer.lastImageParams();
  ASSERT_EQ(params.size(), 3u);

  std::vector<Image8> slices;
  for (const auto& p : scene.photos) {
    const Image8 m = p.maskPath.empty() ? Image8{} : readImage(p.maskPath, 1);
    slices.push_back(ibr::makeSliceImage(p.camera, readImage(p.imagePath), m, renderer.sliceSize(), p.camera.id));
  }
  ibr::TextureLookup tex = [&](int slice, glm::dvec2 uv) {
    for (const auto& p : params)
      if (p.layout.slice == slice) return ibr::sampleBilinear(slices[size_t(p.photo)], uv);
    ADD_FAILURE() << "unknown slice";
    return glm::dvec4(0.0);
  };
  Mesh all = scene.terrain;
  all.append(scene.buildings);
  RayCaster caster(all);
  int compared = 0, partial = 0;
  double maxDiff = 0.0;
  for (int y = 3; y < view.height; y += 5)
    for (int x = 3; x < view.width; x += 5) {
      const glm::dvec2 px(x + 0.5, y + 0.5);
      const auto hit = caster.intersect(view.center, view.rayDirection(px), 0.0, 1e9);
      if (!hit) continue;
      bool flat = true;  // away from the view's depth edges
      for (glm::dvec2 off : {glm::dvec2(1.5, 0), glm::dvec2(-1.5, 0), glm::dvec2(0, 1.5), glm::dvec2(0, -1.5)}) {
        const auto h2 = caster.intersect(view.center, view.rayDirection(px + off), 0.0, 1e9);
        flat = flat && h2 && glm::dot(h2->normal, hit->normal) > 0.999;
      }
      if (!flat) continue;
      const ibr::BlendResult ref =
          ibr::referenceBlend(hit->position - scene.origin, params, ibr::BlendMethod::Blend, tex, nullptr);
      double sum = 0.0;
      bool all = true;  // every image compared: the shares must sum to 1
      for (size_t i = 0; i < params.size(); ++i) {
        const int photo = params[i].photo;
        const double gl = shares[size_t(photo)].at(x, y, 0) / 65535.0;
        const double cpu = ref.share(i);
        // Near an image's border or the mask's edge the bilinear alpha changes within a texel, and
        // float vs double texel positions pick different blends of it: skip those.
        const double a = tex(params[i].layout.slice,
                             ibr::projectIntoImage(params[i], hit->position - scene.origin)
                                 .value_or(ibr::ImageHit{})
                                 .pxDistorted *
                                 params[i].layout.uvScale)
                             .a;
        if (a > 0.0 && a < 1.0) {
          all = false;
          continue;
        }
        // Tolerance: llvmpipe's 8-bit filtering of alpha (1/255 per lerp) and the float shader.
        EXPECT_NEAR(gl, cpu, 0.01) << "photo " << photo << " at " << x << "," << y;
        maxDiff = std::max(maxDiff, std::abs(gl - cpu));
        sum += gl;
        if (ref.covered()) {
          // The colour is the ramp of the share (8-bit rounding and the 16-bit share: 2 levels).
          const glm::dvec3 c = colorRamp(gl);
          for (int k = 0; k < 3; ++k) EXPECT_NEAR(pictures[size_t(photo)].at(x, y, k), 255.0 * c[k], 2.0);
        }
      }
      if (ref.covered() && all) {
        EXPECT_NEAR(sum, 1.0, 3e-3) << "at " << x << "," << y;
        partial += ref.count > 1;
      }
      ++compared;
    }
  EXPECT_GT(compared, 200);
  EXPECT_GT(partial, 50) << "too few pixels where several photographs share the colour";
  std::cout << "weight view: " << compared << " pixels compared, max share difference " << maxDiff << "\n";

  // Counts view: the raw values are the count output.
  renderer.settings().debug = {DebugView::Counts, -1};
  const RenderOutput counts = renderer.render(view, true);
  EXPECT_EQ(counts.debugValues.data, counts.counts.data);
}

// The depth-map view shows a photograph's depth map letterboxed into the view; each texel holds
// the linear depth of the surface under its centre, which a ray cast from the photograph through
// that texel centre finds. The photograph is not among the frame's images (K = 1, another is
// nearer): the view makes it resident for itself.
TEST_F(DebugViewGlTest, DepthMapViewMatchesRayCastDepths) {
  Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  const Camera photo = testing::lookAt("p", o + glm::dvec3(-3, -10, 5), o + glm::dvec3(2, 30, 8), 200, 100, 120);
  addPhoto(scene, photo, testing::patternImage(200, 100, 1));
  const Camera view = testing::lookAt("v", o + glm::dvec3(0, -30, 3), o + glm::dvec3(0, 30, 3), 160, 120, 100);
  addPhoto(scene, testing::lookAt("near", view.center, o + glm::dvec3(0, 30, 3), 80, 60, 50),
           testing::patternImage(80, 60, 2));
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 128;
  settings.debug = {DebugView::DepthMap, 0};
  Renderer renderer(scene, settings, diag);
  const RenderOutput out = renderer.render(view);
  ASSERT_TRUE(diag.ok());
  ASSERT_EQ(renderer.lastPlan().images.size(), 1u);
  EXPECT_EQ(renderer.lastPlan().images[0].photo, 1);
  EXPECT_EQ(renderer.stats().debugImage, -1);
  EXPECT_GE(renderer.stats().debugSlot, 0);
  EXPECT_EQ(renderer.photoState(0), PhotoState::Ready);

  // The renderer's depth-map frustum (renderer.cpp, depthFrustum): the ideal rectangle with a
  // pixel of margin, depth range from the scene's bounds.
  hv::PinholeFrustum fr = hv::idealRectCoveringImage(photo, 1.0);
  hv::setDepthRange(fr, photo, scene.bounds());
  const glm::dvec2 rectPx = fr.pxMax - fr.pxMin;
  const double aspect = rectPx.x / rectPx.y;  // 202 / 102: wider than the view, bars above and below
  const glm::dvec2 rect(view.width, view.width / aspect);
  const glm::dvec2 rectMin = (glm::dvec2(view.width, view.height) - rect) / 2.0;
  Mesh all = scene.terrain;
  all.append(scene.buildings);
  RayCaster caster(all);
  const int n = settings.depthSize;
  auto depthAtTexel = [&](glm::ivec2 t) -> double {
    const glm::dvec2 p = fr.pxMin + (glm::dvec2(t) + 0.5) / double(n) * rectPx;
    const auto hit = caster.intersect(photo.center, photo.rayDirection(p), 0.0, 1e9);
    return hit ? photo.project(hit->position).depth : -1.0;
  };
  int compared = 0, outside = 0, sky = 0;
  double near = 1e30, far = 0.0;
  for (int y = 0; y < view.height; y += 2)
    for (int x = 0; x < view.width; x += 2) {
      const std::uint16_t v = out.debugValues.at(x, y, 0);
      const glm::dvec2 t = (glm::dvec2(x + 0.5, y + 0.5) - rectMin) / rect;
      if (t.x < 0.0 || t.y < 0.0 || t.x >= 1.0 || t.y >= 1.0) {
        if (t.y < -0.02 || t.y > 1.02) {
          ++outside;
          EXPECT_EQ(v, 65535) << "outside the map at " << x << "," << y;
          EXPECT_EQ(out.rgba.at(x, y, 3), 0);
        }
        continue;
      }
      // The texel GL_NEAREST picks; not where the choice is ambiguous (float positions).
      const glm::dvec2 tex = t * double(n);
      const glm::dvec2 frac = tex - glm::floor(tex);
      if (glm::any(glm::lessThan(frac, glm::dvec2(0.02))) || glm::any(glm::greaterThan(frac, glm::dvec2(0.98))))
        continue;
      const glm::ivec2 texel(tex);
      const double z = depthAtTexel(texel);
      // Silhouettes: a texel whose neighbours see another surface may be rasterised either way.
      bool edge = false;
      for (glm::ivec2 off : {glm::ivec2(1, 0), glm::ivec2(-1, 0), glm::ivec2(0, 1), glm::ivec2(0, -1)}) {
        const double zn = depthAtTexel(texel + off);
        edge = edge || (zn < 0.0) != (z < 0.0) || (z > 0.0 && std::abs(zn - z) > 0.1 * z);
      }
      if (edge) continue;
      if (z < 0.0) {
        ++sky;
        EXPECT_EQ(v, 65535) << "the photograph sees no geometry through texel " << texel.x << "," << texel.y;
        continue;
      }
      const double gl = fr.near + v / 65535.0 * (fr.far - fr.near);
      // 16-bit quantisation of [near, far] (two levels) plus float depth (1e-5 relative).
      EXPECT_NEAR(gl, z, 2.0 * (fr.far - fr.near) / 65535.0 + 1e-5 * z) << "texel " << texel.x << "," << texel.y;
      EXPECT_EQ(out.rgba.at(x, y, 3), 255);
      near = std::min(near, z);
      far = std::max(far, z);
      ++compared;
    }
  EXPECT_GT(compared, 500);
  EXPECT_GT(outside, 100);
  EXPECT_GT(sky, 20);
  // The colours span the stored depths: the stats report that range (within the sampling).
  EXPECT_LE(renderer.stats().debugDepthNear, near + 0.05);
  EXPECT_GE(renderer.stats().debugDepthFar, far - 0.05);
  EXPECT_LT(renderer.stats().debugDepthNear, renderer.stats().debugDepthFar);
}

// Frusta over the picture: the yellow of the frame's images along the projection of a selected
// photograph's frustum edge, and nothing else of the picture changed by more than the lines.
TEST_F(DebugViewGlTest, FrustaAreDrawnOverThePicture) {
  Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  const Camera photo = testing::lookAt("p", o + glm::dvec3(0, -10, 4), o + glm::dvec3(0, 10, 4), 160, 120, 110);
  addPhoto(scene, photo, testing::solidImage(160, 120, 40, 40, 200));
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 256;
  Renderer renderer(scene, settings, diag);
  // From the side and above, so the frustum (depth 5) is seen in front of the ground.
  const Camera view = testing::lookAt("v", o + glm::dvec3(12, -14, 8), o + glm::dvec3(0, -8, 4), 200, 150, 150);
  const RenderOutput plain = renderer.render(view);
  renderer.settings().debug.frusta = true;
  renderer.settings().debug.frustumDepth = 5.0;
  const RenderOutput lines = renderer.render(view);
  ASSERT_TRUE(diag.ok());
  const int changed = differingPixels(plain.rgba, lines.rgba);
  EXPECT_GT(changed, 50);
  EXPECT_LT(changed, view.width * view.height / 5);
  // Along each apex-to-corner edge the line's colour appears within a pixel of the projection.
  const FrustumOutline f = frustumOutline(photo, 5.0, 1);
  int found = 0;
  for (int c = 0; c < 4; ++c) {
    const glm::dvec3 mid = 0.5 * (f.apex + f.border[size_t(f.corners[size_t(c)])]);
    const Projection p = view.project(mid);
    ASSERT_TRUE(p.inImage);
    bool yellow = false;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const std::uint8_t* px = lines.rgba.px(int(p.pxIdeal.x) + dx, int(p.pxIdeal.y) + dy);
        yellow = yellow || (px[0] == 255 && px[1] >= 210 && px[1] <= 225 && px[2] <= 45);
      }
    found += yellow;
  }
  EXPECT_EQ(found, 4);
  // Off again: the picture is the plain one.
  renderer.settings().debug.frusta = false;
  EXPECT_EQ(differingPixels(plain.rgba, renderer.render(view).rgba), 0);
}

// A geometry layer switched off leaves the view and the depth maps: the near building (here the
// scene's "mesh") no longer hides the far façade from the photograph, which then textures it; the
// depth maps are redrawn when the layer changes, and switched on again the first picture returns.
TEST_F(DebugViewGlTest, LayersLeaveTheViewAndTheDepthMaps) {
  const glm::dvec3 o = kStreetOrigin;
  Scene scene = testing::streetScene();
  scene.buildings = box(-15, 15, 30, 34, 20);
  scene.mesh = box(-5, 5, 10, 14, 12);
  addPhoto(scene, testing::lookAt("red", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 30, 10), 160, 120, 110),
           testing::solidImage(160, 120, 255, 0, 0));
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 256;
  Renderer renderer(scene, settings, diag);
  // Between the buildings, facing the far façade.
  const Camera view = testing::lookAt("v", o + glm::dvec3(0, 20, 6), o + glm::dvec3(0, 30, 8), 160, 120, 80);
  const RenderOutput before = renderer.render(view);
  const int mapsBefore = renderer.stats().depthMapsRendered;
  int hiddenBefore = 0;
  for (size_t i = 3; i < before.rgba.data.size(); i += 4) hiddenBefore += before.rgba.data[i] == 0;
  EXPECT_GT(hiddenBefore, 500) << "the near building should hide part of the far façade";

  renderer.settings().layers.mesh = false;
  const RenderOutput without = renderer.render(view);
  EXPECT_GT(renderer.stats().depthMapsRendered, mapsBefore) << "the depth map was not redrawn";
  int hiddenWithout = 0;
  for (size_t i = 3; i < without.rgba.data.size(); i += 4) hiddenWithout += without.rgba.data[i] == 0;
  EXPECT_LT(hiddenWithout, hiddenBefore / 10);

  // Terrain off too: the ground (seen looking down, textured now that the near building is gone)
  // becomes background; the façade stays.
  const Camera down = testing::lookAt("d", o + glm::dvec3(0, 20, 6), o + glm::dvec3(0, 26, 0), 160, 120, 80);
  EXPECT_EQ(renderer.render(down).rgba.at(80, 60, 3), 255);
  renderer.settings().layers.terrain = false;
  EXPECT_EQ(renderer.render(down).rgba.at(80, 60, 3), 0);
  EXPECT_EQ(renderer.render(view).rgba.at(80, 40, 3), 255);

  renderer.settings().layers = {};
  const RenderOutput again = renderer.render(view);
  EXPECT_EQ(differingPixels(before.rgba, again.rgba), 0);
  EXPECT_TRUE(diag.ok());
}

// Lens distortion off: the photographs are used as pinhole cameras, exactly as if their cameras
// had no distortion (same picture as such a scene), and on again the corrected picture returns.
TEST_F(DebugViewGlTest, LensDistortionOffProjectsPhotographsAsPinholes) {
  const glm::dvec3 o = kStreetOrigin;
  Scene scene = testing::streetScene();
  Camera cam = testing::lookAt("d", o + glm::dvec3(2, -10, 3), o + glm::dvec3(0, 30, 8), 200, 150, 140);
  LensDistortion d;
  d.center = {104.0, 71.0};
  d.c3 = -6e-6;
  d.r2max = 170.0 * 170.0;
  cam.distortion = d;
  addPhoto(scene, cam, testing::patternImage(200, 150, 4));
  Scene pinhole = scene;
  pinhole.photos[0].camera.distortion.reset();

  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 256;
  const Camera view = testing::lookAt("v", o + glm::dvec3(0, -9, 2.5), o + glm::dvec3(0, 31, 7), 160, 120, 120);
  Diagnostics diag;
  Renderer reference(pinhole, settings, diag);
  const RenderOutput expected = reference.render(view);

  Renderer renderer(scene, settings, diag);
  const RenderOutput corrected = renderer.render(view);
  EXPECT_GT(differingPixels(corrected.rgba, expected.rgba), 1000) << "the distortion should matter here";
  renderer.settings().layers.lensDistortion = false;
  const RenderOutput off = renderer.render(view);
  EXPECT_FALSE(renderer.lastImageParams()[0].camera.distortion);
  EXPECT_EQ(differingPixels(off.rgba, expected.rgba), 0);
  renderer.settings().layers.lensDistortion = true;
  EXPECT_EQ(differingPixels(renderer.render(view).rgba, corrected.rgba), 0);
  EXPECT_TRUE(diag.ok());
}

// Masks off: the photographs are decoded again without them, so a masked half is textured.
TEST_F(DebugViewGlTest, MasksSwitchedOffDecodeThePhotographsAgain) {
  const glm::dvec3 o = kStreetOrigin;
  Scene scene = testing::streetScene();
  const Camera a = testing::lookAt("a", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 10, 6), 160, 120, 110);
  Image8 mask(160, 120, 1, 255);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 80; ++x) mask.at(x, y, 0) = 0;
  addPhoto(scene, a, testing::solidImage(160, 120, 255, 0, 0), &mask);
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 256;
  Renderer renderer(scene, settings, diag);
  RenderOutput out = renderer.render(a);
  EXPECT_EQ(out.rgba.at(40, 90, 3), 0);
  EXPECT_EQ(out.rgba.at(120, 90, 3), 255);
  const int loaded = renderer.stats().imagesLoaded;
  renderer.settings().blend.masks = false;
  out = renderer.render(a);
  EXPECT_EQ(renderer.stats().imagesLoaded, loaded + 1);
  EXPECT_EQ(out.rgba.at(40, 90, 3), 255);
  EXPECT_EQ(out.rgba.at(40, 90, 0), 255);
  renderer.settings().blend.masks = true;
  EXPECT_EQ(renderer.render(a).rgba.at(40, 90, 3), 0);
  EXPECT_TRUE(diag.ok());
}

// Points switched on after construction are uploaded then, drawn, and off again not drawn.
TEST_F(DebugViewGlTest, PointsCanBeSwitchedOnAndOffBetweenFrames) {
  const glm::dvec3 o = kStreetOrigin;
  Scene scene = testing::streetScene();
  PointFields fields;
  fields.normals = true;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 10; ++j) {
      const size_t n = scene.points.size();
      scene.points.resize(n + 1, fields);
      scene.points.positions[n] = o + glm::dvec3(-5.0 + 0.5 * i, 5.0, 0.5 + 0.5 * j);
      scene.points.normals[n] = glm::vec3(0, -1, 0);
    }
  organizeChunks(scene.points);
  const Camera a = testing::lookAt("a", o + glm::dvec3(0, -10, 3), o + glm::dvec3(0, 5, 3), 160, 120, 110);
  addPhoto(scene, a, testing::patternImage(160, 120, 5));
  // Seen from the side, a textured point and the ground behind it take different texels.
  const Camera view = testing::lookAt("v", o + glm::dvec3(3, -10, 3), o + glm::dvec3(0, 5, 3), 160, 120, 110);
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 256;
  settings.points.filter = PointFilter::None;
  Renderer renderer(scene, settings, diag);
  const RenderOutput meshOnly = renderer.render(view);
  EXPECT_EQ(renderer.stats().pointsDrawn, 0u);
  renderer.settings().points.enabled = true;
  const RenderOutput withPoints = renderer.render(view);
  EXPECT_EQ(renderer.stats().pointsDrawn, 200u);
  EXPECT_GT(differingPixels(meshOnly.rgba, withPoints.rgba), 100);
  renderer.settings().points.enabled = false;
  EXPECT_EQ(differingPixels(meshOnly.rgba, renderer.render(view).rgba), 0);
  EXPECT_EQ(renderer.stats().pointsDrawn, 0u);
  EXPECT_TRUE(diag.ok());
}

}  // namespace
}  // namespace hv::render
