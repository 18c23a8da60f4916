// The traffic of a frame in plain C++ (the 2013 paper, §3: the view "repopulated" by a traffic
// simulation): each vehicle's trajectory sampled at the frame's time, lifted onto the terrain
// (hv/traffic/lift.h) and handed to the backend as an instance of its class's model
// (hv/traffic/vehicle_model.h: a glTF file of scene.json traffic.models, or the built-in box with
// wheels), scaled to its size.
#pragma once

#include "hv/render/frame.h"
#include "hv/traffic/lift.h"
#include "hv/traffic/trajectories.h"
#include "hv/traffic/vehicle_model.h"

#include <string>
#include <vector>

namespace hv::render {

// The contact shadow (the paper's future work: "casted shadows (e.g. below cars)"): a dark quad on
// the ground under the vehicle, this much larger than its footprint, this high above the terrain.
constexpr float kShadowScale = 1.12f;
constexpr float kShadowLift = 0.04f;  // metres
constexpr float kShadowOpacity = 0.6f;

// A body colour per vehicle id (a fixed palette of car paints, by a hash of the id).
glm::vec3 vehicleColour(const std::string& id);

// The vehicles on the road at `time` (seconds), lifted onto `terrain`, in the render frame (world
// minus `origin`). A vehicle off the terrain is left out.
std::vector<VehicleInstance> vehicleInstances(const Trajectories& traffic, const TerrainHeight& terrain, double time,
                                              const glm::dvec3& origin);

// Where a ray (render frame, unit direction) first meets the model of an instance (its class's in
// `models`, the built-in box with wheels when null or none), t >= 0; negative: it misses. For CPU
// references of the drawing.
double rayVehicleEntry(const VehicleInstance& v, const VehicleModels* models, const glm::dvec3& origin,
                       const glm::dvec3& dir);

}  // namespace hv::render
