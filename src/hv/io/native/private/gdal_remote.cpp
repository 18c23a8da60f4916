#include <cpl_conv.h>
#include <cpl_http.h>
#include <cpl_string.h>
#include <cpl_vsi.h>

#include "hv/io/native/private/gdal_init.h"
#include "hv/io/native/remote.h"
#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"

#include <cstdlib>
#include <memory>
#include <mutex>

namespace hv {

namespace {

bool startsWithNoCase(const std::string& s, const char* prefix) { return STARTS_WITH_CI(s.c_str(), prefix); }

std::string sizeLimitText(std::uint64_t bytes) { return std::to_string(bytes) + " bytes"; }

std::string readHttp(const std::string& url, std::uint64_t maxBytes, const std::string& what) {
  const std::string maxSize = "MAX_FILE_SIZE=" + std::to_string(maxBytes);
  const char* const options[] = {maxSize.c_str(), nullptr};
  // CPLHTTPFetch takes its time-out and retries from the configuration (kHttpDefaults).
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

std::string readRemoteForUtil(const std::string& url, std::uint64_t maxBytes, const std::string& what) {
  return readRemote(url, maxBytes, what);
}

}  // namespace

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

std::string readRemote(const std::string& url, std::uint64_t maxBytes, const std::string& what) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  if (startsWithNoCase(url, "http://") || startsWithNoCase(url, "https://")) return readHttp(url, maxBytes, what);
  if (startsWithNoCase(url, "/vsi")) return readVsi(url, maxBytes, what);
  throw InputError(inputMessage(url, what,
                                "a GDAL connection string, which only the terrain (rasters) and buildings "
                                "(vector layers) sources open; this input reads a file or an http(s):// URL"));
}

}  // namespace hv
