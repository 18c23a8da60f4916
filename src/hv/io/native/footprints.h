// Building footprints from any OGR vector source (GeoJSON, GeoPackage, Shapefile, ...).
#pragma once

#include "hv/io/native/georef.h"
#include "hv/scene/building_tiles.h"
#include "hv/scene/heightfield.h"
#include "hv/scene/native/lod1.h"
#include "hv/util/diagnostics.h"

#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hv {

struct FootprintFields {
  std::string height = "height";    // attribute: height in metres above the base
  std::optional<std::string> base;  // attribute: absolute base elevation
  std::optional<std::string> top;   // attribute: absolute roof elevation
  std::optional<std::string> validFrom, validTo;
};

// Reads Polygon and MultiPolygon features (a MultiPolygon gives one footprint per part, ids
// "<fid>.<part>"), holes included. A feature with no geometry, another geometry type, fewer than
// 3 points or no usable height is skipped with a warning naming its feature id. Throws InputError
// naming the file when it cannot be opened at all.
// Coordinates and attributes as they are in the file.
std::vector<Footprint> readFootprints(const std::string& path, const FootprintFields& fields, Diagnostics& diag);

struct GeoreferencedFootprints {
  std::vector<Footprint> footprints;  // in the scene frame
  // The CRS they were read in (the first layer's): the one transformed from, or, when the scene
  // has no CRS, the one they declare (taken as they are); empty: none.
  std::string sourceCrs;
};

// The footprints brought into the scene frame (hv/io/georef.h). Each layer's CRS: `georef.crs`,
// else the layer's own (GeoJSON without a `crs` member is WGS 84 longitude, latitude: RFC 7946,
// and GDAL says so), else the scene's. A layer said to be geographic whose coordinates cannot be
// degrees (|lon| > 360, |lat| > 90: an old GeoJSON in projected coordinates) is taken in the scene
// CRS, with a warning. Vertices go through PROJ in longitude-latitude / easting-
// northing order. `height` is in the CRS's height unit (CrsDescription::heightToMetre: feet for a
// 2D CRS in feet) and becomes metres; absolute `base` and `top` go through PROJ at the
// footprint's first vertex when both CRSs have a vertical axis, else are only converted to metres,
// with a warning when the CRSs differ. A footprint PROJ cannot transform is skipped with a
// warning. Throws InputError naming the file, or `georef.field`, when the source or a CRS cannot
// be read, and when the scene is geocentric (LOD1 extrusion needs a vertical z).
GeoreferencedFootprints readFootprints(const std::string& path, const FootprintFields& fields,
                                       const SourceGeoref& georef, Diagnostics& diag);

// Footprints read by tile (de Castro & Brédif 2022: data in tiles, fetched for the view). Each
// layer's extent (its own CRS) is cut into a regular grid of square tiles; a feature belongs to
// the one tile that holds its first vertex (the first point of its first polygon's outer ring),
// so a building crossing tile borders is read, extruded and drawn once. Where the layer has a
// fast spatial filter (OLCFastSpatialFilter: GeoPackage, FlatGeobuf, Shapefile with a .qix),
// each wanted tile is read through OGRLayer::SetSpatialFilterRect; otherwise the layer is read
// once and its features sorted into the tiles in memory (`note` says so).
struct FootprintTileOptions {
  // Tile side in the layer's units; 0: chosen from the layer's density, about `perTile` features
  // per tile (at most 256 x 256 tiles per layer).
  double tileSize = 0.0;
  std::size_t perTile = 256;
  // Which tiles to read, given a tile's box (x, y) in the scene frame; empty: all of them. Asked
  // once for every tile, layer by layer, in the order of FootprintTile::index.
  std::function<bool(glm::dvec2 lo, glm::dvec2 hi)> wanted;
};

struct FootprintTile {
  std::size_t index = 0;              // among every layer's tiles, in the order `wanted` is asked
  glm::dvec2 lo{0.0}, hi{0.0};        // the tile's box in the scene frame (its corners transformed)
  std::vector<Footprint> footprints;  // in the scene frame, as readFootprints gives them
};

