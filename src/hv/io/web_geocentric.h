// The web scene's "geocentric" entry (hv/io/web_scene.h, docs/web.md "Points from 3D Tiles"): the
// quadratic fit from EPSG:4978 into the scene frame (hv/scene/geocentric_fit.h) that `web-export`
// writes, with PROJ, for scenes with a CRS, so that the page can place earth-centred 3D Tiles
// without a projection library:
//   "geocentric": {"centre": [x, y, z], "scale": s, "coefficients": [[x, y, z] x 10], "maxError": e}
#pragma once

#include "hv/scene/geocentric_fit.h"

#include <nlohmann/json.hpp>

#include <string>

namespace hv {

nlohmann::json geocentricJson(const GeocentricFit& fit);
// Throws InputError naming `where` and the field when the entry is not as above.
GeocentricFit geocentricFromJson(const nlohmann::json& j, const std::string& where);

}  // namespace hv
