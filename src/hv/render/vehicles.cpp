#include "hv/render/vehicles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace hv::render {

const std::array<VehiclePart, 2>& vehicleParts() {
  // The body from a ground clearance to the belt line, the cabin set back from the bonnet.
  static const std::array<VehiclePart, 2> parts = {
      VehiclePart{{-0.5f, -0.5f, 0.12f}, {0.5f, 0.5f, 0.58f}, false},
      VehiclePart{{-0.44f, -0.30f, 0.58f}, {0.44f, 0.22f, 1.0f}, true},
  };
  return parts;
}

glm::vec3 vehicleColour(const std::string& id) {
  static const glm::vec3 kPaints[] = {{0.75f, 0.08f, 0.06f}, {0.85f, 0.85f, 0.82f}, {0.10f, 0.12f, 0.14f},
                                      {0.12f, 0.25f, 0.60f}, {0.55f, 0.57f, 0.60f}, {0.90f, 0.70f, 0.10f},
                                      {0.15f, 0.40f, 0.22f}, {0.45f, 0.10f, 0.35f}};
  std::uint32_t h = 2166136261u;  // FNV-1a
  for (const char c : id) h = (h ^ std::uint8_t(c)) * 16777619u;
  return kPaints[h % (sizeof(kPaints) / sizeof(kPaints[0]))];
}

std::vector<VehicleInstance> vehicleInstances(const Trajectories& traffic, const TerrainHeight& terrain, double time,
                                              const glm::dvec3& origin) {
  std::vector<VehicleInstance> out;
  for (const Trajectory& v : traffic.vehicles) {
    const std::optional<GroundPose> ground = sampleTrajectory(v, time);
    if (!ground) continue;
    const std::optional<VehiclePose> pose = liftOntoTerrain(*ground, v.size, terrain);
    if (!pose) continue;
    VehicleInstance i;
    i.position = glm::vec3(pose->position - origin);
    i.right = glm::vec3(pose->worldFromVehicle[0]);
    i.forward = glm::vec3(pose->worldFromVehicle[1]);
    i.up = glm::vec3(pose->worldFromVehicle[2]);
    i.size = glm::vec3(float(v.size.length), float(v.size.width), float(v.size.height));
    i.colour = vehicleColour(v.id);
    out.push_back(i);
  }
  return out;
}

OrientedBox partBox(const VehicleInstance& v, const VehiclePart& part) {
  // Fractions of (width, length, height) along (right, forward, up).
  const glm::dvec3 scale(v.size.y, v.size.x, v.size.z);
  const glm::dvec3 lo = glm::dvec3(part.lo) * scale, hi = glm::dvec3(part.hi) * scale;
  const glm::dvec3 c = 0.5 * (lo + hi), h = 0.5 * (hi - lo);
  OrientedBox b;
  b.centre = glm::dvec3(v.position) + c.x * glm::dvec3(v.right) + c.y * glm::dvec3(v.forward) + c.z * glm::dvec3(v.up);
  b.halfAxes = {h.x * glm::dvec3(v.right), h.y * glm::dvec3(v.forward), h.z * glm::dvec3(v.up)};
  return b;
}

double rayBoxEntry(const OrientedBox& box, const glm::dvec3& origin, const glm::dvec3& dir) {
  // Slabs along each of the box's axes.
  double tNear = -std::numeric_limits<double>::infinity(), tFar = std::numeric_limits<double>::infinity();
  for (const glm::dvec3& a : box.halfAxes) {
    const double len = glm::length(a);
    const glm::dvec3 n = a / len;
    const double o = glm::dot(box.centre - origin, n), d = glm::dot(dir, n);
    if (std::abs(d) < 1e-12) {
      if (std::abs(o) > len) return -1.0;
      continue;
    }
    double t0 = (o - len) / d, t1 = (o + len) / d;
    if (t0 > t1) std::swap(t0, t1);
    tNear = std::max(tNear, t0);
    tFar = std::min(tFar, t1);
    if (tNear > tFar) return -1.0;
  }
  if (tFar < 0.0) return -1.0;
  return std::max(tNear, 0.0);
}

}  // namespace hv::render
