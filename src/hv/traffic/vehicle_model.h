// The 3D model a vehicle is drawn with (the 2013 paper, §3: the simulation's vehicles drawn in 3D
// over the image-based view): one model per vehicle class, a triangle soup in the vehicle frame
// (hv/traffic/lift.h: x right, y forward, z up) *as fractions of the vehicle's size*, so that one
// model serves every vehicle of its class, scaled to the type's length x width x height
// (hv/traffic/trajectories.h, vehicleSizeOf).
//
// Conventions (owned here, repeated in docs/traffic.md):
// - a model's `local` coordinates: x in [-0.5, 0.5] of the width, y in [-0.5, 0.5] of the length,
//   z in [0, 1] of the height (fitToUnitBox puts a model read in metres there);
// - a glTF asset faces +Z with +Y up and +X to its left (glTF 2.0, §3.4): its (X, Y, Z) is the
//   vehicle frame's (-x, z, y) (vehicleFromGltf);
// - `paint` 1: the triangle takes the vehicle's own body colour (a palette by its id), 0: its
//   material's colour (glass, tyres, lights).
#pragma once

#include <glm/glm.hpp>

#include <array>
#include <memory>
#include <string>
#include <vector>

namespace hv {

// The classes a model is chosen by, from the simulator's type name (vehicleClassOf).
enum class VehicleClass { Car, Bus, Truck, Motorcycle, Bicycle };
inline constexpr int kVehicleClasses = 5;
// "car", "bus", "truck", "motorcycle", "bicycle": the keys of scene.json traffic.models.
const char* vehicleClassName(VehicleClass c);
// The class of a simulator's type name, by the same names as vehicleSizeOf: "bus", "coach",
// "tram" are buses; "truck", "trailer", "delivery" trucks; "motorcycle", "moped" motorcycles;
// "bicycle" bicycles; anything else a car.
VehicleClass vehicleClassOf(const std::string& type);

struct ModelVertex {
  glm::vec3 local{0.0f};               // fractions of (width, length, height), vehicle frame
  glm::vec3 normal{0.0f, 0.0f, 1.0f};  // vehicle frame, unit (in metres: see fitToUnitBox)
  glm::vec3 colour{0.5f};              // linear [0, 1], when paint is 0
  float paint = 0.0f;                  // 1: the vehicle's body colour instead
};

struct VehicleModel {
  std::vector<ModelVertex> vertices;  // triangles, three vertices each, counter-clockwise from outside
  std::string source;                 // the file it was read from; "" for the built-in one
};

// The built-in model, drawn where a class has no model or its file could not be read: a body box,
// a cabin box set back from the bonnet (glass) and four wheels (tyres), as fractions of the size.
const VehicleModel& boxWithWheelsModel();

// Moves and scales a model whose `local` is in any unit (metres, as read from a file) into the unit
// box of the conventions above: its bounding box's x, y span [-0.5, 0.5] and z spans [0, 1]. The
// normals are re-scaled by the inverse scales (then normalised), so that they stay normal to the
// surface once the model is scaled by a vehicle's size, as far as the model's own proportions are
// those of the vehicle's. Returns false (model unchanged) when a span is not positive or not
// finite: a flat or empty model.
bool fitToUnitBox(VehicleModel& model);

// A glTF direction (X left, Y up, Z forward) in the vehicle frame (x right, y forward, z up).
inline glm::vec3 vehicleFromGltf(const glm::vec3& p) { return {-p.x, p.z, p.y}; }

// The model of each class, the built-in one where none was given.
struct VehicleModels {
  std::array<std::shared_ptr<const VehicleModel>, kVehicleClasses> byClass{};
  const VehicleModel& of(VehicleClass c) const;
};

// Where a ray (unit direction) first meets a model placed with its frame at `position`, axes
// `right`, `forward`, `up` (unit) and scaled by `size` (length, width, height); t >= 0, negative:
// it misses. Möller-Trumbore on each triangle, both sides. For CPU references of the drawing.
double rayModelEntry(const VehicleModel& model, const glm::dvec3& position, const glm::dvec3& right,
                     const glm::dvec3& forward, const glm::dvec3& up, const glm::dvec3& size, const glm::dvec3& origin,
                     const glm::dvec3& dir);

}  // namespace hv
