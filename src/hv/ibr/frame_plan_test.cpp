#include "hv/ibr/frame_plan.h"

#include "hv/ibr/reference_blend.h"
#include "hv/ibr/slice_image.h"
#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <random>

namespace hv::ibr {
namespace {

Camera testCamera(glm::dvec3 center) {
  Camera c;
  c.id = "c";
  c.width = 400;
  c.height = 300;
  c.center = center;
  const double r[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};  // looking along +y, z up
  c.camFromWorld = mat3FromRowMajor(r);
  c.focal = {350.0, 350.0};
  c.principal = {190.0, 160.0};
  c.skew = 1.5;
  return c;
}

TEST(ClipFromRender, AgreesWithCameraProjection) {
  const glm::dvec3 origin(651000.0, 6862000.0, 40.0);
  const Camera cam = testCamera(origin + glm::dvec3(3.0, -20.0, 2.0));
  PinholeFrustum fr;
  fr.pxMin = {-10.0, -20.0};
  fr.pxMax = {420.0, 310.0};
  fr.near = 0.5;
  fr.far = 200.0;
  const glm::dmat4 clip = clipFromRender(cam, fr, origin);
  for (glm::dvec3 P : {glm::dvec3(651001.0, 6862010.0, 41.0), glm::dvec3(650990.0, 6862100.0, 30.0)}) {
    const Projection p = cam.project(P);
    const glm::dvec4 c = clip * glm::dvec4(P - origin, 1.0);
    EXPECT_NEAR(c.w, p.depth, 1e-9);
    const glm::dvec2 ndc = glm::dvec2(c) / c.w;
    // NDC y = -1 is the top of the rectangle (pxMin.y).
    EXPECT_NEAR(fr.pxMin.x + (ndc.x + 1.0) / 2.0 * (fr.pxMax.x - fr.pxMin.x), p.pxIdeal.x, 1e-7);
    EXPECT_NEAR(fr.pxMin.y + (ndc.y + 1.0) / 2.0 * (fr.pxMax.y - fr.pxMin.y), p.pxIdeal.y, 1e-7);
  }
  // near -> ndc z = -1, far -> +1.
  const glm::dvec3 axis = glm::transpose(cam.camFromWorld)[2];
  for (auto [z, expected] : {std::pair{0.5, -1.0}, std::pair{200.0, 1.0}}) {
    const glm::dvec4 c = clip * glm::dvec4(cam.center + z * axis - origin, 1.0);
    EXPECT_NEAR(c.z / c.w, expected, 1e-9);
  }
}

TEST(IdealRect, CoversTheDistortedImage) {
  Camera cam = testCamera({0, 0, 0});
  EXPECT_EQ(idealRectCoveringImage(cam).pxMin, glm::dvec2(0.0));
  EXPECT_EQ(idealRectCoveringImage(cam).pxMax, glm::dvec2(400.0, 300.0));
  LensDistortion d;
  d.center = {200.0, 150.0};
  d.c3 = -1.5e-6;  // barrel: the image corners come from ideal points farther out
  d.r2max = 400.0 * 400.0;
  cam.distortion = d;
  const PinholeFrustum fr = idealRectCoveringImage(cam);
  for (glm::dvec2 corner : {glm::dvec2(0, 0), glm::dvec2(400, 0), glm::dvec2(0, 300), glm::dvec2(400, 300)}) {
    const auto ideal = cam.undistort(corner);
    ASSERT_TRUE(ideal.has_value());
    EXPECT_LE(fr.pxMin.x, ideal->x + 1e-9);
    EXPECT_LE(fr.pxMin.y, ideal->y + 1e-9);
    EXPECT_GE(fr.pxMax.x, ideal->x - 1e-9);
    EXPECT_GE(fr.pxMax.y, ideal->y - 1e-9);
  }
  EXPECT_LT(fr.pxMin.x, -1.0);  // strictly larger than the image
}

TEST(DepthRange, BracketsTheSceneBounds) {
  const Camera cam = testCamera({0, -10, 0});
  Aabb b;
  b.extend({-5, 0, -1});
  b.extend({5, 30, 4});
  PinholeFrustum fr;
  setDepthRange(fr, cam, b);
  EXPECT_NEAR(fr.far, 40.0 * 1.01, 1e-9);
  EXPECT_NEAR(fr.near, 10.0 * 0.99, 1e-9);
}

TEST(PackImageParams, LayoutMatchesTheShaderReader) {
  Camera cam = testCamera({1, 2, 3});
  LensDistortion d;
  d.center = {201.0, 151.0};
  d.c3 = 1e-7;
  d.c5 = 2e-13;
  d.c7 = 3e-19;
  d.r2max = 9e4;
  cam.distortion = d;
  PinholeFrustum fr;
  fr.pxMin = {-4.0, -2.0};
  fr.pxMax = {404.0, 302.0};
  fr.near = 0.25;
  fr.far = 99.0;
  const ImageParams p = makeImageParams(cam, {1, 1, 1}, SliceLayout{7, {0.5, 0.25}}, 0.125, fr, {0.05, 0.01});
  float o[kTexelsPerImage * 4];
  packImageParams(p, o);
  const glm::dmat3 M = cam.pixFromWorld();
  EXPECT_FLOAT_EQ(o[0], float(M[0][0]));
  EXPECT_FLOAT_EQ(o[1], float(M[1][0]));  // row 0, column 1
  EXPECT_FLOAT_EQ(o[4], float(M[0][1]));  // row 1, column 0
  EXPECT_FLOAT_EQ(o[3], 0.0f);            // C_render.x = 1 - 1
  EXPECT_FLOAT_EQ(o[7], 1.0f);
  EXPECT_FLOAT_EQ(o[11], 2.0f);
  EXPECT_FLOAT_EQ(o[12], 201.0f);
  EXPECT_FLOAT_EQ(o[14], 1e-7f);
  EXPECT_FLOAT_EQ(o[16], 3e-19f);
  EXPECT_FLOAT_EQ(o[17], 9e4f);
  EXPECT_FLOAT_EQ(o[18], 400.0f);
  EXPECT_FLOAT_EQ(o[19], 300.0f);
  EXPECT_FLOAT_EQ(o[20], 0.5f);
  EXPECT_FLOAT_EQ(o[22], 7.0f);
  EXPECT_FLOAT_EQ(o[23], 0.125f);
  EXPECT_FLOAT_EQ(o[24], -4.0f);
  EXPECT_FLOAT_EQ(o[26], float(1.0 / 408.0));
  EXPECT_FLOAT_EQ(o[28], 0.25f);
  EXPECT_FLOAT_EQ(o[29], 99.0f);
  EXPECT_FLOAT_EQ(o[30], 0.05f);
  EXPECT_FLOAT_EQ(o[31], 0.01f);
  EXPECT_FLOAT_EQ(o[32], -1e7f);  // undated: open interval
  EXPECT_FLOAT_EQ(o[33], 1e7f);
  EXPECT_FLOAT_EQ(o[34], 350.0f);  // the focal length, for the geometry weights' footprints
  EXPECT_FLOAT_EQ(o[36], 1.0f);    // a pixel polynomial: scale 1, no tangential or affine terms
  EXPECT_FLOAT_EQ(o[38], 0.0f);
  EXPECT_FLOAT_EQ(o[42], 0.0f);  // polynomial model
  for (int c = 0; c < 3; ++c) {  // no correction: gain 1, offset 0 (t11, t12)
    EXPECT_FLOAT_EQ(o[44 + c], 1.0f);
    EXPECT_FLOAT_EQ(o[48 + c], 0.0f);
  }
  // A photograph as it is: no layer, no group, no uv offset (t8.w, t10.w, t11.w, t12.w).
  EXPECT_EQ(o[35], 0.0f);
  EXPECT_EQ(o[43], 0.0f);
  EXPECT_EQ(o[47], 0.0f);
  EXPECT_EQ(o[51], 0.0f);
  // A layered photograph's sub-image (Layered projective texture maps, 2003, §5.1).
  ImageParams sub = p;
  sub.layer = 2;
  sub.group = 5;
  sub.uvOffset = {120.5, 33.0};
  float os[kTexelsPerImage * 4];
  packImageParams(sub, os);
  EXPECT_EQ(os[35], 2.0f);
  EXPECT_EQ(os[43], 5.0f);
  EXPECT_EQ(os[47], 120.5f);
  EXPECT_EQ(os[51], 33.0f);
  for (int i = 0; i < kTexelsPerImage * 4; ++i)
    if (i != 35 && i != 43 && i != 47 && i != 51) EXPECT_EQ(os[i], o[i]) << "float " << i;
  ImageParams corrected = p;
  corrected.colour = {{1.25, 0.5, 2.0}, {-0.125, 0.25, 0.0625}};
  packImageParams(corrected, o);
  EXPECT_FLOAT_EQ(o[44], 1.25f);
  EXPECT_FLOAT_EQ(o[45], 0.5f);
  EXPECT_FLOAT_EQ(o[46], 2.0f);
  EXPECT_FLOAT_EQ(o[48], -0.125f);
  EXPECT_FLOAT_EQ(o[49], 0.25f);
  EXPECT_FLOAT_EQ(o[50], 0.0625f);
  cam.distortion->model = LensDistortion::Model::Fisheye;
  cam.distortion->scale = {700.0, 710.0};
  cam.distortion->p2 = 0.25;
  cam.distortion->l1 = 0.5;
  packImageParams(makeImageParams(cam, {0, 0, 0}, {}, 1.0, fr, {}), o);
  EXPECT_FLOAT_EQ(o[36], 700.0f);
  EXPECT_FLOAT_EQ(o[37], 710.0f);
  EXPECT_FLOAT_EQ(o[39], 0.25f);
  EXPECT_FLOAT_EQ(o[40], 0.5f);
  EXPECT_FLOAT_EQ(o[42], 1.0f);  // fish-eye
  cam.distortion.reset();
  packImageParams(makeImageParams(cam, {0, 0, 0}, {}, 1.0, fr, {}), o);
  EXPECT_LT(o[17], 0.0f);  // no distortion
}

TEST(SliceLayout, FoldsScaleIntoUv) {
  Camera cam = testCamera({0, 0, 0});
  // Fits as is: uv = p / slice size, no resampling.
  SliceLayout l = sliceLayout(cam, {500, 400}, 3);
  EXPECT_EQ(l.slice, 3);
  EXPECT_DOUBLE_EQ(l.uvScale.x, 1.0 / 500.0);
  EXPECT_DOUBLE_EQ(l.uvScale.y, 1.0 / 400.0);
  // Too big: scaled by 0.5 into 200x150 texels of a 200x200 slice; the far corner maps to (1, 0.75).
  l = sliceLayout(cam, {200, 200}, 0);
  EXPECT_DOUBLE_EQ(400.0 * l.uvScale.x, 1.0);
  EXPECT_DOUBLE_EQ(300.0 * l.uvScale.y, 0.75);
}

TEST(SliceImage, PremultipliesAndAppliesMask) {
  Camera cam = testCamera({0, 0, 0});
  cam.width = 4;
  cam.height = 2;
  Image8 photo(4, 2, 3, 200);
  Image8 mask(4, 2, 1, 255);
  mask.at(1, 0, 0) = 0;
  const Image8 s = makeSliceImage(cam, photo, mask, {6, 3}, "t");
  EXPECT_EQ(s.width, 6);
  EXPECT_EQ(s.at(0, 0, 0), 200);
  EXPECT_EQ(s.at(0, 0, 3), 255);
  EXPECT_EQ(s.at(1, 0, 0), 0);  // masked: premultiplied to transparent black
  EXPECT_EQ(s.at(1, 0, 3), 0);
  EXPECT_EQ(s.at(5, 2, 3), 0);  // padding
  EXPECT_THROW(makeSliceImage(cam, Image8(3, 3, 3), {}, {6, 3}, "t"), InputError);
}

TEST(ReferenceBlend, NormalisesMasksAndPicksNearest) {
  // Two cameras looking at the same point; texture colours are constant per slice.
  const Camera a = testCamera({0, -10, 0}), b = testCamera({1, -10, 0});
  PinholeFrustum fr;
  fr.pxMax = {400, 300};
  std::vector<ImageParams> images = {makeImageParams(a, {0, 0, 0}, {0, {1.0 / 400, 1.0 / 300}}, 3.0, fr, {}),
                                     makeImageParams(b, {0, 0, 0}, {1, {1.0 / 400, 1.0 / 300}}, 1.0, fr, {})};
  glm::dvec4 colour[2] = {{0.8, 0.0, 0.0, 1.0}, {0.0, 0.4, 0.0, 1.0}};
  TextureLookup tex = [&](int slice, glm::dvec2) { return colour[slice]; };
  const glm::dvec3 P(0.5, 0.0, 0.0);
  BlendResult r = referenceBlend(P, images, BlendMethod::Blend, tex, {});
  EXPECT_EQ(r.count, 2);
  EXPECT_NEAR(r.color.r, 0.8 * 3.0 / 4.0, 1e-12);
  EXPECT_NEAR(r.color.g, 0.4 * 1.0 / 4.0, 1e-12);
  // Mask (alpha 0) in the first: the second fills the pixel alone, at full colour.
  colour[0] = glm::dvec4(0.0);
  r = referenceBlend(P, images, BlendMethod::Blend, tex, {});
  EXPECT_EQ(r.count, 1);
  EXPECT_NEAR(r.color.g, 0.4, 1e-12);
  // Nearest: first passing image; occluded images are skipped.
  colour[0] = {0.8, 0.0, 0.0, 1.0};
  r = referenceBlend(P, images, BlendMethod::Nearest, tex, [](size_t i, const glm::dvec3&, double) { return i != 0; });
  EXPECT_NEAR(r.color.g, 0.4, 1e-12);
  EXPECT_NEAR(r.color.r, 0.0, 1e-12);
  // Behind both cameras: nothing.
  EXPECT_FALSE(referenceBlend({0, -20, 0}, images, BlendMethod::Blend, tex, {}).covered());
}

TEST(SampleBilinear, MatchesTexelCentres) {
  Image8 img(2, 1, 4, 0);
  img.at(0, 0, 0) = 0;
  img.at(1, 0, 0) = 255;
  EXPECT_NEAR(sampleBilinear(img, {0.25, 0.5}).r, 0.0, 1e-12);  // centre of texel 0
  EXPECT_NEAR(sampleBilinear(img, {0.5, 0.5}).r, 0.5, 1e-12);   // halfway
  EXPECT_NEAR(sampleBilinear(img, {1.0, 0.5}).r, 1.0, 1e-12);   // clamp to edge
}

}  // namespace
}  // namespace hv::ibr

