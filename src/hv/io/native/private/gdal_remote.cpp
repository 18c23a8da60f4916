#include <cpl_conv.h>
#include <cpl_http.h>
#include <cpl_string.h>
#include <cpl_vsi.h>

#include "hv/io/native/private/gdal_init.h"
#include "hv/io/native/private/service_fetch.h"
#include "hv/io/native/remote.h"
#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"

#include "hv/util/log.h"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace hv {

namespace {

bool startsWithNoCase(const std::string& s, const char* prefix) { return STARTS_WITH_CI(s.c_str(), prefix); }

std::string sizeLimitText(std::uint64_t bytes) { return std::to_string(bytes) + " bytes"; }

// The folders the cap holds together: the responses and GDAL's WMS/WMTS tiles beside them.
std::vector<std::string> cacheFoldersOf(const ResponseCacheSettings& settings) {
  std::vector<std::string> folders{settings.folder};
  if (!settings.tileFolder.empty()) folders.push_back(settings.tileFolder);
  return folders;
}

std::mutex gCountsMutex;
RemoteFetchCounts gCounts;

void countResponse(bool fromCache, std::uint64_t bytes) {
  std::lock_guard lock(gCountsMutex);
  if (fromCache) {
    ++gCounts.cached;
    gCounts.cachedBytes += bytes;
  } else {
    ++gCounts.fetched;
    gCounts.fetchedBytes += bytes;
  }
}

std::string readHttp(const std::string& url, std::uint64_t maxBytes, const std::string& what) {
  const std::string maxSize = "MAX_FILE_SIZE=" + std::to_string(maxBytes);
  const char* const options[] = {maxSize.c_str(), nullptr};
  // CPLHTTPFetch takes its time-out and retries from the configuration (kHttpDefaults). Past the
  // service cache (service_fetch.h): readRemote keeps its own rules of what is cached.
  const gdal::DirectFetch direct;
  std::unique_ptr<CPLHTTPResult, void (*)(CPLHTTPResult*)> result(
      CPLHTTPFetch(url.c_str(), const_cast<char**>(options)), CPLHTTPDestroyResult);
  if (!result) throw InputError(inputMessage(url, what, gdal::lastError("the request failed")));
  if (result->nStatus != 0 || result->pszErrBuf) {
    std::string why = result->pszErrBuf ? result->pszErrBuf : gdal::lastError("transfer error");
    throw InputError(inputMessage(url, what, why));
  }
  if (std::uint64_t(result->nDataLen) > maxBytes)
    throw InputError(inputMessage(
        url, what,
        "the response is over the limit of " + sizeLimitText(maxBytes) + " for this input (docs/formats.md, Limits)"));
  countResponse(false, std::uint64_t(result->nDataLen));
  log::debug(url + ": " + std::to_string(result->nDataLen) + " bytes fetched");
  return std::string(reinterpret_cast<const char*>(result->pabyData), std::size_t(result->nDataLen));
}

std::string readVsi(const std::string& path, std::uint64_t maxBytes, const std::string& what) {
  VSILFILE* f = VSIFOpenL(path.c_str(), "rb");
  if (!f) throw InputError(inputMessage(path, what, gdal::lastError("cannot open")));
  std::string out;
  char buf[1 << 16];
  bool failed = false;
  for (;;) {
    const std::size_t n = VSIFReadL(buf, 1, sizeof buf, f);
    if (n < sizeof buf && !VSIFEofL(f)) failed = true;  // a short read before the end: an error
    if (n == 0) break;
    if (out.size() + n > maxBytes) {
      VSIFCloseL(f);
      throw InputError(inputMessage(
          path, what, "over the limit of " + sizeLimitText(maxBytes) + " for this input (docs/formats.md, Limits)"));
    }
    out.append(buf, n);
  }
  VSIFCloseL(f);
  if (failed) throw InputError(inputMessage(path, what, gdal::lastError("read error")));
  return out;
}

std::string readRemoteForUtil(const std::string& url, std::uint64_t maxBytes, const std::string& what,
                              RemoteCache cache) {
  return readRemote(url, maxBytes, what, cache);
}

namespace fs = std::filesystem;

std::string envValue(const char* key) {
  const char* v = std::getenv(key);
  return v ? std::string(v) : std::string();
}

// A cached response: "<url>\n<body>". Empty when the file is absent, holds another URL or is
// over `maxBytes`; a hit is touched, so the trimming keeps it (least recently used goes first).
std::optional<std::string> cachedResponseFile(const std::string& file, const std::string& url, std::uint64_t maxBytes) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return std::nullopt;
  std::string first;
  if (!std::getline(in, first) || first != url) return std::nullopt;
  std::string body((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad() || body.size() > maxBytes) return std::nullopt;
  std::error_code ec;
  fs::last_write_time(file, fs::file_time_type::clock::now(), ec);
  return body;
}

void storeResponseFile(const ResponseCacheSettings& settings, const std::string& file, const std::string& url,
                       const std::string& body) {
  if (url.size() + 1 + body.size() > settings.capBytes) return;  // would evict everything else
  std::error_code ec;
  fs::create_directories(fs::path(file).parent_path(), ec);
  // Written aside then renamed: a reader (another thread or process) sees a whole response or none.
  static std::atomic<unsigned> counter{0};
  const std::string tmp = file + ".tmp" + std::to_string(std::hash<std::thread::id>()(std::this_thread::get_id())) +
                          "-" + std::to_string(counter++);
  {
    std::ofstream out(tmp, std::ios::binary);
    out << url << '\n';
    out.write(body.data(), std::streamsize(body.size()));
    if (!out) {
      out.close();
      fs::remove(tmp, ec);
      static std::once_flag warned;
      std::call_once(warned, [&] {
        log::warn(settings.folder + ": cannot write the response cache (responses are fetched each time)");
      });
      return;
    }
  }
  fs::rename(tmp, file, ec);
  if (ec) fs::remove(tmp, ec);
  trimResponseCache(cacheFoldersOf(settings), settings.capBytes);
}

}  // namespace

