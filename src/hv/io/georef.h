// Georeferencing: bringing a source's coordinates (cameras, points) from its CRS into the scene
// frame with PROJ, in double precision.
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
  // "RGF93 v1 / Lambert-93 (EPSG:2154), metre"
  std::string summary() const;
};

// Throws InputError when PROJ cannot read `definition` as a CRS.
CrsDescription describeCrs(const std::string& definition);

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

}  // namespace hv
