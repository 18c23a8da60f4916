// Point clouds (lidar, photogrammetry): positions in double in the file's coordinates (after the
// LAS scale and offset), with the optional per-point attributes the formats carry.
//
// Conventions (owned here):
// - Positions are in the source CRS (`crs`, when the file declares one), never transformed here.
// - An attribute vector is either empty (the field is absent) or has one entry per point.
// - `rgb` is 16-bit per channel as in LAS; 8-bit sources are scaled by 257 (255 -> 65535).
// - `classification` is the ASPRS class: the 5-bit class of LAS point formats 0-5, the 8-bit
//   extended class of formats 6-10 (LAS 1.4 R15, tables 9 and 17).
// - `normals` are unit vectors (float), as given by the source; or, when `pendingNormals` is set,
//   empty until estimated on first use (hv/scene/point_normals.h, pointNormals).
#pragma once

#include "hv/scene/mesh.h"

#include <glm/glm.hpp>
#include <glm/gtc/type_precision.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace hv {

struct PendingNormals;  // hv/scene/point_normals.h

// A contiguous range of points of a PointCloud (after organizeChunks, hv/scene/chunks.h), with
// the bounds of those points. Points inside a chunk are in random order, so any prefix
// [first, first + k) is a uniform subsample of the chunk.
struct PointChunk {
  Aabb bounds;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
};

// Which optional attributes a cloud carries.
struct PointFields {
  bool intensity = false;
  bool classification = false;
  bool rgb = false;
  bool normals = false;
  std::string describe() const;  // e.g. "xyz intensity classification rgb"
};

struct PointCloud {
  std::string sourcePath;  // the file it was read from (for messages)
  std::string crs;         // WKT or "EPSG:<code>" as the file declares it; empty: none declared

  std::vector<glm::dvec3> positions;
  std::vector<std::uint16_t> intensity;
  std::vector<std::uint8_t> classification;
  std::vector<glm::u16vec3> rgb;
  std::vector<glm::vec3> normals;
  // Normals still to be estimated, on first use (hv/scene/point_normals.h: pointNormals,
  // resolveNormals): the loader defers the estimate for a source without normals. Null: none
  // pending. Shared by copies of the cloud; the positions must not change while it is set.
  std::shared_ptr<PendingNormals> pendingNormals;

  // Empty until organizeChunks() reorders the points into chunks covering all of them.
  std::vector<PointChunk> chunks;

  std::size_t size() const { return positions.size(); }
  bool empty() const { return positions.empty(); }
  PointFields fields() const;
  // Bounds of the positions (computed).
  Aabb bounds() const;
  // Number of points per class (all zero without classification).
  std::array<std::size_t, 256> classHistogram() const;
  // Allocates every attribute named in `fields` for n points (positions always).
  void resize(std::size_t n, const PointFields& fields);
  // Reorders every attribute: point i of the result is point order[i] of this cloud. `order`
  // must be a permutation of [0, size()); chunks are cleared. Pending normals are estimated first.
  void permute(const std::vector<std::uint32_t>& order);
  // True when every non-empty attribute has size() entries.
  bool consistent() const;
  // Appends `add`'s points (a tileset's tiles into one cloud): the fields both have; a field only
  // one has is dropped, so the cloud stays consistent. An empty cloud takes `add` whole, keeping
  // its own crs and sourcePath where it has them.
  void append(const PointCloud& add);
};

}  // namespace hv
