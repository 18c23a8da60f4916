// The requests GDAL's drivers send to services (WFS, OGC API - Features, WCS, the WMTS and WMS
// capabilities: everything that goes through CPLHTTPFetch), through histoview's response cache,
// and reported as progress while a source loads (docs/services.md, "Cache" and "Progress").
// Private: only .cpp files under io/native/private/ include it.
//
// GDAL lets an application answer CPLHTTPFetch itself (CPLHTTPSetFetchCallback, GDAL >= 3.2): the
// callback answers a GET it holds from the cache, and otherwise asks GDAL's own client (the
// callback stepping aside on that thread) and keeps a successful answer. A request with a body, a
// custom method or a streaming writer is left to GDAL as it is, and so are the ones readRemote
// sends (DirectFetch): its own rules say which of those are cached.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace hv::gdal {

// Installs the callback (once per process; gdal::ensureRegistered calls it).
void installServiceFetch();

// Holds GDAL's WMS/WMTS tile cache (when it is histoview's: GDAL_DEFAULT_WMS_CACHE_PATH not set by
// the user) and the responses under the cache's cap, least recently used first. GDAL's tile cache
// has a cap of its own (64 MiB, cleaned by GDAL after 2 minutes); called after a tiled raster is
// read, it makes histoview's cap hold at once.
void trimTileCache();

// While alive on a thread, the service requests sent from that thread are reported as progress
// (log::info, stderr): "loading buildings from WFS:http://…: tile 2 of 4: GetFeature, 95 KB (1000
// features so far)", "… from the cache". Nested scopes: the innermost reports.
class ServiceProgress {
 public:
  ServiceProgress(std::string what, std::string source);
  ~ServiceProgress();
  ServiceProgress(const ServiceProgress&) = delete;
  ServiceProgress& operator=(const ServiceProgress&) = delete;

  // The innermost scope of this thread, or nullptr.
  static ServiceProgress* current();
  // The tile being read: the k-th (from 1) of n (0: not by tile).
  void tile(std::size_t k, std::size_t n) { tileK_ = k, tileN_ = n; }
  void feature() { ++features_; }
  // A response arrived (from the server or the cache): one line of progress.
  void response(const std::string& url, std::uint64_t bytes, bool fromCache);
  std::size_t requests() const { return requests_; }

 private:
  std::string what_, source_;
  std::size_t tileK_ = 0, tileN_ = 0, requests_ = 0, features_ = 0;
  ServiceProgress* previous_;
};

// While alive on a thread, that thread's CPLHTTPFetch calls go to GDAL's client directly: neither
// cached nor reported (readRemote, which has its own cache rules).
class DirectFetch {
 public:
  DirectFetch();
  ~DirectFetch();
  DirectFetch(const DirectFetch&) = delete;
  DirectFetch& operator=(const DirectFetch&) = delete;

 private:
  bool previous_;
};

// What a request is called in the progress lines: its REQUEST= value (GetFeature, GetCoverage,
// …), else the last segment of its path (an OGC API "items"). Public for its test.
std::string requestName(const std::string& url);

// Whether a response body is an OGC exception report (MapServer, GeoServer and others answer
// errors with status 200 and one): never cached. Public for its test.
bool isExceptionReport(const std::string& body);

}  // namespace hv::gdal
