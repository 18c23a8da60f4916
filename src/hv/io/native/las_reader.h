// LAS point clouds (ASPRS LAS 1.0-1.4, point data record formats 0-10, uncompressed): positions
// with the header's scale and offset applied, intensity, classification (the extended 8-bit class
// of formats 6-10) and RGB where the format has it (2, 3, 5, 7, 8, 10). Extra bytes (a record
// longer than its format's minimum) are skipped. The CRS comes from the OGC WKT VLR (record 2112,
// also as an EVLR) or else the GeoTIFF keys VLR (34735: "EPSG:<projected or geographic code>").
//
// LAZ (compressed) files are refused with an InputError that says how to convert them: no LAZ
// decoder is packaged for Debian.
#pragma once

#include "hv/scene/point_cloud.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace hv {

// Reads a .las file. Throws InputError naming the file, the header field and what was expected
// for a LAZ file, a truncated file or inconsistent header fields; never reads out of bounds.
PointCloud readLas(const std::string& path);
// The same on a file already in memory; `name` is used in messages.
PointCloud parseLas(const std::uint8_t* data, std::size_t size, const std::string& name);

}  // namespace hv
