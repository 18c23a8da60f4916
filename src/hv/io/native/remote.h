// Sources that live on a server (docs/services.md): the HTTP settings histoview gives GDAL, the
// cache folder, and the reader of whole remote files (cameras JSON, CityJSON, LAS, PLY, meshes)
// behind hv::readTextFile / hv::readFileBytes. Rasters and vector layers named by a connection
// string ("WCS:http://...", "WFS:http://...") are opened by GDAL's own drivers instead.
#pragma once

#include <cstdint>
#include <string>

namespace hv {

// GDAL's HTTP settings as histoview sets them unless the user set them (environment or
// --config): time-out, connection time-out, retries with backoff on 429/502/503/504, WFS paging.
// The values are in docs/services.md ("HTTP settings").
struct HttpDefault {
  const char* key;
  const char* value;
};
inline constexpr HttpDefault kHttpDefaults[] = {
    {"GDAL_HTTP_TIMEOUT", "30"},                    // seconds for a whole request
    {"GDAL_HTTP_CONNECTTIMEOUT", "10"},             // seconds to connect
    {"GDAL_HTTP_MAX_RETRY", "3"},                   // retries of a request answered 429, 502, 503 or 504
    {"GDAL_HTTP_RETRY_DELAY", "1"},                 // seconds before the first retry, doubled at each
    {"OGR_WFS_PAGING_ALLOWED", "ON"},               // WFS 2.0: GetFeature pages (STARTINDEX, COUNT)
    {"OGR_WFS_PAGE_SIZE", "1000"},                  // features per WFS page
    {"GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR"},  // no listing of a URL's "folder" on open
};

// Sets kHttpDefaults in GDAL (once per process), and lets readTextFile / readFileBytes read
// http(s):// URLs and GDAL virtual paths (/vsicurl/...) through GDAL. Idempotent.
void enableRemoteReading();

// histoview's cache folder (docs/services.md, "Cache"): $HV_CACHE_DIR, else
// $XDG_CACHE_HOME/histoview, else $HOME/.cache/histoview; "" when none of these is set. Never
// beside the user's data.
std::string cacheFolder();

// The whole of a remote source, at most `maxBytes`: an http(s):// URL through GDAL's HTTP client
// (its time-out and retries), a /vsi path through GDAL's virtual file system. Throws InputError
// naming the URL, `what` and the HTTP status or transport error.
std::string readRemote(const std::string& url, std::uint64_t maxBytes, const std::string& what);

}  // namespace hv
