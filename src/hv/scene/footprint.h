// A building footprint and its LOD1 extrusion, portable (the browser build extrudes the footprints
// it fetches from a WFS with the same code as the native loader: docs/services.md, "In the
// browser"). The native loader (hv/scene/native/lod1.h) checks each polygon with GEOS and
// triangulates its roof by GEOS's constrained Delaunay triangulation; the browser, without GEOS,
// triangulates by ear clipping (earClipPolygon). Everything else (the rings' cleaning and
// orientation, the vertex layout, the walls, the base and roof elevations, the validity dates)
// is this file's, for both.
#pragma once

#include "hv/scene/heightfield.h"
#include "hv/scene/mesh.h"
#include "hv/util/dates.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace hv {

struct Footprint {
  std::string id;                              // feature id, for messages
  std::vector<std::vector<glm::dvec2>> rings;  // rings[0] outer, the rest holes; not closed (no repeated first point)
  std::optional<double> height;                // metres above the base
  std::optional<double> base;                  // absolute elevation of the base
  std::optional<double> top;                   // absolute elevation of the roof
  std::optional<std::string> validFrom, validTo;  // ISO dates (time filtering)
};

// Twice the signed area of a ring (shoelace formula): positive for a counter-clockwise ring.
double twiceSignedArea(const std::vector<glm::dvec2>& ring);

// "footprint ID: message" (InputError's form).
std::string footprintMessage(const Footprint& footprint, const std::string& message);

// The footprint's rings without consecutive repeats nor a closing repeat of the first point.
// Throws InputError (naming the footprint) for no ring, a non-finite coordinate or a ring of fewer
// than 3 distinct points.
std::vector<std::vector<glm::dvec2>> cleanFootprintRings(const Footprint& footprint);

// Outer ring counter-clockwise, holes clockwise seen from above (the solid on the left of each
// directed edge). Throws InputError for a ring of zero area.
void orientFootprintRings(const Footprint& footprint, std::vector<std::vector<glm::dvec2>>& rings);

// The closed, outward-oriented prism of oriented `rings` between baseZ and topZ: vertex k of the
// concatenated rings is 2k at the base and 2k + 1 at the roof; `roof` (triangles as indices into
// the concatenated rings, counter-clockwise from above) gives the roof and, reversed, the floor;
// one quad per ring edge gives the walls.
Mesh extrudePrism(const std::vector<std::vector<glm::dvec2>>& rings, const std::vector<glm::uvec3>& roof, double baseZ,
                  double topZ);

// A simple polygon (rings[0] outer, the rest holes, not closed) triangulated by ear clipping with
// the holes bridged to the outer ring (Eberly, "Triangulation by Ear Clipping"): no vertex added,
// triangles as indices into the rings concatenated in order, counter-clockwise. Expects a valid
// polygon (GEOS's check is native only): on a self-intersecting one it still ends, and covers
// what it can. Throws InputError (naming `what`) for fewer than 3 points or zero area.
std::vector<glm::uvec3> earClipPolygon(const std::vector<std::vector<glm::dvec2>>& rings, const std::string& what);

// One footprint extruded as extrudeLod1 does, the roof triangulated by earClipPolygon.
Mesh extrudeLod1EarClip(const Footprint& footprint, double baseZ, double topZ);

using Lod1Extruder = std::function<Mesh(const Footprint&, double baseZ, double topZ)>;

// All buildings of a layer, each by `extrude`. Base: `base` attribute, else the lowest terrain
// elevation under the footprint (when a terrain is given), else 0 with a warning. Top: `top`,
// else base + height. A footprint that cannot be built is skipped with a warning naming its id;
// the rest is built. Triangle tags are the footprint's index in `footprints`.
Mesh buildLod1With(const std::vector<Footprint>& footprints, const Heightfield* terrain, Diagnostics& diag,
                   const Lod1Extruder& extrude);

// Each footprint's validity (open-ended unless validFrom / validTo parse as ISO 8601 dates; one
// that does not is warned about, naming `path`, the footprint and the attribute `fromField` /
// `toField`, and ignored), in the footprints' order (the triangle tags of buildLod1With).
std::vector<DateInterval> footprintValidity(const std::vector<Footprint>& footprints, const std::string& fromField,
                                            const std::string& toField, const std::string& path, Diagnostics& diag);

}  // namespace hv
