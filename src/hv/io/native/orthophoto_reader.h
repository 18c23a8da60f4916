// scene.json "orthophoto" (docs/formats.md): any raster GDAL opens — a GeoTIFF, `/vsicurl/…`, a
// `WMTS:` or `WMS:` connection string — read once at load over the terrain's extent into one RGBA
// image of the scene frame (hv/scene/orthophoto.h), warped by GDAL's warper when its CRS is not
// the scene's.
#pragma once

#include "hv/scene/orthophoto.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <memory>
#include <string>

namespace hv {

// The largest side the orthophoto is read at: 4096 x 4096 RGBA is 64 MiB.
constexpr int kMaxOrthophotoSide = 4096;

struct OrthophotoRequest {
  std::string path;       // resolved (hv::resolveSourcePath): a local file or a connection string
  std::string field;      // for messages: "orthophoto.path"
  std::string crs;        // scene.json orthophoto.crs: overrides the raster's; empty: the raster's
  std::string sceneCrs;   // empty: the raster is taken as it is (a scene without CRS)
  double resolution = 0;  // metres per pixel; <= 0: the raster's own (its finest level)
  // The rectangle to cover, scene frame (metres): the terrain's extent.
  double minX = 0, minY = 0, maxX = 0, maxY = 0;
};

// The rectangle read at `resolution` (else the raster's own), coarsened so that neither side
// exceeds kMaxOrthophotoSide, through GDAL's warper (bilinear; from the overview GDAL picks for
// that size); outside the raster, alpha 0. Bands: one (grey, or a palette), three (RGB), or
// either with an alpha band; samples other than bytes are clipped to [0, 255] with a warning.
// Throws InputError naming the path, the field and what was expected.
Orthophoto readOrthophoto(const OrthophotoRequest& request, Diagnostics& diag);

// The orthophoto scene.json names ("orthophoto": {"path", "resolution", "crs"}), read over the
// loaded scene's terrain (its extent: the streamed quadtree's root, else the terrain mesh's): null
// when scene.json names none, and, with a warning naming the path, the field and what was
// expected, when it cannot be read (the terrain is then shaded as without one). Kept beside the
// scene, not in it; the session hands it to the renderer (render::Renderer::setOrthophoto).
std::shared_ptr<const Orthophoto> loadOrthophoto(const Scene& scene, Diagnostics& diag);

// Writes an RGB or RGBA image (width * height * channels bytes, row 0 the northern edge) as a
// cloud-optimised GeoTIFF (GDAL's COG driver: tiled, DEFLATE, overviews) covering the rectangle
// of `o` in `crs`. Throws InputError naming the file.
void writeOrthophotoCog(const std::string& path, const Orthophoto& o, const std::string& crs);

}  // namespace hv
