// GL tests of the renderer on llvmpipe: the shaders compile, the GL blend equals the CPU
// reference (hv::ibr::referenceBlend) at sampled pixels, occlusion and masks behave.
#include "hv/render/renderer.h"

#include "hv/gpu/shader_sources.h"
#include "hv/ibr/reference_blend.h"
#include "hv/ibr/slice_image.h"
#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/scene/native/raycast.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

namespace hv::render {
namespace {

using testing::kStreetOrigin;

class RendererGlTest : public testing::PhotoGlTest {
 protected:
  // Renders `view` and compares it with hv::ibr::referenceBlend at sampled pixels (visibility by
  // ray casting). Returns how many compared pixels blend an image that is not among the K nearest
  // candidates (another failed a test there), in region selection.
  int compareWithReference(const Scene& scene, const RenderSettings& settings, const Camera& view,
                           size_t expectedImages) {
    Diagnostics diag;
    Renderer renderer(scene, settings, diag);
    const RenderOutput out = renderer.render(view);
    EXPECT_TRUE(diag.ok());
    const auto& params = renderer.lastImageParams();
    EXPECT_EQ(params.size(), expectedImages);
    if (params.size() != expectedImages) return 0;
    // The plan's weights: f(d_i) in region selection, and eq. 2 with no K+1-th candidate in global.
    const bool region = settings.blend.selection == ibr::Selection::Region;
    if (region || settings.blend.weighting == ibr::Weighting::Geometry || renderer.lastPlan().nextDistance < 0.0)
      for (const auto& im : renderer.lastPlan().images)
        EXPECT_NEAR(im.weight, 1.0 / (25.0 + im.distance * im.distance), 1e-12);

    // CPU side: the same slices, visibility by ray casting (independent of the GL depth maps).
    Mesh all = scene.terrain;
    all.append(scene.buildings);
    RayCaster caster(all);
    std::vector<Image8> slices;
    std::vector<std::vector<Image8>> chains;
    for (const auto& p : scene.photos) {
      const Image8 mask = p.maskPath.empty() || !settings.blend.masks ? Image8{} : readImage(p.maskPath, 1);
      slices.push_back(ibr::makeSliceImage(p.camera, readImage(p.imagePath), mask, renderer.sliceSize(), p.camera.id));
      chains.push_back(ibr::sliceMipChain(slices.back()));
    }
    auto photoOfSlice = [&](int slice) {
      for (const auto& p : params)
        if (p.layout.slice == slice) return size_t(p.photo);
      ADD_FAILURE() << "unknown slice";
      return size_t(0);
    };
    // texelShift: the transient filter's conditioning check below shifts every photograph's colours
    // by this, up or down by bit `shiftBit` of the slice index.
    double texelShift = 0.0;
    int shiftBit = 0;
    ibr::TextureLookup tex = [&](int slice, glm::dvec2 uv) {
      glm::dvec4 t = ibr::sampleBilinear(slices[photoOfSlice(slice)], uv);
      if (texelShift != 0.0) {
        const double d = (slice >> shiftBit) & 1 ? -texelShift : texelShift;
        t = glm::dvec4(glm::clamp(glm::dvec3(t) + d * t.a, glm::dvec3(0.0), glm::dvec3(t.a)), t.a);
      }
      return t;
    };
    // The geometry weights and feathering, as the shader gets them (the normal: the ray cast's).
    ibr::BlendOptions opt;
    const ibr::BlendSettings& b = settings.blend;
    opt.weighting = b.weighting;
    opt.resolutionWeight = b.resolutionWeight;
    opt.penaltyEpsilon = b.penaltyEpsilon;
    opt.geometryK = b.geometryK;
    opt.featherPx = b.featherPx;
    opt.consensusSpread = b.consensus;
    opt.viewCenter = view.center - scene.origin;
    opt.viewFocal = 0.5 * (view.focal.x + view.focal.y);
    opt.sliceWidth = renderer.sliceSize().width;
    if (b.featherPx > 0.0 && b.masks)
      opt.mask = [&](int slice, glm::dvec2 uv, double lod) {
        return ibr::sampleTrilinear(chains[photoOfSlice(slice)], uv, lod).a;
      };
    // A point's visibility from image i is "robust" when the ray casts at +-2 image pixels around its
    // projection agree; pixels near an occlusion edge (where a 512^2 depth map and an exact ray cast
    // may legitimately differ) are not compared.
    bool robust = true;
    ibr::VisibilityTest visible = [&](size_t i, const glm::dvec3& Pr, double) {
      const Camera& cam = params[i].camera;
      const glm::dvec3 P = Pr + scene.origin;
      auto seen = [&](const glm::dvec3& target) {
        const glm::dvec3 dir = target - cam.center;
        const double dist = glm::length(dir);
        const auto hit = caster.intersect(cam.center, dir, 0.0, dist * 2.0);
        return hit && hit->t > dist - 0.02 - 1e-3 * dist;
      };
      const bool v = seen(P);
      // At grazing incidence a depth map's texel spans a long stretch of depth, so any shadow map
      // (with a bias of a few texels) self-shadows there while the exact ray cast does not:
      // compare only where the photograph sees the surface at more than 15 degrees.
      const auto direct = caster.intersect(cam.center, P - cam.center, 0.0, 1e9);
      if (direct && std::abs(glm::dot(direct->normal, glm::normalize(P - cam.center))) < 0.26) robust = false;
      const Projection p = cam.project(P);
      for (glm::dvec2 off : {glm::dvec2(2, 0), glm::dvec2(-2, 0), glm::dvec2(0, 2), glm::dvec2(0, -2)}) {
        const glm::dvec3 dir = cam.rayDirection(p.pxIdeal + off);
        const auto hit = caster.intersect(cam.center, dir, 0.0, 1e9);
        if (!hit) continue;
        if (seen(hit->position) != true || (glm::length(hit->position - P) > 1.0) != false) {
          // The neighbour ray lands on another surface: occlusion edge nearby.
          if (glm::dot(hit->normal, caster.intersect(cam.center, P - cam.center, 0.0, 1e9)->normal) < 0.99)
            robust = false;
        }
      }
      return v;
    };

    int compared = 0, replaced = 0, illConditioned = 0;
    double maxDiff = 0.0;
    for (int y = 4; y < view.height; y += 7) {
      for (int x = 4; x < view.width; x += 7) {
        const glm::dvec2 px(x + 0.5, y + 0.5);
        const auto hit = caster.intersect(view.center, view.rayDirection(px), 0.0, 1e9);
        if (!hit) continue;
        // Skip depth edges in the view: all four neighbours must hit the same plane.
        bool flat = true;
        for (glm::dvec2 off : {glm::dvec2(1.5, 0), glm::dvec2(-1.5, 0), glm::dvec2(0, 1.5), glm::dvec2(0, -1.5)}) {
          const auto h2 = caster.intersect(view.center, view.rayDirection(px + off), 0.0, 1e9);
          if (!h2 || glm::dot(h2->normal, hit->normal) < 0.999 ||
              std::abs(glm::dot(h2->position - hit->position, hit->normal)) > 1e-3)
            flat = false;
        }
        if (!flat) continue;
        robust = true;
        opt.normal = hit->normal;
        const ibr::BlendResult ref = ibr::referenceBlend(hit->position - scene.origin, params, ibr::BlendMethod::Blend,
                                                         tex, visible, settings.blend.selection, settings.blend.k, opt);
        if (!robust) continue;
        // The transient filter's weights follow the colours, so the GL filtering's error on the
        // texels (up to 2/255) moves the result by more than it moves a plain blend: the
        // tolerance adds the CPU result's own change when the photographs' colours are shifted
        // by 2/255 apart (four ways: up or down, split by two bits of the slice index). Where that
        // change is large, two modes of the pixel's colours are about as strong and the choice
        // between them may flip (an optimised and a Debug build of this test flip differently):
        // such pixels are not compared (the filter's rule is checked against independent values
        // in src/hv/ibr/consensus_test.cpp).
        double sensitivity = 0.0;
        if (settings.blend.consensus > 0.0) {
          for (int bit : {0, 1})
            for (double shift : {2.0 / 255.0, -2.0 / 255.0}) {
              texelShift = shift;
              shiftBit = bit;
              const ibr::BlendResult r = ibr::referenceBlend(hit->position - scene.origin, params,
                                                             ibr::BlendMethod::Blend, tex, visible,
                                                             settings.blend.selection, settings.blend.k, opt);
              texelShift = 0.0;
              sensitivity =
                  r.covered() != ref.covered() ? 1.0 : std::max(sensitivity, glm::length(r.color - ref.color));
            }
          if (sensitivity > 12.0 / 255.0) {
            ++illConditioned;
            continue;
          }
        }
        const std::uint8_t* g = out.rgba.px(x, y);
        EXPECT_EQ(g[3] > 0, ref.covered()) << "coverage differs at " << x << "," << y;
        if (!ref.covered() || g[3] == 0) continue;
        for (int c = 0; c < 3; ++c) {
          const double diff = std::max(0.0, std::abs(g[c] / 255.0 - ref.color[c]) - sensitivity);
          if (diff > 4.0 / 255.0)
            ADD_FAILURE() << "pixel " << x << "," << y << " channel " << c << ": GL " << int(g[c]) << " vs CPU "
                          << ref.color[c] * 255.0 << " (CPU count " << ref.count << ")";
          maxDiff = std::max(maxDiff, diff);
        }
        ++compared;
        for (size_t i = size_t(settings.blend.k); region && i < params.size(); ++i)
          if (ref.contribution[i] > 0.0) {
            ++replaced;
            break;
          }
      }
    }
    // Tolerance: llvmpipe filters RGBA8 with 8-bit interpolation weights (up to ~1/255 per lerp,
    // two lerps), the shader projects in float, and the output is rounded to 8 bits.
    EXPECT_GT(compared + illConditioned, 100);
    EXPECT_LT(illConditioned, compared / 3);
    EXPECT_LE(maxDiff, 4.0 / 255.0) << "over " << compared << " pixels";
    return replaced;
  }
};

TEST_F(RendererGlTest, EveryShaderCompilesAndLinks) {
  std::set<std::string> used;
  for (const ProgramSource& p : programSources()) {
    EXPECT_NO_THROW(gpu::Program(p.vertex, p.fragment, p.defines)) << p.vertex << " + " << p.fragment;
    used.insert(p.vertex);
    used.insert(p.fragment);
  }
  // Every shader file is part of some program (shared chunks are included by them), and every one
  // is GLSL ES 3.00 (the WebGL2 subset).
  for (const auto& name : gpu::shaderNames()) {
    if (name.ends_with(".glsl")) continue;
    EXPECT_TRUE(used.count(name)) << name << " is not used by any program";
    EXPECT_EQ(gpu::findShaderSource(name)->rfind("#version 300 es", 0), 0u) << name;
  }
}

TEST_F(RendererGlTest, MatchesCpuReferenceAtSampledPixels) {
  Scene scene = testing::streetScene();
  // Three photographs of the street with different intrinsics, one distorted; sizes differ so one
  // of them sits padded in its slice.
  addStreetPhotos(scene, "abc", 160.0);

  RenderSettings settings;
  settings.blend.k = 3;
  settings.blend.sigma = 5.0;
  settings.depthSize = 512;
  const Camera view = testing::streetView();
  // Global: the papers' weights; region with K = 3 of 3 candidates: the same picture.
  for (ibr::Selection selection : {ibr::Selection::Global, ibr::Selection::Region}) {
    settings.blend.selection = selection;
    compareWithReference(scene, settings, view, 3);
  }
}

// Colour corrections (hv::ColourCorrection) applied by the shader as by the CPU reference
// (ibr::correctTexel), clamping included; `colour-correction off` gives the photographs back.
TEST_F(RendererGlTest, ColourCorrectionsMatchCpuReference) {
  Scene scene = testing::streetScene();
  addStreetPhotos(scene, "abc");
  scene.photos[0].colour = {{0.8, 1.3, 1.0}, {0.05, -0.1, 0.0}};  // green clips at 1 on bright texels
  scene.photos[2].colour = {{1.1, 0.9, 0.6}, {0.0, 0.05, 0.2}};
  RenderSettings settings;
  settings.blend.k = 3;
  settings.blend.sigma = 5.0;
  settings.depthSize = 512;
  const Camera view = testing::streetView();
  compareWithReference(scene, settings, view, 3);

  // On and off: the corrections reach the parameters, and the picture changes.
  Diagnostics diag;
  Renderer renderer(scene, settings, diag);
  const Image8 on = renderer.render(view).rgba;
  bool corrected = false;
  for (const auto& p : renderer.lastImageParams()) corrected |= !p.colour.isIdentity();
  EXPECT_TRUE(corrected);
  renderer.settings().blend.colourCorrection = false;
  const Image8 off = renderer.render(view).rgba;
  for (const auto& p : renderer.lastImageParams()) EXPECT_TRUE(p.colour.isIdentity());
  double diff = 0.0;
  for (size_t i = 0; i < on.data.size(); ++i) diff += std::abs(int(on.data[i]) - int(off.data[i]));
  // Mean absolute byte difference over the whole RGBA image (uncovered pixels included): 1.5 measured.
  EXPECT_GT(diff / double(on.data.size()), 0.5);
  settings.blend.colourCorrection = false;
  compareWithReference(scene, settings, view, 3);
}

// Region selection where it differs from the global one: five photographs, K = 2, so that where
// the near building hides some of them from the far façade, others take their place per pixel.
TEST_F(RendererGlTest, RegionSelectionMatchesCpuReferenceAtSampledPixels) {
  Scene scene = testing::streetScene();
  addStreetPhotos(scene, "abcde");
  RenderSettings settings;
  settings.blend.k = 2;
  settings.blend.sigma = 5.0;
  settings.depthSize = 512;
  settings.blend.selection = ibr::Selection::Region;
  const Camera view = testing::streetView();
  const int replaced = compareWithReference(scene, settings, view, 5);
  // Pixels where a nearer photograph fails a test and a farther one is blended in its place.
  EXPECT_GT(replaced, 20);
  // With tile culling off the loop visits every candidate in the same order: the same picture.
  settings.tileCulling = false;
  compareWithReference(scene, settings, view, 5);
}

// Geometry weights (best K per pixel by penalty) and feathering (borders and, through the slices'
// mip levels, masks) against the CPU reference, alone and together, in both selections.
TEST_F(RendererGlTest, GeometryWeightsAndFeatheringMatchCpuReference) {
  Scene scene = testing::streetScene();
  // "b"'s lens domain: the lens domain cuts the corners: its edge is feathered too
  addStreetPhotos(scene, "abc", 110.0);
  // A mask with a hole in the middle of d.
  Image8 mask(160, 120, 1, 255);
  for (int y = 40; y < 80; ++y)
    for (int x = 50; x < 110; ++x) mask.at(x, y, 0) = 0;
  addPhoto(scene, testing::streetPhotoCamera('d'), testing::patternImage(160, 120, 4), &mask);
  addStreetPhotos(scene, "e");
  RenderSettings settings;
  settings.blend.k = 2;
  settings.blend.sigma = 5.0;
  settings.depthSize = 512;
  const Camera view = testing::streetView();
  settings.blend.weighting = ibr::Weighting::Geometry;
  compareWithReference(scene, settings, view, 5);
  settings.blend.k = 3;
  settings.blend.resolutionWeight = 2.0;
  compareWithReference(scene, settings, view, 5);
  // geometry-k: the best 2 per pixel though K = 4 (the shader stops at the third that passes).
  settings.blend.k = 4;
  settings.blend.geometryK = 2;
  compareWithReference(scene, settings, view, 5);
  settings.blend.geometryK = 0;
  settings.blend.weighting = ibr::Weighting::Distance;
  settings.blend.featherPx = 12.0;
  settings.blend.k = 5;
  compareWithReference(scene, settings, view, 5);
  settings.blend.weighting = ibr::Weighting::Geometry;
  settings.blend.k = 2;
  compareWithReference(scene, settings, view, 5);
  settings.blend.selection = ibr::Selection::Region;
  compareWithReference(scene, settings, view, 5);
  settings.blend.weighting = ibr::Weighting::Distance;
  compareWithReference(scene, settings, view, 5);
  // The transient filter, in each selection and weighting (K = 5: enough images agree or not).
  settings.blend.consensus = 0.25;
  settings.blend.k = 5;
  compareWithReference(scene, settings, view, 5);
  settings.blend.selection = ibr::Selection::Global;
  compareWithReference(scene, settings, view, 5);
  settings.blend.weighting = ibr::Weighting::Geometry;
  settings.blend.featherPx = 0.0;
  compareWithReference(scene, settings, view, 5);
}

// Mipmaps: a photograph of a one-pixel checkerboard seen from its own centre at a quarter of its
// resolution. Each view pixel covers 4.3 x 4.3 photograph pixels (not a whole number, so level 0
// samples every phase of the checker), whose mean (the CPU truth) is grey; level 0 aliases, the
// mip level from the footprint does not.
TEST_F(RendererGlTest, MipmapsFilterMinifiedPhotographs) {
  Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  Image8 checker(160, 120, 3, 0);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x)
      for (int c = 0; c < 3; ++c) checker.at(x, y, c) = (x + y) % 2 ? 255 : 0;
  addPhoto(scene, testing::lookAt("a", o + glm::dvec3(-6, -12, 2), o + glm::dvec3(0, 30, 8), 160, 120, 130), checker);
  const Camera view = testing::lookAt("v", o + glm::dvec3(-6, -12, 2), o + glm::dvec3(0, 30, 8), 37, 28, 130.0 / 4.3);
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 512;
  settings.untextured.sky = false;
  auto error = [&](bool mipmaps) {
    settings.blend.mipmaps = mipmaps;
    Diagnostics diag;
    Renderer renderer(scene, settings, diag);
    const RenderOutput out = renderer.render(view);
    double sum = 0.0;
    int n = 0;
    // Away from the photograph's border, where the footprint straddles the padding.
    for (int y = 2; y < view.height - 2; ++y)
      for (int x = 2; x < view.width - 2; ++x) {
        const std::uint8_t* g = out.rgba.px(x, y);
        if (g[3] == 0) continue;
        sum += std::abs(g[0] - 127.5);
        ++n;
      }
    EXPECT_GT(n, 500);
    return n > 0 ? sum / n : 1e9;
  };
  const double level0 = error(false), mipmapped = error(true);
  EXPECT_LT(mipmapped, 8.0) << "level 0: " << level0;
  EXPECT_GT(level0, 4.0 * mipmapped);
}

TEST_F(RendererGlTest, OccludedFacadeGetsNoPixelsFromThePhotograph) {
  Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  // Photograph "red" looks at the far building straight through the near one.
  addPhoto(scene, testing::lookAt("red", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 30, 10), 160, 120, 110),
           testing::solidImage(160, 120, 255, 0, 0));
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 1;
  settings.depthSize = 512;
  Renderer renderer(scene, settings, diag);
  // The view stands between the buildings, facing the far façade.
  const Camera view = testing::lookAt("v", o + glm::dvec3(0, 20, 6), o + glm::dvec3(0, 30, 8), 160, 120, 80);
  RenderOutput out = renderer.render(view, true);
  Mesh all = scene.terrain;
  all.append(scene.buildings);
  RayCaster caster(all);
  const Camera& red = scene.photos[0].camera;
  int hidden = 0, seen = 0;
  for (int y = 0; y < view.height; y += 3)
    for (int x = 0; x < view.width; x += 3) {
      const auto hit = caster.intersect(view.center, view.rayDirection({x + 0.5, y + 0.5}), 0.0, 1e9);
      if (!hit || hit->normal.y > -0.9) continue;  // the far façade faces -y
      if (!red.project(hit->position).inImage) continue;
      const glm::dvec3 toP = hit->position - red.center;
      const auto first = caster.intersect(red.center, toP, 0.0, 1e9);
      const double margin = glm::length(toP) - first->t;
      if (margin > 1.0) {  // clearly behind the near building from the photograph
        ++hidden;
        EXPECT_EQ(out.rgba.at(x, y, 3), 0) << "hidden façade pixel " << x << "," << y << " got the photo";
        EXPECT_EQ(out.counts.at(x, y, 0), 0);
      } else if (margin < 1e-3) {
        ++seen;
      }
    }
  EXPECT_GT(hidden, 50);
  EXPECT_GT(seen, 0);
  // The same view without the occlusion test paints the hidden façade red: the test above could fail.
  renderer.settings().blend.occlusion = false;
  out = renderer.render(view);
  int red_ = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) red_ += out.rgba.at(x, y, 3) > 0 && out.rgba.at(x, y, 0) == 255;
  EXPECT_GT(red_, hidden);
}

