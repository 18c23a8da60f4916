#include "hv/camera/camera.h"

#include "hv/util/diagnostics.h"

#include <Eigen/SVD>  // header-only; SVD for re-orthonormalisation

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hv {

bool RadialDistortion::inDomain(glm::dvec2 pxIdeal) const {
  const glm::dvec2 r = pxIdeal - center;
  return glm::dot(r, r) <= r2max;
}

glm::dvec2 RadialDistortion::distort(glm::dvec2 pxIdeal) const {
  const glm::dvec2 r = pxIdeal - center;
  const double r2 = glm::dot(r, r);
  return pxIdeal + r * (r2 * (c3 + r2 * (c5 + r2 * c7)));
}

std::optional<glm::dvec2> RadialDistortion::undistort(glm::dvec2 pxDistorted) const {
  // Radial: p_d - center = r (1 + c3 s^2 + c5 s^4 + c7 s^6) with s = |r|. Solve for s with
  // Newton on g(s) = s (1 + c3 s^2 + c5 s^4 + c7 s^6) - |r_d|.
  const glm::dvec2 rd = pxDistorted - center;
  const double sd = glm::length(rd);
  if (sd == 0.0) return pxDistorted;
  double s = sd;
  for (int it = 0; it < 50; ++it) {
    const double s2 = s * s;
    const double g = s * (1 + s2 * (c3 + s2 * (c5 + s2 * c7))) - sd;
    const double dg = 1 + s2 * (3 * c3 + s2 * (5 * c5 + s2 * 7 * c7));
    if (dg <= 0.0) return std::nullopt;  // beyond the turning point: not invertible here
    const double step = g / dg;
    s -= step;
    if (s < 0.0) return std::nullopt;
    if (std::abs(step) < 1e-12 * (1.0 + sd)) break;
  }
  const glm::dvec2 p = center + rd * (s / sd);
  if (!inDomain(p)) return std::nullopt;
  if (glm::length(distort(p) - pxDistorted) > 1e-6 * (1.0 + sd)) return std::nullopt;
  return p;
}

glm::dmat3 Camera::pixFromCam() const {
  glm::dmat3 k(0.0);
  k[0][0] = focal.x;
  k[1][0] = skew;
  k[2][0] = principal.x;
  k[1][1] = focal.y;
  k[2][1] = principal.y;
  k[2][2] = 1.0;
  return k;
}

glm::dmat3 Camera::camFromPix() const { return glm::inverse(pixFromCam()); }

Projection Camera::project(const glm::dvec3& world) const {
  Projection out;
  const glm::dvec3 ph = pixFromWorld() * (world - center);
  out.depth = ph.z;
  out.inFront = ph.z > 0.0;
  if (!out.inFront) return out;
  out.pxIdeal = glm::dvec2(ph.x, ph.y) / ph.z;
  out.inDistortionDomain = !distortion || distortion->inDomain(out.pxIdeal);
  out.pxDistorted = distort(out.pxIdeal);
  out.inImage = out.inDistortionDomain && out.pxDistorted.x >= 0.0 && out.pxDistorted.y >= 0.0 &&
                out.pxDistorted.x <= width && out.pxDistorted.y <= height;
  return out;
}

glm::dvec2 Camera::distort(glm::dvec2 pxIdeal) const {
  return distortion ? distortion->distort(pxIdeal) : pxIdeal;
}

std::optional<glm::dvec2> Camera::undistort(glm::dvec2 pxDistorted) const {
  if (!distortion) return pxDistorted;
  return distortion->undistort(pxDistorted);
}

glm::dvec3 Camera::rayDirection(glm::dvec2 pxIdeal) const {
  const glm::dvec3 dirCam = camFromPix() * glm::dvec3(pxIdeal, 1.0);
  return glm::transpose(camFromWorld) * dirCam;
}

Camera Camera::scaled(double s, int newWidth, int newHeight) const {
  Camera c = *this;
  c.width = newWidth;
  c.height = newHeight;
  c.focal *= s;
  c.principal *= s;
  c.skew *= s;
  if (c.distortion) {
    // p'_d = s p_d  with p' = s p:  r' = s r, so c3' = c3 / s^2, c5' = c5 / s^4, c7' = c7 / s^6.
    RadialDistortion& d = *c.distortion;
    d.center *= s;
    d.c3 /= s * s;
    d.c5 /= std::pow(s, 4);
    d.c7 /= std::pow(s, 6);
    d.r2max *= s * s;
  }
  return c;
}

Camera Camera::resized(int newWidth, int newHeight) const {
  if (newWidth == width && newHeight == height) return *this;
  const double s = double(newWidth) / width;
  if (newWidth <= 0 || newHeight <= 0 || std::abs(height * s - newHeight) > 1.0)
    throw std::invalid_argument("camera '" + id + "' is " + std::to_string(width) + "x" + std::to_string(height) +
                                ", cannot be resized to " + std::to_string(newWidth) + "x" +
                                std::to_string(newHeight) + " (a different aspect ratio)");
  return scaled(s, newWidth, newHeight);
}

Camera lookAtCamera(const std::string& id, const glm::dvec3& center, const glm::dvec3& target, int width,
                    int height, double focal, const glm::dvec3& up) {
  Camera c;
  c.id = id;
  c.width = width;
  c.height = height;
  c.center = center;
  const glm::dvec3 z = glm::normalize(target - center);
  const glm::dvec3 x = glm::normalize(glm::cross(z, up));
  const glm::dvec3 y = glm::cross(z, x);  // image down
  c.camFromWorld = glm::transpose(glm::dmat3(x, y, z));  // rows of R: the camera axes in the world
  c.focal = {focal, focal};
  c.principal = {width / 2.0, height / 2.0};
  return c;
}

glm::dmat3 orthonormalize(const glm::dmat3& m) {
  Eigen::Matrix3d a;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a(r, c) = m[c][r];
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(a, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d q = svd.matrixU() * svd.matrixV().transpose();
  glm::dmat3 out;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[c][r] = q(r, c);
  return out;
}

glm::dmat3 mat3FromRowMajor(const double* v) {
  glm::dmat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m[c][r] = v[3 * r + c];
  return m;
}

void mat3ToRowMajor(const glm::dmat3& m, double* v) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) v[3 * r + c] = m[c][r];
}

