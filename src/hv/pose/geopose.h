// OGC GeoPose 1.0 (OGC 21-056r11), the Basic-Quaternion form: a position in WGS 84 (latitude and
// longitude in degrees, height above the ellipsoid in metres) and a unit quaternion giving the
// orientation of the object in the local tangent plane at that position, East-North-Up.
//
// Conventions (owned here, repeated in docs/pose.md):
// - the outer frame is East-North-Up (x east, y north, z up) at the position;
// - the quaternion (x, y, z, w; w the scalar part) is the rotation that carries the ENU axes onto
//   the object's axes: the columns of its matrix are the object's x, y, z axes in ENU
//   (enuFromObject). The identity is an object whose axes are ENU's;
// - GeoPose's yaw, pitch, roll turn about z, then the new x, then the newest y (its Basic-YPR
//   form and the worked example of the standard agree only so): the object's forward axis is y,
//   its up axis z, x to its right. A camera's frame (x right, y down, z forward, docs/conventions.md)
//   becomes the object frame x = camera x, y = camera z, z = −camera y. A camera looking north,
//   level, with no roll, is then the identity quaternion; looking east, a yaw of −90°.
#pragma once

#include "hv/camera/camera.h"

#include <glm/glm.hpp>

#include <string>

namespace hv::pose {

struct GeoPose {
  double latDeg = 0.0;
  double lonDeg = 0.0;
  double heightM = 0.0;                       // above the WGS 84 ellipsoid
  glm::dvec4 quaternion{0.0, 0.0, 0.0, 1.0};  // x, y, z, w: enuFromObject
};

// The rotation from ECEF (WGS 84 geocentric) directions to the East-North-Up directions at a
// geodetic latitude and longitude (rows: east, north, up).
glm::dmat3 enuFromEcef(double latDeg, double lonDeg);

// The GeoPose object frame of a camera, in the ENU frame: enuFromWorld (a rotation: the ENU
// axes in world coordinates as its rows) times worldFromCam times camFromObject.
glm::dmat3 enuFromCameraObject(const glm::dmat3& camFromWorld, const glm::dmat3& enuFromWorld);

// The unit quaternion (x, y, z, w) of a rotation matrix, w >= 0 (Shepperd's method: the largest
// of the four squared components picked first, so none is found by dividing by a small one).
glm::dvec4 quaternionOf(const glm::dmat3& rotation);
// The rotation matrix of a unit quaternion (x, y, z, w).
glm::dmat3 rotationOf(const glm::dvec4& quaternion);

// The Basic-Quaternion JSON: {"position": {"lat", "lon", "h"}, "quaternion": {"x", "y", "z", "w"}},
// full double precision.
std::string geoPoseJson(const GeoPose& pose);

}  // namespace hv::pose
