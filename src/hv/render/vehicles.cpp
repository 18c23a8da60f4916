#include "hv/render/vehicles.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

namespace hv::render {

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
    i.model = int(vehicleClassOf(v.type));
    out.push_back(i);
  }
  return out;
}

double rayVehicleEntry(const VehicleInstance& v, const VehicleModels* models, const glm::dvec3& origin,
                       const glm::dvec3& dir) {
  const VehicleModel& m = models ? models->of(VehicleClass(v.model)) : boxWithWheelsModel();
  return rayModelEntry(m, glm::dvec3(v.position), glm::dvec3(v.right), glm::dvec3(v.forward), glm::dvec3(v.up),
                       glm::dvec3(v.size), origin, dir);
}

}  // namespace hv::render
