// CityJSON (https://www.cityjson.org/specs/, versions 1.0 to 2.0) buildings as one triangle mesh:
// the 3D city models of the Netherlands' 3D BAG and many cities, read without conversion.
//
// What is read: the city objects of type Building and BuildingPart (a part carries its parent
// building's tag), each by its geometry of the highest LOD (LOD1 blocks, LOD2 with their roofs),
// of type MultiSurface, CompositeSurface, Solid, MultiSolid or CompositeSolid. Surfaces are
// planar polygons with holes, triangulated in their plane (hv::triangulatePolygon, GEOS's
// constrained Delaunay triangulation), counter-clockwise as the file orders the outer ring (the
// specification's rule: counter-clockwise seen from outside). Vertices are the file's integers
// times `transform.scale` plus `transform.translate` (without `transform`, as written).
// The CRS is `metadata.referenceSystem` (1.0: "urn:ogc:def:crs:EPSG::7415"; 1.1 and later:
// "https://www.opengis.net/def/crs/EPSG/0/7415"), given back as "EPSG:7415".
#pragma once

#include "hv/scene/mesh.h"
#include "hv/util/diagnostics.h"

#include <string>
#include <string_view>
#include <vector>

namespace hv {

struct CityJsonBuildings {
  Mesh mesh;                     // triangle tags: the building's index in `ids`
  std::vector<std::string> ids;  // the buildings' CityObjects keys, in key order
  std::vector<int> lods;         // the LOD read for each building (the integer part)
  std::string crs;               // "EPSG:n", or the referenceSystem as written; "" when none
};

// Reads a CityJSON file. Throws InputError naming the file for a file that is not CityJSON
// (no "type": "CityJSON", no CityObjects or vertices); a building whose geometry is broken (an
// index out of range, a ring of fewer than 3 points, a non-planar or invalid polygon) is named in
// `diag` with its id and field and left out, the rest read.
CityJsonBuildings readCityJson(const std::string& path, Diagnostics& diag);
CityJsonBuildings parseCityJson(std::string_view text, const std::string& path, Diagnostics& diag);

// True when the file is CityJSON by its name (".city.json", ".cityjson") or, for another ".json",
// by a "CityJSON" type near its start.
bool isCityJsonFile(const std::string& path);

}  // namespace hv
