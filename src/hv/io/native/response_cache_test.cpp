// The response cache of photographs, masks and IIIF descriptions fetched by URL
// (hv/io/native/remote.h, docs/services.md "Cache"): its settings from the environment, its file
// names, and the least-recently-used trimming under the size cap. The fetching itself is tested
// against real servers by tests/iiif_test.sh.
#include "hv/io/native/remote.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

namespace hv {
namespace {

namespace fs = std::filesystem;

// Sets (or unsets) an environment variable for the scope, restoring it after.
class ScopedEnv {
 public:
  ScopedEnv(const char* key, const char* value) : key_(key) {
    if (const char* old = std::getenv(key)) old_ = old;
    value ? ::setenv(key, value, 1) : ::unsetenv(key);
  }
  ~ScopedEnv() { old_ ? ::setenv(key_, old_->c_str(), 1) : ::unsetenv(key_); }
  ScopedEnv(const ScopedEnv&) = delete;
  ScopedEnv& operator=(const ScopedEnv&) = delete;

 private:
  const char* key_;
  std::optional<std::string> old_;
};

class ResponseCache : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_response_cache_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A cached response of `bytes` bytes, last used `ageS` seconds ago.
  void entry(const std::string& name, std::size_t bytes, int ageS) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << std::string(bytes, 'x');
    fs::last_write_time(p, fs::file_time_type::clock::now() - std::chrono::seconds(ageS));
  }
  fs::path dir_;
};

TEST_F(ResponseCache, SettingsFromTheEnvironment) {
  ScopedEnv dir("HV_CACHE_DIR", dir_.c_str());
  {
    ScopedEnv off("HV_NO_CACHE", nullptr), cap("HV_CACHE_MAX_MB", nullptr);
    const ResponseCacheSettings s = responseCacheSettings();
    EXPECT_EQ(s.folder, dir_.string() + "/responses");
    EXPECT_EQ(s.capBytes, kDefaultResponseCacheMiB << 20);
  }
  {
    ScopedEnv cap("HV_CACHE_MAX_MB", "3");
    EXPECT_EQ(responseCacheSettings().capBytes, std::uint64_t(3) << 20);
  }
  {
    ScopedEnv cap("HV_CACHE_MAX_MB", "0.25");  // decimals: a quarter of a MiB
    const ResponseCacheSettings s = responseCacheSettings();
    EXPECT_EQ(s.capBytes, std::uint64_t(1) << 18);
    EXPECT_EQ(s.tileFolder, dir_.string() + "/gdal-wms");  // GDAL's tiles, under the same cap
  }
  {
    ScopedEnv cap("HV_CACHE_MAX_MB", "-1");  // refused: the default
    EXPECT_EQ(responseCacheSettings().capBytes, kDefaultResponseCacheMiB << 20);
  }
  {
    ScopedEnv cap("HV_CACHE_MAX_MB", "lots");  // refused with a warning: the default
    EXPECT_EQ(responseCacheSettings().capBytes, kDefaultResponseCacheMiB << 20);
  }
  {
    ScopedEnv cap("HV_CACHE_MAX_MB", "0");  // a cap of nothing: no cache
    EXPECT_EQ(responseCacheSettings().folder, "");
  }
  {
    ScopedEnv off("HV_NO_CACHE", "1");
    EXPECT_EQ(responseCacheSettings().folder, "");
  }
  {
    ScopedEnv off("HV_NO_CACHE", "0");  // "0" does not disable
    EXPECT_EQ(responseCacheSettings().folder, dir_.string() + "/responses");
  }
}

TEST_F(ResponseCache, OneFilePerUrl) {
  const std::string a = responseCacheFile("/c", "http://h/iiif?IIIF=a.tif/info.json");
  EXPECT_EQ(a, responseCacheFile("/c", "http://h/iiif?IIIF=a.tif/info.json"));
  EXPECT_NE(a, responseCacheFile("/c", "http://h/iiif?IIIF=b.tif/info.json"));
  EXPECT_EQ(a.rfind("/c/", 0), 0u);
  EXPECT_EQ(a.size(), 3u + 16u);  // 64-bit hash, hexadecimal
  // FNV-1a of the empty string is its offset basis.
  EXPECT_EQ(responseCacheFile("/c", ""), "/c/cbf29ce484222325");
}

