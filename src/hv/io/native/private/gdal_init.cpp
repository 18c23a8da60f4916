#include "hv/io/native/private/gdal_init.h"

#include <gdal.h>
#include <ogr_spatialref.h>

#include <mutex>

namespace hv::gdal {

void ensureRegistered() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

std::string lastError(const std::string& fallback) {
  const char* message = CPLGetLastErrorMsg();
  return (message && *message) ? std::string(message) : fallback;
}

std::string crsDefinition(const OGRSpatialReference* srs) {
  if (!srs) return {};
  const char* authority = srs->GetAuthorityName(nullptr);
  const char* code = srs->GetAuthorityCode(nullptr);
  if (authority && code && std::string(authority) == "EPSG") return std::string("EPSG:") + code;
  char* wkt = nullptr;
  std::string out;
  const char* const options[] = {"FORMAT=WKT2_2019", nullptr};
  if (srs->exportToWkt(&wkt, options) == OGRERR_NONE && wkt) out = wkt;
  CPLFree(wkt);
  return out;
}

}  // namespace hv::gdal
