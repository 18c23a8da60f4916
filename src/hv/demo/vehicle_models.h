// Low-poly vehicle models made by code, written as glTF 2.0 with their buffer embedded (a base64
// data: URI): a car, a bus and a truck, in metres at their SUMO class's size (hv::vehicleSizeOf),
// facing +Z with +Y up (glTF's convention). The demo city's scene.json names them
// (traffic.models); the same files are committed under data/vehicles/ (a test keeps them equal).
//
// Materials: "paint" (the vehicle's own colour when drawn: hv/traffic/vehicle_model.h), "glass",
// "tyre", "cargo" (a truck's box), "light".
#pragma once

#include "hv/traffic/vehicle_model.h"

#include <string>
#include <vector>

namespace hv::demo {

// The classes that have a generated model: car, bus, truck.
const std::vector<VehicleClass>& generatedVehicleClasses();
// The .gltf text of a class's model (the same bytes on every run).
std::string vehicleModelGltf(VehicleClass c);
// Writes <dir>/<class>.gltf for each generated class; returns the file names, relative to `dir`.
std::vector<std::string> writeVehicleModels(const std::string& dir);

}  // namespace hv::demo
