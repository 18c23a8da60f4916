// The camera catalog: photographs' cameras in a PostgreSQL/PostGIS table (docs/catalog.md), the
// way Brédif's 2016 viewer keeps them, written by `histoview catalog load` and read by scene.json's
// `"cameras": {"postgis": ..., "table": ...}`. Through GDAL/OGR's PostgreSQL driver: no libpq of
// our own.
//
// One row per photograph: the camera centre as a 3D point (`centre`, geometry(PointZ, SRID of the
// cameras' CRS; 0 when they have none)) under a GiST index, the rest as columns, each field of
// hv::Photo without loss (docs/catalog.md has the layout). Rows are numbered by `fid` from 1 in the order of the
// collection written, and read back in that order: photo i of a catalog is the row of fid i + 1.
//
// Connections: "postgresql://user@host:port/db", "PG:host=... dbname=..." or anything else GDAL's
// PostgreSQL driver opens. Messages name the connection with its password hidden
// (redactConnection). Table names: `name` or `schema.name`, letters, digits and underscores, not
// starting with a digit (they are written into SQL).
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hv {

inline constexpr const char* kDefaultCatalogTable = "cameras";

// The connection as GDAL's PostgreSQL driver opens it: "postgresql://..." and "PG:..." as they
// are; anything else is refused (InputError) so that a file path is not taken for a database.
std::string catalogConnection(const std::string& connection);
// The connection with its password replaced by "***" (URI user:password@, or password=...).
std::string redactConnection(const std::string& connection);
// Throws InputError naming `field` unless `table` is `name` or `schema.name` as above.
void checkCatalogTableName(const std::string& table, const std::string& field);

struct CatalogWriteResult {
  std::size_t rows = 0;
  int srid = 0;  // of `centre`; 0: no CRS
};

// Writes `photos` into `table`, replacing a table of that name. `crs` is the frame of their
// centres and rotations (the scene CRS; empty: none, SRID 0). Image and mask paths are written as
// they are (the caller makes them absolute). Throws InputError naming the connection (redacted)
// and the table when the database cannot be reached or written; nothing is left half-written (one
// transaction).
CatalogWriteResult writeCameraCatalog(const std::vector<Photo>& photos, const std::string& crs,
                                      const std::string& connection, const std::string& table);

struct CatalogCameras {
  std::vector<Photo> photos;  // in fid order
  std::string crs;            // the table's CRS ("EPSG:2154", else WKT); empty for SRID 0
};

// Reads every row of `table` (mode (a) of docs/catalog.md: all the cameras at open). A row with a
// bad field is skipped with an error naming the connection, table, fid, camera and field; the
// others load. Throws InputError when the database or the table cannot be read.
CatalogCameras readCameraCatalog(const std::string& connection, const std::string& table, Diagnostics& diag);

// The same cameras as a point layer of any OGR source (docs/formats.md, "Cameras as an OGR point
// layer"): a 3D point at the camera centre, the catalog's columns as properties, the way de Castro &
// Brédif 2022 publish them through WFS. Number arrays may be list fields or text ("{a,b,...}",
// "[a,b,...]").
//
// Writes `photos` as layer `layer` of a new GeoPackage (.gpkg) or GeoJSON (.geojson) file at `path`
// (replaced when it exists), doubles exact (GeoPackage REAL; GeoJSON and the arrays' text with 17
// significant digits). Throws InputError naming the file.
std::size_t writeOgrCameras(const std::vector<Photo>& photos, const std::string& crs, const std::string& path,
                            const std::string& layer);
// Reads every feature of `layer` (empty: the source's only layer) of `source`: a file GDAL opens
// or a connection string ("WFS:http://...", "OAPIF:http://..."). A feature with a bad or missing
// field is skipped with an error naming the source, layer, feature id, camera and field. Throws
// InputError when the source or the layer cannot be opened. Image paths are as the layer has them.
CatalogCameras readOgrCameras(const std::string& source, const std::string& layer, Diagnostics& diag);

// The text forms of number fields: one number (surrounding blanks allowed), and a list "{a,b,...}"
// (PostgreSQL) or "[a,b,...]" (JSON). nullopt when malformed or not finite.
std::optional<double> parseNumber(std::string_view text);
std::optional<std::vector<double>> parseNumberList(std::string_view text);

// Nearest cameras asked of the database (docs/catalog.md, "Nearest cameras"), for views that do not
// hold every camera: the 2016 paper's query by the PostGIS `<->` operator on the GiST index, made
// exact in 3D so that it selects what the in-memory selection (hv/ibr/selection.h) selects.
class CameraCatalog {
 public:
  struct Neighbour {
    std::int64_t fid = 0;  // the row (photo fid - 1 of readCameraCatalog)
    std::string id;        // the camera's id
    double distance = 0;   // |position - centre|, in the table's units
  };

  // Throws InputError when the database or the table cannot be read.
  CameraCatalog(const std::string& connection, const std::string& table);
  ~CameraCatalog();
  CameraCatalog(CameraCatalog&&) noexcept;
  CameraCatalog& operator=(CameraCatalog&&) noexcept;

  std::size_t size() const;  // rows
  int srid() const;
  // The `k` rows whose centres are nearest to `position` (in the table's frame), ascending
  // distance, ties broken by fid. Throws InputError when the query fails.
  std::vector<Neighbour> nearestCameras(const glm::dvec3& position, std::size_t k) const;
  // The same for several positions in one query, one round trip (the positions a path will reach,
  // for prefetching): result i is nearestCameras(positions[i], k).
  std::vector<std::vector<Neighbour>> nearestCameras(const std::vector<glm::dvec3>& positions, std::size_t k) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hv
