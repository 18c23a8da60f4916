// GDAL set-up shared by the readers under hv/io/native/private/. Private: includes GDAL headers, so only
// .cpp files under io/native/private/ may include it.
#pragma once

#include <cpl_error.h>

#include <string>

class GDALDataset;
class OGRSpatialReference;

namespace hv::gdal {

// Registers GDAL's drivers once per process, whichever thread asks first (std::call_once).
void ensureRegistered();

// While alive, GDAL errors raised on this thread are not printed to stderr; the caller reports
// them through InputError / Diagnostics instead (GDAL's handler stack is thread-local).
class QuietErrors {
 public:
  QuietErrors() {
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLErrorReset();
  }
  ~QuietErrors() { CPLPopErrorHandler(); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;
};

// Throws InputError naming `path` and `what` unless GDAL may open it without blocking: a regular
// file, or (`allowDirectory`: OGR reads a folder of shapefiles) a directory. A FIFO would block
// GDAL's open forever and a device would be read without end. GDAL's virtual paths ("/vsizip/",
// "/vsicurl/") are left to GDAL.
void requireOpenable(const std::string& path, const std::string& what, bool allowDirectory);

// Opens `path` as a vector source, read-only (nullptr when GDAL cannot; lastError says why), with
// the open options histoview gives services: an OGC API - Features source ("OAPIF:…") is read
// kOapifPageSize features a request instead of GDAL 3.6's 10 (the standard's default limit), so
// that a tile of a city is one request or a few, not one per ten buildings. A server whose limit
// is lower answers with fewer and a link to the next page, which GDAL follows.
GDALDataset* openVector(const std::string& path);
inline constexpr int kOapifPageSize = 1000;

// GDAL's last error message on this thread, or `fallback` when it left none.
std::string lastError(const std::string& fallback);

// A CRS as hv::GeoTransform takes it: "EPSG:n" when GDAL identifies an EPSG CRS (short, and what
// users write), else its WKT2 (which PROJ reads without loss, compound CRSs included); empty for
// none.
std::string crsDefinition(const OGRSpatialReference* srs);

}  // namespace hv::gdal
