#include "hv/camera/camera.h"

#include "hv/util/diagnostics.h"
#include "hv/util/log.h"

#include <Eigen/SVD>  // header-only; SVD for re-orthonormalisation

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace hv {

namespace {

// The displacement x_d - x of the model in normalised coordinates (camera.h, LensDistortion).
glm::dvec2 displacement(const LensDistortion& d, glm::dvec2 x) {
  glm::dvec2 a = x;
  if (d.model == LensDistortion::Model::Fisheye) {
    const double r = glm::length(x);
    if (r > 0.0) a = x * (std::atan(r) / r);
  }
  const double r2 = glm::dot(a, a);
  glm::dvec2 out = a * (r2 * (d.c3 + r2 * (d.c5 + r2 * d.c7))) + (a - x);
  out += glm::dvec2(2.0 * d.p1 * a.x * a.y + d.p2 * (r2 + 2.0 * a.x * a.x),
                    d.p1 * (r2 + 2.0 * a.y * a.y) + 2.0 * d.p2 * a.x * a.y);
  out += glm::dvec2(d.l1 * a.x - d.l2 * a.y, -d.l2 * a.x);
  return out;
}

bool purelyRadial(const LensDistortion& d) {
  return d.model == LensDistortion::Model::Polynomial && d.p1 == 0.0 && d.p2 == 0.0;
}

// Radial profile rho (1 + c3 rho^2 + c5 rho^4 + c7 rho^6) and its derivative.
double profileSlope(const LensDistortion& d, double rho) {
  const double r2 = rho * rho;
  return 1.0 + r2 * (3.0 * d.c3 + r2 * (5.0 * d.c5 + r2 * 7.0 * d.c7));
}

}  // namespace

bool LensDistortion::isIdentity() const {
  return model == Model::Polynomial && c3 == 0.0 && c5 == 0.0 && c7 == 0.0 && p1 == 0.0 && p2 == 0.0 &&
         l1 == 0.0 && l2 == 0.0;
}

bool LensDistortion::inDomain(glm::dvec2 pxIdeal) const {
  const glm::dvec2 x = (pxIdeal - center) / scale;
  return glm::dot(x, x) <= r2max;
}

glm::dvec2 LensDistortion::distort(glm::dvec2 pxIdeal) const {
  // Written as p + displacement so that a small distortion keeps full precision.
  return pxIdeal + scale * displacement(*this, (pxIdeal - center) / scale);
}

std::optional<glm::dvec2> LensDistortion::undistort(glm::dvec2 pxDistorted) const {
  const glm::dvec2 xd = (pxDistorted - center) / scale;
  const double sd = glm::length(xd);
  if (sd == 0.0) return pxDistorted;
  glm::dvec2 x;
  if (purelyRadial(*this)) {
    // x_d = x (1 + c3 s^2 + c5 s^4 + c7 s^6) with s = |x|: Newton on the radius.
    double s = sd;
    for (int it = 0; it < 50; ++it) {
      const double s2 = s * s;
      const double g = s * (1 + s2 * (c3 + s2 * (c5 + s2 * c7))) - sd;
      const double dg = profileSlope(*this, s);
      if (dg <= 0.0) return std::nullopt;  // beyond the turning point: not invertible here
      const double step = g / dg;
      s -= step;
      if (s < 0.0) return std::nullopt;
      if (std::abs(step) < 1e-12 * (1.0 + sd)) break;
    }
    x = xd * (s / sd);
  } else {
    // Newton in two dimensions on x + displacement(x) = x_d, Jacobian by central differences.
    x = xd;
    if (model == Model::Fisheye) {
      if (sd >= 1.5) return std::nullopt;  // beyond ~86 degrees from the axis
      x = xd * (std::tan(sd) / sd);
    }
    for (int it = 0; it < 50; ++it) {
      const glm::dvec2 f = x + displacement(*this, x) - xd;
      const double h = 1e-7 * (1.0 + glm::length(x));
      glm::dmat2 j;
      for (int k = 0; k < 2; ++k) {
        glm::dvec2 e(0.0);
        e[k] = h;
        j[k] = ((x + e + displacement(*this, x + e)) - (x - e + displacement(*this, x - e))) / (2.0 * h);
      }
      const double det = glm::determinant(j);
      if (!(std::abs(det) > 1e-12)) return std::nullopt;
      const glm::dvec2 step = glm::inverse(j) * f;
      x -= step;
      if (!std::isfinite(x.x) || !std::isfinite(x.y)) return std::nullopt;
      if (glm::length(step) < 1e-13 * (1.0 + glm::length(x))) break;
    }
  }
  const glm::dvec2 p = center + scale * x;
  if (!inDomain(p)) return std::nullopt;
  const double scalePx = std::max(scale.x, scale.y);
  if (glm::length(distort(p) - pxDistorted) > 1e-6 * (1.0 + sd * scalePx)) return std::nullopt;
  return p;
}

LensDistortion LensDistortion::scaled(double s) const {
  // Normalised coordinates do not change when pixels are scaled: only the centre and scale do.
  LensDistortion d = *this;
  d.center *= s;
  d.scale *= s;
  return d;
}

std::string LensDistortion::fitDomain() {
  std::ostringstream msg;
  // The radial profile is checked over the angle (fish-eye) or the radius (polynomial).
  const bool fisheye = model == Model::Fisheye;
  double limit = std::sqrt(std::min(r2max, 1e30));
  if (fisheye) limit = std::atan(limit);
  const double scanTo = std::min(limit, fisheye ? 3.2 : 1e6);
  // First zero of the slope: scan finely near the centre, coarser outwards, then bisect.
  double lo = 0.0, turn = -1.0;
  for (int i = 1; i <= 4000 && turn < 0.0; ++i) {
    const double rho = scanTo * std::pow(double(i) / 4000.0, 2.0);
    if (profileSlope(*this, rho) <= 0.0) {
      double a = lo, b = rho;
      for (int k = 0; k < 60; ++k) ((profileSlope(*this, 0.5 * (a + b)) > 0.0) ? a : b) = 0.5 * (a + b);
      turn = a;
    }
    lo = rho;
  }
  double newLimit = limit;
  if (turn >= 0.0 && turn < limit) {
    newLimit = 0.999 * turn;
    msg << "the radial profile turns back at " << turn << (fisheye ? " rad" : " (normalised radius)")
        << ", inside the domain (" << limit << "): domain shrunk to " << newLimit;
  }
  if (fisheye) {
    const double maxAngle = kFisheyeMaxAngleDeg * M_PI / 180.0;
    if (newLimit > maxAngle) {
      if (!msg.str().empty()) msg << "; ";
      msg << "field of view clipped to " << kFisheyeMaxAngleDeg
          << " degrees from the axis (a pinhole depth map cannot cover wider)";
      newLimit = maxAngle;
    }
    if (newLimit != limit) r2max = std::pow(std::tan(newLimit), 2);
  } else if (newLimit != limit) {
    r2max = newLimit * newLimit;
  }
  return msg.str();
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
    c.distortion = c.distortion->scaled(s);
  }
  return c;
}

