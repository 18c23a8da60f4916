// PLY point clouds (Turk 1994; the format as Paul Bourke documents it): ascii,
// binary_little_endian and binary_big_endian. The `vertex` element gives the points: x y z
// (any numeric type), and when present nx ny nz, red green blue (uchar scaled by 257 to 16 bits,
// ushort as is, floats taken in [0, 1]), intensity or scalar_intensity, classification or
// scalar_classification. Other elements (faces, ...) and other properties, list properties
// included, are skipped. A header comment `comment crs <CRS>` gives the CRS (histoview's own
// convention; PLY has none).
#pragma once

#include "hv/scene/point_cloud.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace hv {

// Throws InputError naming the file, the element or property and what was expected for a bad
// header, a missing x/y/z, truncated data or non-finite coordinates; never reads out of bounds.
PointCloud readPlyPoints(const std::string& path);
PointCloud parsePlyPoints(const std::uint8_t* data, std::size_t size, const std::string& name);
// Reads the whole file, every element after the vertices included (a mesh's faces and their
// lists), and throws InputError as above at the first malformed value: the check a PLY mesh
// passes before Assimp reads it (io/native/mesh_reader.h).
void validatePly(const std::uint8_t* data, std::size_t size, const std::string& name);

// Binary little-endian PLY: x y z as double (world coordinates keep their precision), then
// whichever of nx ny nz (float), red green blue (uchar: the 16-bit value / 257, rounded),
// intensity (ushort) and classification (uchar) the cloud has; `comment crs` when it has one.
// Throws std::runtime_error when the file cannot be written.
void writePlyPoints(const std::string& path, const PointCloud& cloud);
std::string plyPointBytes(const PointCloud& cloud);

}  // namespace hv
