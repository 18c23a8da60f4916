// Georeferencing: bringing a source's coordinates (cameras, points, terrain, footprints, meshes)
// from its CRS into the scene frame with PROJ, in double precision.
//
// The scene frame (owned here, repeated in docs/conventions.md) is the scene CRS with every linear
// unit converted to metres: x, y scaled by the horizontal axes' unit (EPSG:2994's international
// foot: 0.3048), z by the vertical axis' unit. A 2D CRS has no vertical axis: z is whatever PROJ
// passes through — the source's vertical axis when it has one (ECEF and 3D geographic CRSs give
// ellipsoidal heights in metres), else, both being 2D, the source's horizontal unit (a 2D CRS's
// z is in its horizontal unit, as in LAS files and the Autzen sample). Axis order is PROJ's
// "visualisation" order (proj_normalize_for_visualization): easting/longitude first.
//
// Cameras: the centre goes through PROJ; the rotation through the local Jacobian J of the
// transform at the centre (central finite differences through PROJ): camFromWorld' =
// polar(camFromWorld J⁻¹), the nearest rotation (J of a conformal projection is a scaled rotation
// up to the difference between its horizontal scale factor and the vertical scale 1, which the
// polar decomposition removes; `nonOrthogonality` reports what was removed). For a geographic
// source (degrees), J's columns are first normalised: a camera given in a geographic CRS has its
// rotation in the local east-north-up axes.
#pragma once

#include "hv/camera/camera.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hv {

struct CrsDescription {
  std::string definition;  // as given
  std::string name;        // PROJ's name
  std::optional<int> epsg;
  std::string type;  // "projected", "geographic 2D", "geographic 3D", "geocentric", "compound", ...
  std::string horizontalUnit;
  double horizontalToMetre = 1.0;  // 0 for angular units
  std::string verticalUnit;        // empty: no vertical axis (a 2D CRS)
  double verticalToMetre = 0.0;    // 0: no vertical axis
  bool geographic = false;
  bool geocentric = false;
  bool hasVerticalAxis() const { return verticalToMetre > 0.0; }
  // The unit of a height given in this CRS, in metres: its vertical axis' unit, else (a 2D CRS)
  // its horizontal linear unit, as for z above; 1 for a 2D geographic CRS (heights in metres).
  double heightToMetre() const;
  // "RGF93 v1 / Lambert-93 (EPSG:2154), metre"
  std::string summary() const;
};

// Throws InputError when PROJ cannot read `definition` as a CRS.
CrsDescription describeCrs(const std::string& definition);

// Whether two definitions are the same CRS (PROJ's equivalence, axis order of geographic CRSs
// aside); false when either cannot be read.
bool equivalentCrs(const std::string& a, const std::string& b);

// The local up direction (unit) of an ECEF point: the GRS80 ellipsoid normal.
glm::dvec3 ecefUp(const glm::dvec3& ecef);

class GeoTransform {
 public:
  // Source CRS -> the scene frame of `sceneCrs`. Throws InputError naming the CRSs when either
  // cannot be read, the scene CRS is geographic (degrees are no frame to render in), or PROJ finds
  // no operation. Warns in `diag` when the best operation needs a grid that is not installed (a
  // geoid: heights would be converted without it), when only a ballpark operation exists, and
  // when ellipsoidal heights go into a scene CRS that declares no vertical datum.
  GeoTransform(const std::string& sourceCrs, const std::string& sceneCrs, Diagnostics& diag);
  ~GeoTransform();
  GeoTransform(GeoTransform&&) noexcept;
  GeoTransform& operator=(GeoTransform&&) noexcept;

  const CrsDescription& source() const;
  const CrsDescription& scene() const;
  // Units PROJ's output z is in (see the header comment), and its factor to metres.
  double zToMetre() const;
  // The two CRSs are the same (PROJ's equivalence, axis order of geographic CRSs aside): only
  // the units may change.
  bool sameCrs() const;
  // Their horizontal parts are the same (a compound CRS's horizontal CRS, a 3D CRS taken as 2D):
  // x, y only change unit, so a raster needs no resampling.
  bool sameHorizontalCrs() const;
  // Heights go through PROJ, datums included, only when both CRSs have a vertical axis
  // (compound, 3D or geocentric); otherwise a height is only converted to metres.
  bool transformsHeights() const;
  // Nothing changes: same CRS, every unit already metres.
  bool isIdentity() const;

  // Throws InputError when PROJ cannot transform the point (outside the CRS's domain).
  glm::dvec3 point(const glm::dvec3& source) const;
  void points(std::vector<glm::dvec3>& inPlace) const;
  // d point / d source at `source` (central differences; steps of about a metre).
  glm::dmat3 jacobian(const glm::dvec3& source) const;
  // The camera in the scene frame (intrinsics unchanged). `nonOrthogonality`: max |Ĵᵀ Ĵ − I| of J
  // scaled to unit determinant (column-normalised for a geographic source).
  Camera camera(const Camera& source, double* nonOrthogonality = nullptr) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Where a point of the scene frame is on the Earth, for GeoPose (hv/pose/geopose.h): its WGS 84
// latitude, longitude (degrees) and height, through PROJ from the scene CRS to EPSG:4979, and the
// rotation from the scene frame's directions to the local East-North-Up ones there (the rows of
// `enuFromWorld` are east, north, up in the scene frame), from the Jacobian of the scene CRS ->
// EPSG:4978 (geocentric) transform made the nearest rotation (a conformal projection's Jacobian is
// a scaled rotation but for the horizontal scale factor; `nonOrthogonality` is what was removed,
// as GeoTransform::camera says). A scene CRS without a vertical axis passes z through as the
// ellipsoidal height (`heightIsZ`). Throws InputError when `sceneCrs` is empty or PROJ cannot
// transform the point.
struct GeodeticFrame {
  double latDeg = 0.0, lonDeg = 0.0, heightM = 0.0;
  glm::dmat3 enuFromWorld{1.0};
  double nonOrthogonality = 0.0;
  bool heightIsZ = false;
};
GeodeticFrame geodeticFrameAt(const std::string& sceneCrs, const glm::dvec3& worldPoint, Diagnostics& diag);

// How scene.json brings one source (terrain, buildings, mesh, points) into the scene frame.
struct SourceGeoref {
  std::string crs;       // scene.json `<source>.crs`: overrides what the file declares; empty: none
  std::string sceneCrs;  // the scene CRS; empty: the source is taken as it is (a local frame)
  std::string field;     // where `crs` comes from, for messages: "scene.json: terrain.crs"
};

// The CRS a source is in: `georef.crs` when given, else what the file declares (`declared`), else
// (the file declares none) the scene CRS itself, whose units still become metres. Empty when the
// scene has no CRS: nothing is transformed.
std::string sourceCrsOf(const SourceGeoref& georef, const std::string& declared);

// The transform of a source named `file` into the scene frame; an InputError names the file, or
// `georef.field` when the CRS came from scene.json, and what was expected.
GeoTransform sourceTransform(const SourceGeoref& georef, const std::string& sourceCrs, const std::string& file,
                             Diagnostics& diag);

}  // namespace hv
