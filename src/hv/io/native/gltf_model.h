// A vehicle model from a glTF 2.0 file (.gltf with its buffers embedded as data: URIs, or .glb),
// through tinygltf: every triangle of every mesh the default scene's nodes place (node transforms
// applied), in the vehicle frame (glTF's +Z forward, +Y up: hv/traffic/vehicle_model.h), fitted to
// the unit box so that it scales to each vehicle's size.
//
// Materials: the base colour factor (linear RGB) of a triangle's material; a material named
// "paint" (or "body") takes the vehicle's own colour instead. Textures are not read. Normals: the
// file's NORMAL, else each triangle's own.
#pragma once

#include "hv/traffic/vehicle_model.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace hv {

// Limits: 64 MiB of file, 1 million triangles.
inline constexpr std::uint64_t kMaxGltfBytes = 64ull << 20;
inline constexpr std::size_t kMaxGltfTriangles = 1000000;

// From the file's bytes (JSON text or GLB, by its magic). Throws InputError "<source>: <what was
// expected>" for a broken file: not glTF, buffers outside the file, no triangles, an accessor of
// the wrong type or out of range, a flat model.
VehicleModel parseGltfVehicle(const std::uint8_t* data, std::size_t size, const std::string& source);
VehicleModel readGltfVehicle(const std::string& path);

}  // namespace hv
