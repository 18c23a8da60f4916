// The traffic of a frame in plain C++ (the 2013 paper, §3: the view "repopulated" by a traffic
// simulation): each vehicle's trajectory sampled at the frame's time, lifted onto the terrain
// (hv/traffic/lift.h) and handed to the backend as an instance of a box model. The model is here
// too, so that the GL pass (render/gl/vehicles_pass.cpp) and its CPU reference draw the same boxes.
#pragma once

#include "hv/render/frame.h"
#include "hv/traffic/lift.h"
#include "hv/traffic/trajectories.h"

#include <array>
#include <string>
#include <vector>

namespace hv::render {

// One box of the vehicle model, in the vehicle frame (hv/traffic/lift.h: x right, y forward, z up)
// as fractions of the vehicle's size: x of its width, y of its length, z of its height.
struct VehiclePart {
  glm::vec3 lo, hi;
  bool glass = false;  // drawn in the glass colour, not the body's
};
// A body box and a cabin box.
const std::array<VehiclePart, 2>& vehicleParts();
// The contact shadow (the paper's future work: "casted shadows (e.g. below cars)"): a dark quad on
// the ground under the vehicle, this much larger than its footprint, this high above the terrain.
constexpr float kShadowScale = 1.12f;
constexpr float kShadowLift = 0.04f;  // metres
constexpr float kShadowOpacity = 0.6f;
inline const glm::vec3 kGlassColour{0.08f, 0.10f, 0.13f};

// A body colour per vehicle id (a fixed palette of car paints, by a hash of the id).
glm::vec3 vehicleColour(const std::string& id);

// The vehicles on the road at `time` (seconds), lifted onto `terrain`, in the render frame (world
// minus `origin`). A vehicle off the terrain is left out.
std::vector<VehicleInstance> vehicleInstances(const Trajectories& traffic, const TerrainHeight& terrain, double time,
                                              const glm::dvec3& origin);

// The box of a part of an instance as a world-frame oriented box (render frame): centre, the
// three half-extent axes. For CPU references.
struct OrientedBox {
  glm::dvec3 centre{0.0};
  std::array<glm::dvec3, 3> halfAxes{};
};
OrientedBox partBox(const VehicleInstance& v, const VehiclePart& part);
// Where a ray (render frame, unit direction) enters the box, t >= 0; a negative value: it misses.
double rayBoxEntry(const OrientedBox& box, const glm::dvec3& origin, const glm::dvec3& dir);

}  // namespace hv::render