struct FootprintTileSource {
  std::string path;
  std::string sourceCrs;        // as GeoreferencedFootprints::sourceCrs
  std::size_t tilesTotal = 0;   // over every layer
  std::size_t tilesRead = 0;    // the wanted ones
  std::size_t tilesFailed = 0;  // wanted ones whose reading failed part-way (a service error): reported
  std::size_t features = 0;     // the layers' feature counts (OGRLayer::GetFeatureCount; 0: a service)
  bool spatialFilter = true;    // every layer read through OGR's spatial filter
  double tileSize = 0.0;        // the first layer's, in its units
  std::string note;             // why a layer was read whole and indexed in memory; empty: none
};

// Reads the wanted tiles, calling `consume` once per tile that holds footprints (so the caller
// can extrude a tile and drop its footprints before the next is read). Same checks, warnings and
// georeferencing as readFootprints; a feature is read (and warned about) only with its tile. With
// a spatial filter, features without geometry are never returned by it: their number is given in
// one warning when every tile is read. Throws like readFootprints.
FootprintTileSource readFootprintTiles(const std::string& path, const FootprintFields& fields,
                                       const SourceGeoref& georef, const FootprintTileOptions& options,
                                       const std::function<void(FootprintTile&)>& consume, Diagnostics& diag);

// The tiles of readFootprintTiles read one at a time from a source kept open: the dataset and each
// layer's frame (its CRS transform) and grid are made once, each read is one tile through the
// spatial filter, with the footprints, warnings and errors readFootprintTiles gives for it. Every
// layer must have a fast spatial filter (FootprintTileSource::spatialFilter). Not thread-safe
// (a GDAL dataset is used by one thread at a time): one reader per thread.
class FootprintTileReader {
 public:
  // Throws like readFootprintTiles.
  FootprintTileReader(const std::string& path, const FootprintFields& fields, const SourceGeoref& georef,
                      const FootprintTileOptions& options);
  ~FootprintTileReader();
  FootprintTileReader(const FootprintTileReader&) = delete;
  FootprintTileReader& operator=(const FootprintTileReader&) = delete;
  std::size_t tiles() const;
  // Tile `tile` (FootprintTile::index), in the scene frame; std::out_of_range beyond tiles().
  std::vector<Footprint> read(std::size_t tile, Diagnostics& diag);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One tile's footprints extruded as the whole load extrudes them (buildLod1 on `dtm`, null: none),
// with the validity dates of their attributes (`fields.validFrom`, `validTo`: ISO 8601; one that
// does not parse is warned about, naming `path` and the footprint, and ignored). Triangle tags
// index `validity`, one per footprint, in their order.
BuildingTileData extrudeFootprintTile(const std::vector<Footprint>& footprints, const Heightfield* dtm,
                                      const FootprintFields& fields, const std::string& path, Diagnostics& diag);

// extrudeFootprintTile for many tiles at once, on up to `threads` threads (0: the machine's
// cores): the same meshes, dates and warnings as extruding them one after the other in their
// order (each tile's warnings go to `diag` in the tiles' order). The scene loader's tiles read at
// load: the extrusion is most of their cost, the reading through one dataset stays sequential.
std::vector<BuildingTileData> extrudeFootprintTiles(const std::vector<std::vector<Footprint>>& tiles,
                                                    const Heightfield* dtm, const FootprintFields& fields,
                                                    const std::string& path, Diagnostics& diag, int threads = 0);

// The buildings of `path` as tiles read on demand (docs/design.md, "Building streaming"): the grid
// of readFootprintTiles (about options.perTile footprints a tile; `options.wanted` is not used),
// each tile's box (its cell widened by a cell on each side: buildings crossing its borders) with
// heights `zlo`..`zhi`, and a reader extruding one tile on `dtm` (shared, may be null) as
// extrudeFootprintTile does. Through the spatial filter, each read reads that one tile with a
// FootprintTileReader of its thread's own (safe from several threads: the readers, each opened
// once, are pooled and each used by one thread at a time); a source without one is read once now and its footprints
// kept by tile in memory (`info.note` says so). `info` gets the grid's figures; warnings of the
// first reading go to `diag`, a tile's to its BuildingTileData. Throws like readFootprintTiles; the
// reader throws for a tile out of range or one whose reading failed.
std::shared_ptr<const BuildingTileSet> footprintTileSet(const std::string& path, const FootprintFields& fields,
                                                        const SourceGeoref& georef, const FootprintTileOptions& options,
                                                        std::shared_ptr<const Heightfield> dtm, double zlo, double zhi,
                                                        FootprintTileSource& info, Diagnostics& diag);

}  // namespace hv
