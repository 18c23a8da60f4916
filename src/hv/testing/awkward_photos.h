// Photographs whose every field is awkward to carry (doubles that are not short in decimal, every
// lens model, dates at every precision, a mask, a colour correction, a name in another script),
// and the comparison of two photographs field by field: for the tests of what writes cameras and
// reads them back (PostGIS catalog, OGR layers, the browser's GeoJSON reader).
#pragma once

#include "hv/camera/camera.h"
#include "hv/scene/scene.h"

#include <gtest/gtest.h>

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace hv::testing {

// A pinhole camera `cam<i>` with awkward doubles everywhere, turned by an angle that is not a
// multiple of anything, its image at /photos/cam<i>.jpg.
inline Photo awkwardPhoto(int i) {
  const double t = 0.1 + 0.7 * i;
  const std::string id = "cam" + std::to_string(i);
  Camera c = lookAtCamera(id, glm::dvec3(651234.123456789 + i / 3.0, 6861234.98765432 - i / 7.0, 35.3 + 1.0 / 3.0),
                          glm::dvec3(651250.0 + std::sin(t), 6861240.0 + std::cos(t), 30.1), 1000 + i, 700 + i,
                          812.3456789012345 + i / 9.0);
  c.focal.y = c.focal.x * (1.0 + 1e-7);
  c.principal += glm::dvec2(1.0 / 3.0, -2.0 / 7.0);
  c.skew = 1e-9 / 3.0;
  Photo p;
  p.camera = c;
  p.imagePath = "/photos/" + id + ".jpg";
  return p;
}

// Five awkward photographs: cam0 with MicMac's radial polynomial in pixels (Brédif 2013), cam1
// with COLMAP / OpenCV's (normalised by the focal lengths, tangential terms) and a mask, cam2 with
// iTowns' equilinear fish-eye and its affine terms; dates to the year, the month and the second;
// a colour correction on cam3; cam4 named in other scripts.
inline std::vector<Photo> awkwardPhotos() {
  std::vector<Photo> photos;
  for (int i = 0; i < 5; ++i) photos.push_back(awkwardPhoto(i));
  LensDistortion radial;
  radial.center = {501.0 / 3.0, 349.9};
  radial.c3 = 1.2345678901234e-8, radial.c5 = -3.3e-15 / 7.0, radial.c7 = 2e-22 / 3.0, radial.r2max = 1234567.891;
  photos[0].camera.distortion = radial;
  LensDistortion opencv;
  opencv.center = photos[1].camera.principal;
  opencv.scale = photos[1].camera.focal;
  opencv.c3 = 0.1 / 3.0, opencv.c5 = -0.02, opencv.c7 = 1e-3 / 7.0, opencv.p1 = 1e-4 / 3.0, opencv.p2 = -2e-4 / 9.0;
  photos[1].camera.distortion = opencv;
  LensDistortion fisheye;
  fisheye.model = LensDistortion::Model::Fisheye;
  fisheye.center = {512.25, 384.75};
  fisheye.scale = {600.0 / 7.0, 600.0 / 7.0};
  fisheye.c3 = -0.01 / 3.0, fisheye.l1 = 1e-5 / 3.0, fisheye.l2 = -2e-5 / 7.0, fisheye.r2max = 3.7;
  photos[2].camera.distortion = fisheye;
  photos[0].date = "1905";
  photos[1].date = "1905-06";
  photos[2].date = "1905-06-01T10:30:00+01:00";
  photos[1].maskPath = "/photos/masks/cam1.png";
  photos[3].colour.gain = {1.1 / 3.0, 0.9, 1.0 + 1e-15};
  photos[3].colour.offset = {-0.01 / 7.0, 0.0, 0.02};
  photos[4].camera.id = "Île de la Cité, n° 4 — 照片";
  photos[4].imagePath = "/photos/Île de la Cité 4.jpg";
  return photos;
}

// `b` equals `a` to `rel` relative (0: bit for bit, compared with ==).
inline void expectNearRelative(double a, double b, double rel, const char* what) {
  if (rel == 0)
    EXPECT_EQ(a, b) << what;
  else
    EXPECT_LE(std::abs(a - b), rel * std::max(std::abs(a), 1e-300)) << what << ": " << a << " vs " << b;
}

// Every field of a Photo: the doubles to `rel` relative (0: bit for bit), the rest equal.
inline void expectSamePhoto(const Photo& a, const Photo& b, double rel = 0.0) {
  const Camera &x = a.camera, &y = b.camera;
  SCOPED_TRACE("camera '" + x.id + "'");
  EXPECT_EQ(x.id, y.id);
  EXPECT_EQ(x.width, y.width);
  EXPECT_EQ(x.height, y.height);
  for (int i = 0; i < 3; ++i) expectNearRelative(x.center[i], y.center[i], rel, "centre");
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) expectNearRelative(x.camFromWorld[i][j], y.camFromWorld[i][j], rel, "cam_from_world");
  for (int i = 0; i < 2; ++i) expectNearRelative(x.focal[i], y.focal[i], rel, "focal");
  for (int i = 0; i < 2; ++i) expectNearRelative(x.principal[i], y.principal[i], rel, "principal");
  expectNearRelative(x.skew, y.skew, rel, "skew");
  ASSERT_EQ(x.distortion.has_value(), y.distortion.has_value());
  if (x.distortion) {
    const LensDistortion &d = *x.distortion, &e = *y.distortion;
    EXPECT_EQ(d.model, e.model);
    const double u[] = {d.center.x, d.center.y, d.scale.x, d.scale.y, d.c3, d.c5,
                        d.c7,       d.p1,       d.p2,      d.l1,      d.l2, d.r2max};
    const double v[] = {e.center.x, e.center.y, e.scale.x, e.scale.y, e.c3, e.c5,
                        e.c7,       e.p1,       e.p2,      e.l1,      e.l2, e.r2max};
    for (int i = 0; i < 12; ++i) expectNearRelative(u[i], v[i], rel, "distortion");
  }
  EXPECT_EQ(a.imagePath, b.imagePath);
  EXPECT_EQ(a.maskPath, b.maskPath);
  EXPECT_EQ(a.date, b.date);
  for (int i = 0; i < 3; ++i) expectNearRelative(a.colour.gain[i], b.colour.gain[i], rel, "colour_gain");
  for (int i = 0; i < 3; ++i) expectNearRelative(a.colour.offset[i], b.colour.offset[i], rel, "colour_offset");
}

inline void expectSamePhotos(const std::vector<Photo>& a, const std::vector<Photo>& b, double rel = 0.0) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) expectSamePhoto(a[i], b[i], rel);
}

}  // namespace hv::testing