Camera Camera::resized(int newWidth, int newHeight) const {
  if (newWidth == width && newHeight == height) return *this;
  const double s = double(newWidth) / width;
  if (newWidth <= 0 || newHeight <= 0 || std::abs(height * s - newHeight) > 1.0)
    throw std::invalid_argument("camera '" + id + "' is " + std::to_string(width) + "x" + std::to_string(height) +
                                ", cannot be resized to " + std::to_string(newWidth) + "x" + std::to_string(newHeight) +
                                " (a different aspect ratio; the nearest size of its "
                                "own: " +
                                std::to_string(newWidth) + "x" + std::to_string(std::max(1L, std::lround(height * s))) +
                                ")");
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

namespace {

// A polynomial lens that moves a corner of the photograph by more than its diagonal is no real
// lens: coefficients typed in the wrong unit (pixels for normalised, or the wrong power of the
// radius). Positive coefficients never turn back, so LensDistortion::fitDomain accepts them; the
// camera would project every point off the photograph without a word. Fish-eyes are left alone:
// their corners legitimately map far from a pinhole's.
void warnAbsurdLens(const Camera& camera, const std::string& where, Diagnostics& diag) {
  const LensDistortion& d = *camera.distortion;
  if (d.model != LensDistortion::Model::Polynomial) return;
  const double diagonal = std::hypot(double(camera.width), double(camera.height));
  double worst = 0.0;
  for (const glm::dvec2 corner : {glm::dvec2(0.0), glm::dvec2(camera.width, 0.0), glm::dvec2(0.0, camera.height),
                                  glm::dvec2(camera.width, camera.height)}) {
    const glm::dvec2 moved = d.distort(corner);
    worst = std::max(worst, finite(moved) ? glm::length(moved - corner) : HUGE_VAL);
  }
  if (worst > diagonal) {
    std::ostringstream s;
    s << where << ": camera '" << camera.id << "': distortion: moves a corner of the photograph by " << worst
      << " pixels, more than its diagonal (" << diagonal
      << "): expected the coefficients of a real lens (check their unit: docs/formats.md)";
    diag.warn(s.str());
  }
}

}  // namespace

void fitLensDomain(Camera& camera, const std::string& where, Diagnostics& diag) {
  if (!camera.distortion) return;
  warnAbsurdLens(camera, where, diag);
  const std::string change = camera.distortion->fitDomain();
  if (change.empty()) return;
  // Only a domain that cuts into the photograph is worth a warning.
  bool cut = false;
  for (const glm::dvec2 corner : {glm::dvec2(0.0), glm::dvec2(camera.width, 0.0), glm::dvec2(0.0, camera.height),
                                  glm::dvec2(camera.width, camera.height)})
    cut = cut || !camera.undistort(corner);
  if (cut) diag.warn(where + ": camera '" + camera.id + "': distortion: " + change + " (part of the image is left out)");
  else log::debug(where + ": camera '" + camera.id + "': distortion: " + change);
}

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
        !std::isfinite(d.p1) || !std::isfinite(d.p2) || !std::isfinite(d.l1) || !std::isfinite(d.l2) ||
        std::isnan(d.r2max) || d.r2max <= 0.0)
      fail("distortion", "expected finite center and coefficients and a positive r2max");
    if (!finite(d.scale) || d.scale.x <= 0.0 || d.scale.y <= 0.0)
      fail("distortion", "expected a positive scale (focal length of the normalised coordinates)");
  }
}

}  // namespace hv