namespace hv::ibr {
namespace {

TEST(ShadowBias, GrowsWithTheTangentOfIncidence) {
  const DepthBias b{0.05, 0.002};
  EXPECT_DOUBLE_EQ(shadowBias(b, 10.0, 1.0), 0.05 + 0.02);                                    // facing: tan 0
  EXPECT_NEAR(shadowBias(b, 10.0, std::cos(M_PI / 4)), 0.05 + 0.04, 1e-12);                   // 45 degrees: tan 1
  EXPECT_NEAR(shadowBias(b, 10.0, 0.0), 0.05 + 0.02 * (1.0 + std::sqrt(0.99) / 0.1), 1e-12);  // clamped
}

}  // namespace
}  // namespace hv::ibr

namespace hv::ibr {
namespace {

TEST(FrustumFilter, KeepsPhotographsThatSeeTheView) {
  Aabb street;
  street.extend({-20, 0, 0});
  street.extend({20, 60, 15});
  // The view looks along +y into the street from its south end.
  const FrustumCorners view = sceneFrustum(testCamera({0, -2, 1.7}), street);
  // Same direction, a few metres ahead: sees the same street.
  EXPECT_TRUE(frustaOverlap(view, sceneFrustum(testCamera({2, 5, 1.7}), street)));
  // Turned around, behind the view, looking out of the street: no common point.
  Camera away = testCamera({0, -3, 1.7});
  const double r[9] = {-1, 0, 0, 0, 0, -1, 0, -1, 0};
  away.camFromWorld = mat3FromRowMajor(r);
  EXPECT_FALSE(frustaOverlap(view, sceneFrustum(away, street)));
  // Far ahead looking back towards the view: the frusta meet.
  Camera back = testCamera({0, 50, 1.7});
  back.camFromWorld = mat3FromRowMajor(r);
  EXPECT_TRUE(frustaOverlap(view, sceneFrustum(back, street)));
}

TEST(FrustumFilter, SeparatingAxesAgreeWithPointSampling) {
  // Two frusta overlap iff some point lies in both: compare with dense sampling of one of them.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Aabb box;
  box.extend({-30, -30, 0});
  box.extend({30, 30, 20});
  int overlaps = 0, separated = 0;
  for (int trial = 0; trial < 60; ++trial) {
    Camera a = testCamera({60 * u(rng) - 30, 60 * u(rng) - 30, 20 * u(rng)});
    Camera b = testCamera({60 * u(rng) - 30, 60 * u(rng) - 30, 20 * u(rng)});
    const double ya = 2 * M_PI * u(rng), yb = 2 * M_PI * u(rng);
    auto yaw = [](double t) {
      const double r[9] = {std::cos(t + M_PI / 2), std::sin(t + M_PI / 2), 0, 0, 0, -1, std::cos(t), std::sin(t), 0};
      return mat3FromRowMajor(r);
    };
    a.camFromWorld = yaw(ya);
    b.camFromWorld = yaw(yb);
    a.distortion.reset();
    b.distortion.reset();
    const FrustumCorners fa = sceneFrustum(a, box), fb = sceneFrustum(b, box);
    PinholeFrustum ra = idealRectCoveringImage(a);
    setDepthRange(ra, a, box);
    PinholeFrustum rb = idealRectCoveringImage(b);
    setDepthRange(rb, b, box);
    bool sampledOverlap = false;
    for (int i = 0; i < 20000 && !sampledOverlap; ++i) {
      const glm::dvec2 px = glm::mix(ra.pxMin, ra.pxMax, glm::dvec2(u(rng), u(rng)));
      const double z = ra.near + u(rng) * (ra.far - ra.near);
      const glm::dvec3 P = a.center + z * a.rayDirection(px);
      const Projection p = b.project(P);
      sampledOverlap = p.inFront && p.depth >= rb.near && p.depth <= rb.far && p.pxIdeal.x >= rb.pxMin.x &&
                       p.pxIdeal.x <= rb.pxMax.x && p.pxIdeal.y >= rb.pxMin.y && p.pxIdeal.y <= rb.pxMax.y;
    }
    const bool sat = frustaOverlap(fa, fb);
    if (sampledOverlap) EXPECT_TRUE(sat) << "trial " << trial;  // never a false "separated"
    overlaps += sat;
    separated += !sat;
  }
  EXPECT_GT(overlaps, 5);
  EXPECT_GT(separated, 5);
}

}  // namespace
}  // namespace hv::ibr
