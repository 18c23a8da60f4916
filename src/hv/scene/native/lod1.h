// LOD1 buildings: 2D footprints extruded into vertical walls and a flat roof.
// Roofs are triangulated with their holes by GEOS's constrained Delaunay triangulation
// (no hand-written triangulator). GEOS is only used inside lod1.cpp. The rest of the extrusion
// (rings, walls, base and roof elevations) is the portable hv/scene/footprint.h, which the
// browser build uses with its own roof triangulation.
#pragma once

#include "hv/scene/footprint.h"
#include "hv/scene/heightfield.h"
#include "hv/scene/mesh.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace hv {

// Closed, outward-oriented prism: floor (down-facing), roof (up-facing), walls. The floor is
// included so the mesh is closed (volumes check out); it costs little and is never seen.
// Throws InputError (naming the footprint id) for a footprint that is invalid (self-intersecting,
// fewer than 3 distinct points, zero area) or when topZ <= baseZ.
Mesh extrudeLod1(const Footprint& footprint, double baseZ, double topZ);

// A planar polygon (rings[0] outer, the rest holes; not closed) triangulated by GEOS's constrained
// Delaunay triangulation, which adds no vertex. Returns triangles as indices into the rings
// concatenated in order, counter-clockwise in the plane of the points. Throws InputError (naming
// `what`) for a polygon GEOS finds invalid or of zero area.
std::vector<glm::uvec3> triangulatePolygon(const std::vector<std::vector<glm::dvec2>>& rings, const std::string& what);

// All buildings of a layer. Base: `base` attribute, else the lowest terrain elevation under the
// footprint (when a terrain is given), else 0 with a warning. Top: `top`, else base + height.
// A footprint that cannot be built is skipped with a warning naming its id; the rest is built.
// Triangle tags are the footprint's index in `footprints`.
Mesh buildLod1(const std::vector<Footprint>& footprints, const Heightfield* terrain, Diagnostics& diag);

}  // namespace hv