TEST_F(ResponseCache, TrimsTheLeastRecentlyUsedFirst) {
  entry("old", 400, 300);
  entry("mid", 400, 200);
  entry("new", 400, 100);
  entry("x.tmp1-0", 5000, 1000);                             // a response being written: neither counted nor removed
  EXPECT_EQ(trimResponseCache(dir_.string(), 2000), 1200u);  // under the cap: nothing removed
  EXPECT_TRUE(fs::exists(dir_ / "old"));
  EXPECT_EQ(trimResponseCache(dir_.string(), 900), 800u);
  EXPECT_FALSE(fs::exists(dir_ / "old"));
  EXPECT_TRUE(fs::exists(dir_ / "mid"));
  EXPECT_TRUE(fs::exists(dir_ / "new"));
  EXPECT_TRUE(fs::exists(dir_ / "x.tmp1-0"));
  EXPECT_EQ(trimResponseCache(dir_.string(), 399), 0u);
  EXPECT_EQ(trimResponseCache((dir_ / "none").string(), 10), 0u);  // no folder yet
}

TEST_F(ResponseCache, OneCapOverTheResponsesAndGdalsTiles) {
  // GDAL's tile cache keeps files in sub-folders: trimmed with the responses, oldest first.
  fs::create_directories(dir_ / "responses");
  fs::create_directories(dir_ / "gdal-wms" / "a" / "b");
  entry("responses/r1", 300, 400);
  entry("gdal-wms/a/b/t1", 300, 300);
  entry("responses/r2", 300, 200);
  entry("gdal-wms/a/b/t2", 300, 100);
  const std::vector<std::string> both{(dir_ / "responses").string(), (dir_ / "gdal-wms").string()};
  EXPECT_EQ(trimResponseCache(both, 1200), 1200u);
  EXPECT_EQ(trimResponseCache(both, 700), 600u);
  EXPECT_FALSE(fs::exists(dir_ / "responses" / "r1"));
  EXPECT_FALSE(fs::exists(dir_ / "gdal-wms" / "a" / "b" / "t1"));
  EXPECT_TRUE(fs::exists(dir_ / "responses" / "r2"));
  EXPECT_TRUE(fs::exists(dir_ / "gdal-wms" / "a" / "b" / "t2"));
}

TEST_F(ResponseCache, StoresAndReadsByKeyUnderTheCap) {
  ResponseCacheSettings s;
  s.folder = (dir_ / "responses").string();
  s.capBytes = 1000;
  EXPECT_FALSE(readCachedResponse(s, "GDAL http://h/a", 1 << 20));
  writeCachedResponse(s, "GDAL http://h/a", "text/xml\n<a/>");
  EXPECT_EQ(readCachedResponse(s, "GDAL http://h/a", 1 << 20), std::optional<std::string>("text/xml\n<a/>"));
  EXPECT_FALSE(readCachedResponse(s, "http://h/a", 1 << 20));  // another key: readRemote's entry
  EXPECT_FALSE(readCachedResponse(s, "GDAL http://h/a", 4));   // over the reader's limit
  writeCachedResponse(s, "GDAL http://h/big", std::string(2000, 'x'));  // over the cap: not kept
  EXPECT_FALSE(readCachedResponse(s, "GDAL http://h/big", 1 << 20));
  EXPECT_TRUE(readCachedResponse(s, "GDAL http://h/a", 1 << 20));  // and it evicted nothing
  // A second response that does not fit beside the first evicts it (the least recently used: last
  // used a minute ago, so that the file system's coarse clock cannot order them the other way).
  fs::last_write_time(responseCacheFile(s.folder, "GDAL http://h/a"),
                      fs::file_time_type::clock::now() - std::chrono::seconds(60));
  writeCachedResponse(s, "GDAL http://h/b", std::string(980, 'y'));
  EXPECT_FALSE(readCachedResponse(s, "GDAL http://h/a", 1 << 20));
  EXPECT_TRUE(readCachedResponse(s, "GDAL http://h/b", 1 << 20));
  ResponseCacheSettings off;  // no folder: nothing read or written
  writeCachedResponse(off, "GDAL http://h/c", "x");
  EXPECT_FALSE(readCachedResponse(off, "GDAL http://h/c", 1 << 20));
}

}  // namespace
}  // namespace hv
