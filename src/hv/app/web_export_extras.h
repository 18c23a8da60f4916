// What web-export adds to the web scene's manifest beyond hv::writeWebScene (docs/web.md), for
// the page's service layers (docs/services.md, "In the browser"):
//   "geocentric"     the EPSG:4978 fit (hv/io/web_geocentric.h), for a scene with a CRS, so that
//                    the page can place earth-centred 3D Tiles;
//   "terrainExtent"  [minX, minY, maxX, maxY], the rectangle the native loader drapes an
//                    orthophoto over (the terrain's), so that the page can read one from a WMTS;
//   "orthophoto"     the scene's orthophoto, when scene.json has one (hv/io/web_orthophoto.h).
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <string>

namespace hv::app {

// Adds the entries above to the manifest at `manifestPath` (the orthophoto's file beside it). A
// part that cannot be made is left out with a warning in `diag`.
void writeWebSceneExtras(const Scene& scene, const std::string& manifestPath, Diagnostics& diag);

}  // namespace hv::app
