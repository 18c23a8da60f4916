#include "hv/io/native/private/gdal_init.h"
#include "hv/io/native/private/service_fetch.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "hv/io/native/remote.h"
#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"

#include <cstring>
#include <filesystem>
#include <mutex>
#include <system_error>

namespace hv::gdal {

void ensureRegistered() {
  static std::once_flag once;
  std::call_once(once, [] {
    // What the user set (environment, --config) wins; CPLGetConfigOption reads the environment.
    for (const HttpDefault& d : kHttpDefaults)
      if (!CPLGetConfigOption(d.key, nullptr)) CPLSetConfigOption(d.key, d.value);
    // GDAL's WMS and WMTS drivers keep the tiles they fetched in ./gdalwmscache by default, beside
    // whatever folder histoview runs in: histoview's cache folder instead, under its cap, and none
    // when the cache is off (docs/services.md, "Cache"). What the user set wins.
    if (!CPLGetConfigOption("GDAL_DEFAULT_WMS_CACHE_PATH", nullptr) &&
        !CPLGetConfigOption("GDAL_ENABLE_WMS_CACHE", nullptr)) {
      const ResponseCacheSettings cache = responseCacheSettings();
      if (cache.tileFolder.empty())
        CPLSetConfigOption("GDAL_ENABLE_WMS_CACHE", "NO");
      else
        CPLSetConfigOption("GDAL_DEFAULT_WMS_CACHE_PATH", cache.tileFolder.c_str());
    }
    // Services' requests through the response cache, with progress (service_fetch.h).
    installServiceFetch();
    GDALAllRegister();
  });
}

void requireOpenable(const std::string& path, const std::string& what, bool allowDirectory) {
  // GDAL's virtual paths and connection strings ("WFS:http://...", docs/services.md) are GDAL's to
  // open; a local file of that name is checked like any other.
  if (isRemoteSource(path)) return;
  if (allowDirectory) {
    std::error_code ec;
    if (path.find('\0') == std::string::npos && std::filesystem::is_directory(path, ec)) return;
  }
  requireRegularFile(path, what);
}

GDALDataset* openVector(const std::string& path) {
  auto startsWith = [&](const char* prefix) { return EQUALN(path.c_str(), prefix, std::strlen(prefix)); };
  const std::string pageSize = "PAGE_SIZE=" + std::to_string(kOapifPageSize);
  const char* const oapif[] = {pageSize.c_str(), nullptr};
  const bool isOapif = startsWith("OAPIF:") || startsWith("WFS3:");
  return GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, isOapif ? oapif : nullptr);
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