TEST_F(RendererGlTest, MaskedPixelsAreFilledByAnotherImage) {
  Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  const Camera a = testing::lookAt("a", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 10, 6), 160, 120, 110);
  Camera b = a;
  b.id = "b";
  b.center += glm::dvec3(0.5, 0, 0);
  Image8 mask(160, 120, 1, 255);
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 80; ++x) mask.at(x, y, 0) = 0;  // left half of "a" is a moving object
  addPhoto(scene, a, testing::solidImage(160, 120, 255, 0, 0), &mask);
  addPhoto(scene, b, testing::solidImage(160, 120, 0, 255, 0));
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 2;
  settings.blend.sigma = 1.0;
  Renderer renderer(scene, settings, diag);
  const RenderOutput out = renderer.render(a, true);
  // Left half: only "b" (pure green), a hole in "a" filled; right half: a blend dominated by "a"
  // (nearer, so heavier), still with some green.
  // Row 90 is ground, seen by both photographs.
  const std::uint8_t* left = out.rgba.px(40, 90);
  const std::uint8_t* right = out.rgba.px(120, 90);
  EXPECT_EQ(left[3], 255);
  EXPECT_LE(left[0], 1);
  EXPECT_GE(left[1], 254);
  EXPECT_EQ(out.counts.at(40, 90, 0), 1);
  EXPECT_EQ(out.counts.at(120, 90, 0), 2);
  EXPECT_GT(right[0], right[1]);
  EXPECT_GT(right[1], 0);
}

