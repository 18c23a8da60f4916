#include "hv/pose/geopose.h"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace hv::pose {

glm::dmat3 enuFromEcef(double latDeg, double lonDeg) {
  const double lat = latDeg * M_PI / 180.0, lon = lonDeg * M_PI / 180.0;
  const double sp = std::sin(lat), cp = std::cos(lat), sl = std::sin(lon), cl = std::cos(lon);
  const glm::dvec3 east(-sl, cl, 0.0), north(-sp * cl, -sp * sl, cp), up(cp * cl, cp * sl, sp);
  // glm is column-major: the rows east, north, up are the transpose's columns.
  return glm::transpose(glm::dmat3(east, north, up));
}

glm::dmat3 enuFromCameraObject(const glm::dmat3& camFromWorld, const glm::dmat3& enuFromWorld) {
  // Columns: the object's x, y, z axes in the camera frame (x, z, −y of the camera).
  const glm::dmat3 camFromObject(glm::dvec3(1, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, -1, 0));
  return enuFromWorld * glm::transpose(camFromWorld) * camFromObject;
}

glm::dvec4 quaternionOf(const glm::dmat3& m) {
  // m[col][row]: r(i, j) is row i, column j.
  auto r = [&](int i, int j) { return m[j][i]; };
  const double tr = r(0, 0) + r(1, 1) + r(2, 2);
  glm::dvec4 q;
  if (tr >= r(0, 0) && tr >= r(1, 1) && tr >= r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + tr);
    q = {(r(2, 1) - r(1, 2)) / s, (r(0, 2) - r(2, 0)) / s, (r(1, 0) - r(0, 1)) / s, 0.25 * s};
  } else if (r(0, 0) >= r(1, 1) && r(0, 0) >= r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + r(0, 0) - r(1, 1) - r(2, 2));
    q = {0.25 * s, (r(0, 1) + r(1, 0)) / s, (r(0, 2) + r(2, 0)) / s, (r(2, 1) - r(1, 2)) / s};
  } else if (r(1, 1) >= r(2, 2)) {
    const double s = 2.0 * std::sqrt(1.0 + r(1, 1) - r(0, 0) - r(2, 2));
    q = {(r(0, 1) + r(1, 0)) / s, 0.25 * s, (r(1, 2) + r(2, 1)) / s, (r(0, 2) - r(2, 0)) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r(2, 2) - r(0, 0) - r(1, 1));
    q = {(r(0, 2) + r(2, 0)) / s, (r(1, 2) + r(2, 1)) / s, 0.25 * s, (r(1, 0) - r(0, 1)) / s};
  }
  q /= glm::length(q);
  return q.w < 0.0 ? -q : q;
}

glm::dmat3 rotationOf(const glm::dvec4& q) {
  const double x = q.x, y = q.y, z = q.z, w = q.w;
  glm::dmat3 m;
  m[0] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w)};
  m[1] = {2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w)};
  m[2] = {2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)};
  return m;
}

std::string geoPoseJson(const GeoPose& p) {
  std::ostringstream s;
  s << std::setprecision(17);
  s << "{\n  \"position\": {\"lat\": " << p.latDeg << ", \"lon\": " << p.lonDeg << ", \"h\": " << p.heightM
    << "},\n  \"quaternion\": {\"x\": " << p.quaternion.x << ", \"y\": " << p.quaternion.y
    << ", \"z\": " << p.quaternion.z << ", \"w\": " << p.quaternion.w << "}\n}\n";
  return s.str();
}

}  // namespace hv::pose
