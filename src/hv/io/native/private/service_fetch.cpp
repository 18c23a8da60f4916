#include "hv/io/native/private/service_fetch.h"

#include <cpl_conv.h>
#include <cpl_http.h>
#include <cpl_string.h>

#include "hv/io/native/remote.h"
#include "hv/util/load_progress.h"
#include "hv/util/log.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <mutex>
#include <optional>
#include <utility>
#include <vector>

namespace hv::gdal {

namespace {

thread_local ServiceProgress* tCurrent = nullptr;
thread_local bool tDirect = false;  // DirectFetch, or the callback asking GDAL's client itself

std::string sizeText(std::uint64_t bytes) {
  char buf[32];
  if (bytes < 10 * 1024)
    std::snprintf(buf, sizeof buf, "%llu bytes", static_cast<unsigned long long>(bytes));
  else if (bytes < 10 * 1024 * 1024)
    std::snprintf(buf, sizeof buf, "%.0f KB", double(bytes) / 1024.0);
  else
    std::snprintf(buf, sizeof buf, "%.1f MB", double(bytes) / (1024.0 * 1024.0));
  return buf;
}

// The cache key of a GET: "GDAL <url>", with the request's extra headers (an OGC API client asks
// for GeoJSON by its Accept header) on the same line. The prefix keeps these apart from readRemote's
// entries, whose key is the URL alone.
std::string cacheKey(const char* url, CSLConstList options) {
  std::string key = std::string("GDAL ") + url;
  if (const char* headers = CSLFetchNameValue(options, "HEADERS")) {
    std::string h = headers;
    std::replace(h.begin(), h.end(), '\r', ' ');
    std::replace(h.begin(), h.end(), '\n', ' ');
    key += " [" + h + "]";
  }
  return key;
}

// A cached entry is "<content type>\n<body>": the WCS driver reads a multipart answer's boundary
// from the content type, the OGC API driver its media type.
CPLHTTPResult* resultFromCache(const std::string& entry) {
  const std::size_t eol = entry.find('\n');
  if (eol == std::string::npos) return nullptr;
  auto* r = static_cast<CPLHTTPResult*>(CPLCalloc(1, sizeof(CPLHTTPResult)));
  if (eol > 0) r->pszContentType = CPLStrdup(entry.substr(0, eol).c_str());
  const std::size_t n = entry.size() - eol - 1;
  r->pabyData = static_cast<GByte*>(CPLMalloc(n + 1));
  std::memcpy(r->pabyData, entry.data() + eol + 1, n);
  r->pabyData[n] = 0;
  r->nDataLen = static_cast<int>(n);
  r->nDataAlloc = static_cast<int>(n + 1);
  return r;
}

// Whether GDAL's answer to a GET may be answered from, and kept in, the cache.
bool cacheable(const char* url, CSLConstList options, CPLHTTPFetchWriteFunc write) {
  if (write) return false;  // streamed to the caller's writer
  if (!STARTS_WITH_CI(url, "http://") && !STARTS_WITH_CI(url, "https://")) return false;
  for (const char* key : {"POSTFIELDS", "CUSTOMREQUEST", "NO_BODY", "FORM_FILE_PATH", "FORM_ITEM_COUNT",
                          "CLOSE_PERSISTENT"})
    if (CSLFetchNameValue(options, key)) return false;
  return true;
}

CPLHTTPResult* serviceFetch(const char* url, CSLConstList options, GDALProgressFunc progress, void* progressArg,
                            CPLHTTPFetchWriteFunc write, void* writeArg, void* /*userData*/) {
  if (tDirect) return nullptr;  // GDAL's own client
  ServiceProgress* report = tCurrent;
  const bool useCache = cacheable(url, options, write);
  const ResponseCacheSettings settings = useCache ? responseCacheSettings() : ResponseCacheSettings{};
  const std::string key = settings.folder.empty() ? std::string() : cacheKey(url, options);
  if (!key.empty()) {
    if (std::optional<std::string> hit = readCachedResponse(settings, key, std::uint64_t(1) << 31)) {
      if (CPLHTTPResult* r = resultFromCache(*hit)) {
        log::debug(std::string(url) + ": from the response cache");
        countRemoteResponse(true, std::uint64_t(r->nDataLen));
        if (report) report->response(url, std::uint64_t(r->nDataLen), true);
        return r;
      }
    }
  }
  // GDAL's client, this callback stepping aside on this thread.
  CPLHTTPResult* r = nullptr;
  {
    const DirectFetch direct;
    r = CPLHTTPFetchEx(url, options, progress, progressArg, write, writeArg);
  }
  // Never nullptr from here: GDAL would then send the request a second time itself.
  if (!r) r = static_cast<CPLHTTPResult*>(CPLCalloc(1, sizeof(CPLHTTPResult)));
  const bool ok = r->nStatus == 0 && !r->pszErrBuf && r->pabyData && r->nDataLen > 0;
  if (ok) {
    countRemoteResponse(false, std::uint64_t(r->nDataLen));
    if (report) report->response(url, std::uint64_t(r->nDataLen), false);
    const std::string body(reinterpret_cast<const char*>(r->pabyData), std::size_t(r->nDataLen));
    if (!key.empty() && !isExceptionReport(body)) {
      std::string entry = r->pszContentType ? r->pszContentType : "";
      entry.erase(std::remove(entry.begin(), entry.end(), '\n'), entry.end());
      writeCachedResponse(settings, key, entry + '\n' + body);
    }
  }
  return r;
}

}  // namespace

void installServiceFetch() {
  static std::once_flag once;
  std::call_once(once, [] { CPLHTTPSetFetchCallback(&serviceFetch, nullptr); });
}

void trimTileCache() {
  const ResponseCacheSettings s = responseCacheSettings();
  const char* gdalPath = CPLGetConfigOption("GDAL_DEFAULT_WMS_CACHE_PATH", nullptr);
  if (s.folder.empty() || !gdalPath || s.tileFolder != gdalPath) return;
  trimResponseCache(std::vector<std::string>{s.folder, s.tileFolder}, s.capBytes);
}

ServiceProgress::ServiceProgress(std::string what, std::string source)
    : what_(std::move(what)), source_(std::move(source)), previous_(tCurrent) {
  tCurrent = this;
}

ServiceProgress::~ServiceProgress() { tCurrent = previous_; }

ServiceProgress* ServiceProgress::current() { return tCurrent; }

void ServiceProgress::response(const std::string& url, std::uint64_t bytes, bool fromCache) {
  ++requests_;
  std::string line = "loading " + what_ + " from " + source_ + ": ";
  if (tileN_ > 0) line += "tile " + std::to_string(tileK_) + " of " + std::to_string(tileN_) + ": ";
  line += requestName(url) + ", " + sizeText(bytes) + (fromCache ? " from the cache" : "");
  if (features_ > 0 || tileN_ > 0) line += " (" + std::to_string(features_) + " features so far)";
  log::info(line);
  recordLoadProgress(what_, source_, bytes, fromCache, line);
}

DirectFetch::DirectFetch() : previous_(tDirect) { tDirect = true; }
DirectFetch::~DirectFetch() { tDirect = previous_; }

std::string requestName(const std::string& url) {
  const std::size_t q = url.find('?');
  if (q != std::string::npos) {
    std::size_t at = q;
    while (at != std::string::npos && at < url.size()) {
      const std::size_t start = at + 1;
      if (url.size() - start > 8 && STARTS_WITH_CI(url.c_str() + start, "REQUEST=")) {
        const std::size_t end = url.find('&', start);
        return url.substr(start + 8, end == std::string::npos ? std::string::npos : end - start - 8);
      }
      at = url.find('&', start);
    }
  }
  const std::string path = url.substr(0, q);
  const std::size_t slash = path.find_last_of('/');
  std::string last = slash == std::string::npos ? path : path.substr(slash + 1);
  return last.empty() ? path : last;
}

bool isExceptionReport(const std::string& body) {
  const std::string head = body.substr(0, 4096);
  return head.find("ExceptionReport") != std::string::npos || head.find("ServiceException") != std::string::npos;
}

}  // namespace hv::gdal