TEST_F(RendererGlTest, BrokenImageIsReportedAndTheRestRenders) {
  Scene scene = testing::streetScene();
  const glm::dvec3 o = kStreetOrigin;
  const Camera a = testing::lookAt("good", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 10, 6), 80, 60, 55);
  Camera b = a;
  b.id = "broken";
  b.center += glm::dvec3(0.1, 0, 0);
  addPhoto(scene, a, testing::solidImage(80, 60, 0, 0, 255));
  addPhoto(scene, b, testing::solidImage(80, 60, 255, 0, 0));
  {
    std::ofstream f(scene.photos[1].imagePath, std::ios::trunc);
    f << "not a png";
  }
  Diagnostics diag;
  RenderSettings settings;
  settings.blend.k = 2;
  Renderer renderer(scene, settings, diag);
  const RenderOutput out = renderer.render(b);
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("broken"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[0].find("image"), std::string::npos) << diag.errors[0];
  EXPECT_EQ(out.rgba.at(40, 30, 2), 255);  // the good photograph textures the view
  EXPECT_EQ(renderer.lastPlan().images.size(), 1u);
}

}  // namespace
}  // namespace hv::render

namespace hv::render {
namespace {

// Time: a photograph does not texture a building that did not exist at its date, and
// sees through it in its depth map.
TEST_F(RendererGlTest, PhotographsIgnoreBuildingsThatDidNotExistAtTheirDate) {
  const glm::dvec3 o = kStreetOrigin;
  Mesh all;
  {
    Scene s = testing::streetScene();
    all = s.terrain;
    all.append(s.buildings);
  }
  RayCaster caster(all);
  auto scenario = [&](const std::string& photoDate, int& hiddenRed, int& nearRed, int& hiddenTotal) {
    Scene scene = testing::streetScene();
    // Tag the buildings: 0 = near (built in 1950), 1 = far (always there).
    scene.buildings.triangleTags.assign(scene.buildings.triangles.size(), 1);
    for (size_t t = 0; t < 12; ++t) scene.buildings.triangleTags[t] = 0;  // the near box's 12 triangles come first
    DateInterval builtIn1950;
    builtIn1950.first = parseDate("1950")->first;
    scene.buildingValidity = {builtIn1950, DateInterval{}};
    addPhoto(scene, testing::lookAt("red", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 30, 10), 160, 120, 110),
             testing::solidImage(160, 120, 255, 0, 0));
    scene.photos.back().date = photoDate;
    Diagnostics diag;
    RenderSettings settings;
    settings.blend.k = 1;
    settings.depthSize = 512;
    Renderer renderer(scene, settings, diag);
    const Camera& red = scene.photos[0].camera;
    hiddenRed = nearRed = hiddenTotal = 0;
    // View of the far façade from between the buildings: which part is hidden from the photo today?
    const Camera back = testing::lookAt("v", o + glm::dvec3(0, 20, 6), o + glm::dvec3(0, 30, 8), 160, 120, 80);
    RenderOutput out = renderer.render(back);
    for (int y = 0; y < back.height; y += 3)
      for (int x = 0; x < back.width; x += 3) {
        const auto hit = caster.intersect(back.center, back.rayDirection({x + 0.5, y + 0.5}), 0.0, 1e9);
        if (!hit || hit->normal.y > -0.9 || !red.project(hit->position).inImage) continue;
        const glm::dvec3 toP = hit->position - red.center;
        if (glm::length(toP) - caster.intersect(red.center, toP, 0.0, 1e9)->t < 1.0) continue;
        ++hiddenTotal;  // behind the near building as seen from the photograph
        hiddenRed += out.rgba.at(x, y, 3) > 0;
      }
    // View of the near building's front: does it receive the photograph's pixels?
    const Camera front = testing::lookAt("f", o + glm::dvec3(0, 2, 6), o + glm::dvec3(0, 10, 6), 80, 60, 40);
    out = renderer.render(front);
    nearRed = out.rgba.at(40, 30, 3) > 0 ? 1 : 0;
    EXPECT_TRUE(diag.ok());
  };
  int hiddenRed = 0, nearRed = 0, hidden = 0;
  scenario("1905-06-01", hiddenRed, nearRed, hidden);
  EXPECT_GT(hidden, 50);
  EXPECT_EQ(hiddenRed, hidden) << "a 1905 photograph sees the far façade through the 1950 building";
  EXPECT_EQ(nearRed, 0) << "a 1905 photograph must not texture a building built in 1950";
  scenario("1960", hiddenRed, nearRed, hidden);
  EXPECT_EQ(hiddenRed, 0) << "in 1960 the near building hides the far façade";
  EXPECT_EQ(nearRed, 1);
}

}  // namespace
}  // namespace hv::render
