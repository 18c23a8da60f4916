// Sources that live on a server (docs/services.md): the HTTP settings histoview gives GDAL, the
// cache folder, and the reader of whole remote files (cameras JSON, CityJSON, LAS, PLY, meshes)
// behind hv::readTextFile / hv::readFileBytes. Rasters and vector layers named by a connection
// string ("WCS:http://...", "WFS:http://...") are opened by GDAL's own drivers instead.
#pragma once

#include "hv/util/input_file.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

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
    {"OGR_WFS_USE_STREAMING", "NO"},                // GetFeature pages through CPLHTTPFetch: cached
    {"GDAL_DISABLE_READDIR_ON_OPEN", "EMPTY_DIR"},  // no listing of a URL's "folder" on open
};

// Sets kHttpDefaults in GDAL (once per process), and lets readTextFile / readFileBytes read
// http(s):// URLs and GDAL virtual paths (/vsicurl/...) through GDAL. Idempotent.
void enableRemoteReading();

// histoview's cache folder (docs/services.md, "Cache"): $HV_CACHE_DIR, else
// $XDG_CACHE_HOME/histoview, else $HOME/.cache/histoview; "" when none of these is set. Never
// beside the user's data.
std::string cacheFolder();

// The response cache (docs/services.md, "Cache"): whole http(s):// responses on disk in
// cacheFolder()/responses/, one file per URL, kept under a size cap by removing the least
// recently used (file modification time, touched at each hit). Photographs, masks and IIIF
// descriptions (RemoteCache::Yes), and the requests GDAL's drivers send to services — WFS, OGC API
// - Features, WCS, WMTS capabilities (private/service_fetch.h); no revalidation: remove the folder
// to ask again. GDAL's own cache of WMS/WMTS tiles (cacheFolder()/gdal-wms/) is held under the same
// cap, together with the responses.
struct ResponseCacheSettings {
  std::string folder;          // "" : no cache
  std::string tileFolder;      // GDAL's WMS/WMTS tile cache, trimmed with the responses
  std::uint64_t capBytes = 0;  // total size of the cached responses and tiles
};
inline constexpr std::uint64_t kDefaultResponseCacheMiB = 1024;
// From the environment: HV_NO_CACHE (set and not "0": no cache), HV_CACHE_MAX_MB (the cap in
// MiB, decimals allowed, default kDefaultResponseCacheMiB; 0: no cache) and cacheFolder().
ResponseCacheSettings responseCacheSettings();
// The file that holds `url`'s response in `folder` (a hash of the URL; the file's first line is
// the URL itself, so that two URLs of one hash are told apart).
std::string responseCacheFile(const std::string& folder, const std::string& url);
// Removes the least recently used files under `folder` (or under all `folders` together, their
// sub-folders included) until they take at most `capBytes`. Returns the bytes left.
std::uint64_t trimResponseCache(const std::string& folder, std::uint64_t capBytes);
std::uint64_t trimResponseCache(const std::vector<std::string>& folders, std::uint64_t capBytes);
// The cached response stored under `key` (its first line), touched; nullopt when the cache is off,
// holds none or holds one over `maxBytes`.
std::optional<std::string> readCachedResponse(const ResponseCacheSettings& settings, const std::string& key,
                                              std::uint64_t maxBytes);
// Stores `body` under `key` (written aside then renamed) and trims the cache under its cap; a body
// over the cap is not kept. Nothing when the cache is off.
void writeCachedResponse(const ResponseCacheSettings& settings, const std::string& key, const std::string& body);
// Counts a response in remoteFetchCounts (for the readers that fetch through GDAL's drivers).
void countRemoteResponse(bool fromCache, std::uint64_t bytes);

// The whole of a remote source, at most `maxBytes`: an http(s):// URL through GDAL's HTTP client
// (its time-out and retries), a /vsi path through GDAL's virtual file system. Throws InputError
// naming the URL, `what` and the HTTP status or transport error. With RemoteCache::Yes an
// http(s):// response comes from the response cache when it holds it, and goes into it otherwise.
std::string readRemote(const std::string& url, std::uint64_t maxBytes, const std::string& what,
                       RemoteCache cache = RemoteCache::No);

// What readRemote read over http(s) since the process started: responses (and their bytes)
// fetched from the servers and read from the response cache. Failed requests are not counted.
struct RemoteFetchCounts {
  std::uint64_t fetched = 0, fetchedBytes = 0;
  std::uint64_t cached = 0, cachedBytes = 0;
};
RemoteFetchCounts remoteFetchCounts();

}  // namespace hv