std::optional<std::string> readCachedResponse(const ResponseCacheSettings& settings, const std::string& key,
                                              std::uint64_t maxBytes) {
  if (settings.folder.empty()) return std::nullopt;
  return cachedResponseFile(responseCacheFile(settings.folder, key), key, maxBytes);
}

void writeCachedResponse(const ResponseCacheSettings& settings, const std::string& key, const std::string& body) {
  if (settings.folder.empty()) return;
  storeResponseFile(settings, responseCacheFile(settings.folder, key), key, body);
}

void countRemoteResponse(bool fromCache, std::uint64_t bytes) { countResponse(fromCache, bytes); }

void enableRemoteReading() {
  gdal::ensureRegistered();  // sets kHttpDefaults too
  setRemoteReader(&readRemoteForUtil);
}

std::string cacheFolder() {
  const auto env = [](const char* key) -> std::string {
    const char* v = std::getenv(key);
    return v && *v ? std::string(v) : std::string();
  };
  if (std::string d = env("HV_CACHE_DIR"); !d.empty()) return d;
  if (std::string d = env("XDG_CACHE_HOME"); !d.empty()) return d + "/histoview";
  if (std::string d = env("HOME"); !d.empty()) return d + "/.cache/histoview";
  return {};
}

ResponseCacheSettings responseCacheSettings() {
  ResponseCacheSettings s;
  if (const std::string off = envValue("HV_NO_CACHE"); !off.empty() && off != "0") return s;
  const std::string folder = cacheFolder();
  if (folder.empty()) return s;
  double mib = double(kDefaultResponseCacheMiB);
  if (const std::string cap = envValue("HV_CACHE_MAX_MB"); !cap.empty()) {
    char* end = nullptr;
    const double v = std::strtod(cap.c_str(), &end);
    if (end && *end == '\0' && end != cap.c_str() && std::isfinite(v) && v >= 0.0 && v <= double(1ull << 40)) {
      mib = v;
    } else {
      static std::once_flag warned;
      std::call_once(warned, [&] {
        log::warn("HV_CACHE_MAX_MB: expected a size in MiB, got '" + cap + "' (the default " +
                  std::to_string(kDefaultResponseCacheMiB) + " MiB is used)");
      });
    }
  }
  const auto capBytes = static_cast<std::uint64_t>(std::llround(mib * double(1 << 20)));
  if (capBytes == 0) return s;
  s.folder = folder + "/responses";
  s.tileFolder = folder + "/gdal-wms";
  s.capBytes = capBytes;
  return s;
}

std::string responseCacheFile(const std::string& folder, const std::string& url) {
  // FNV-1a, 64 bits: a file name, not a security boundary (the URL in the file decides a hit).
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char c : url) h = (h ^ c) * 1099511628211ull;
  char name[32];
  std::snprintf(name, sizeof name, "%016llx", static_cast<unsigned long long>(h));
  return folder + "/" + name;
}

std::uint64_t trimResponseCache(const std::string& folder, std::uint64_t capBytes) {
  return trimResponseCache(std::vector<std::string>{folder}, capBytes);
}

std::uint64_t trimResponseCache(const std::vector<std::string>& folders, std::uint64_t capBytes) {
  struct Entry {
    fs::file_time_type time;
    std::uint64_t bytes;
    fs::path path;
  };
  std::vector<Entry> entries;
  std::uint64_t total = 0;
  for (const std::string& folder : folders) {
    std::error_code ec;
    // Recursive: GDAL's tile cache keeps its files in sub-folders.
    for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
      std::error_code e;
      if (!it->is_regular_file(e) || it->path().filename().string().find(".tmp") != std::string::npos) continue;
      const std::uint64_t bytes = it->file_size(e);
      if (e) continue;
      const fs::file_time_type time = it->last_write_time(e);
      if (e) continue;
      entries.push_back({time, bytes, it->path()});
      total += bytes;
    }
  }
  if (total <= capBytes) return total;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.time < b.time; });
  for (const Entry& e : entries) {
    if (total <= capBytes) break;
    std::error_code r;
    if (fs::remove(e.path, r)) total -= e.bytes;
  }
  return total;
}

RemoteFetchCounts remoteFetchCounts() {
  std::lock_guard lock(gCountsMutex);
  return gCounts;
}

std::string readRemote(const std::string& url, std::uint64_t maxBytes, const std::string& what, RemoteCache cache) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  if (startsWithNoCase(url, "http://") || startsWithNoCase(url, "https://")) {
    const ResponseCacheSettings settings =
        cache == RemoteCache::Yes ? responseCacheSettings() : ResponseCacheSettings{};
    if (settings.folder.empty()) return readHttp(url, maxBytes, what);
    const std::string file = responseCacheFile(settings.folder, url);
    if (std::optional<std::string> hit = cachedResponseFile(file, url, maxBytes)) {
      log::debug(url + ": from the response cache " + file);
      countResponse(true, hit->size());
      return std::move(*hit);
    }
    std::string body = readHttp(url, maxBytes, what);
    storeResponseFile(settings, file, url, body);
    return body;
  }
  if (startsWithNoCase(url, "/vsi")) return readVsi(url, maxBytes, what);
  throw InputError(inputMessage(url, what,
                                "a GDAL connection string, which only the terrain (rasters) and buildings "
                                "(vector layers) sources open; this input reads a file or an http(s):// URL"));
}

}  // namespace hv
