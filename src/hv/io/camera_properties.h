// Cameras as feature properties (docs/formats.md, "Cameras as an OGR point layer"; de Castro &
// Brédif 2022 publish photographs' cameras this way through WFS): a 3D point at the camera centre,
// the rest as properties named as the catalog's columns (docs/catalog.md, "Table layout"):
//   id, image, mask, width, height, focal_x, focal_y, principal_x, principal_y, skew,
//   cam_from_world (9 numbers, row-major), distortion_model ("polynomial" | "fisheye" | null),
//   distortion (12 numbers, hv::LensDistortion's), date (ISO 8601), colour_gain, colour_offset
//   (3 numbers each), and optionally centre_x, centre_y, centre_z in place of the point.
// The per-feature decoding, portable: the browser's GeoJSON camera reader (hv/io/geojson_cameras.h)
// uses it; each reader says how its values come (a JSON value, an OGR field).
//
// Numbers may come as numbers or as text holding one (a WFS schema that did not say the type);
// number arrays as arrays or as text "{a,b,...}" (PostgreSQL) or "[a,b,...]" (JSON, as GeoJSON
// writers and WFS servers pass them on). Anything else is refused, never read as 0.
#pragma once

#include "hv/scene/scene.h"

#include <glm/glm.hpp>

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hv {

// The text forms of number fields: one number (surrounding blanks allowed), and a list "{a,b,...}"
// (PostgreSQL) or "[a,b,...]" (JSON). nullopt when malformed or not finite.
std::optional<double> parseNumber(std::string_view text);
std::optional<std::vector<double>> parseNumberList(std::string_view text);

// One property's value as the layer holds it.
struct CameraProperty {
  enum class Kind { Missing, Number, Text, NumberList, Other };
  Kind kind = Kind::Missing;  // Missing: absent or null
  double number = 0;          // Number
  std::vector<double> list;   // NumberList
  std::string text;           // the value as text, as the layer writes it (Text, Number, Other)
  std::string type;           // what it is, for messages ("number", "array", "Real", ...)
};

// The property named `name` (Missing when the feature has none).
using CameraPropertyLookup = std::function<CameraProperty(const char* name)>;

// One feature's camera, every field checked, validateCamera's checks included (on a copy: the
// rotation is kept bit for bit). `point` gives the feature's geometry as the centre, or throws
// InputError "centre: ..." saying why it cannot (asked only when the properties have no
// centre_x/y/z). Throws InputError naming the field ("focal_x: expected a number, got \"a\"").
// Image and mask paths are as the layer has them.
Photo decodeCameraProperties(const CameraPropertyLookup& property, const std::function<glm::dvec3()>& point);

}  // namespace hv
