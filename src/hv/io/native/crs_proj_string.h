// A CRS as a PROJ.4 string ("+proj=lcc +lat_0=46.5 ... +units=m +no_defs +type=crs"), for what
// has no PROJ database: the page's service scenes without an export take the scene CRS in that
// form (their "projection", docs/services.md "In the browser") for proj4js; `histoview info`
// prints it.
#pragma once

#include <string>

namespace hv {

// PROJ's PROJ.4 string of `definition` (anything describeCrs reads); empty when PROJ has none
// (a CRS PROJ.4 strings cannot say). Throws InputError when PROJ cannot read `definition`.
std::string crsProjString(const std::string& definition);

}  // namespace hv