namespace {
bool finite(const glm::dvec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }
bool finite(const glm::dvec2& v) { return std::isfinite(v.x) && std::isfinite(v.y); }
}  // namespace

void validateCamera(Camera& cam, double orthoTolerance) {
  auto fail = [&](const std::string& field, const std::string& what) {
    throw InputError("camera '" + cam.id + "': " + field + ": " + what);
  };
  if (cam.width <= 0 || cam.height <= 0) fail("width/height", "expected positive image size");
  if (!finite(cam.center)) fail("center", "expected 3 finite numbers");
  if (!finite(cam.focal) || cam.focal.x <= 0.0 || cam.focal.y <= 0.0)
    fail("focal", "expected two positive finite numbers");
  if (!finite(cam.principal)) fail("principal", "expected 2 finite numbers");
  if (!std::isfinite(cam.skew)) fail("skew", "expected a finite number");
  for (int c = 0; c < 3; ++c)
    if (!finite(cam.camFromWorld[c])) fail("rotation", "expected 9 finite numbers");
  const glm::dmat3 rrt = cam.camFromWorld * glm::transpose(cam.camFromWorld);
  double defect = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) defect = std::max(defect, std::abs(rrt[c][r] - (r == c ? 1.0 : 0.0)));
  if (defect > orthoTolerance) {
    std::ostringstream s;
    s << "not orthonormal (max |R R^T - I| = " << defect << " > " << orthoTolerance << ")";
    fail("rotation", s.str());
  }
  if (defect > 0.0) cam.camFromWorld = orthonormalize(cam.camFromWorld);
  if (glm::determinant(cam.camFromWorld) < 0.0) fail("rotation", "expected a rotation (det = +1), got a reflection");
  if (cam.distortion) {
    const auto& d = *cam.distortion;
    if (!finite(d.center) || !std::isfinite(d.c3) || !std::isfinite(d.c5) || !std::isfinite(d.c7) ||
        std::isnan(d.r2max) || d.r2max <= 0.0)
      fail("distortion", "expected finite center, c3, c5, c7 and a positive r2max");
  }
}

}  // namespace hv
