// The rule for scene.json source paths (docs/services.md, "Paths"): local paths that exist are
// local, whatever they look like; connection strings are handed on as they are; anything else is
// a local path relative to scene.json's folder.
#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

TEST(ConnectionString, GdalPrefixesAndUrls) {
  for (const char* s :
       {"WFS:http://127.0.0.1:8080/mapserv?TYPENAME=buildings", "WCS:http://h/wcs?COVERAGE=dtm", "WMTS:https://h/wmts",
        "WMS:http://h/wms", "OAPIF:http://h/ogcapi/collections/b", "PG:dbname=city", "/vsicurl/https://h/dtm.tif",
        "/vsizip/a.zip/b.shp", "http://h/cameras.json", "https://h/points.las", "GPKG:/data/a.gpkg:layer"})
    EXPECT_TRUE(isConnectionString(s)) << s;
  for (const char* s : {"dtm.tif", "./dtm.tif", "/data/dtm.tif", "C:/data/dtm.tif", "c:dtm.tif", "sub/WFS:x", ":x",
                        "1WFS:http://h", "", "dtm tif:x", "/vs/x"})
    EXPECT_FALSE(isConnectionString(s)) << s;
  EXPECT_FALSE(isConnectionString(std::string("WFS\0:http://h", 14)));
}

class SourcePaths : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_source_path_test_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(SourcePaths, RelativeLocalAbsoluteAndConnectionStrings) {
  const std::string dir = dir_.string();
  EXPECT_EQ(resolveSourcePath("dtm.tif", dir), (dir_ / "dtm.tif").string());  // need not exist
  EXPECT_EQ(resolveSourcePath("a/../dtm.tif", dir), (dir_ / "dtm.tif").string());
  EXPECT_EQ(resolveSourcePath("/abs/dtm.tif", dir), "/abs/dtm.tif");
  const std::string wfs = "WFS:http://127.0.0.1:1/mapserv?map=city&TYPENAME=buildings";
  EXPECT_EQ(resolveSourcePath(wfs, dir), wfs);  // not resolved against the folder, not normalised
  EXPECT_EQ(resolveSourcePath("http://h//a/../b.json", dir), "http://h//a/../b.json");
  EXPECT_TRUE(isRemoteSource(wfs));
  EXPECT_FALSE(isRemoteSource("dtm.tif"));

  // A local file whose name looks like a connection string is the local file.
  { std::ofstream(dir_ / "PG:city") << "x"; }
  EXPECT_EQ(resolveSourcePath("PG:city", dir), (dir_ / "PG:city").string());
  EXPECT_EQ(resolveSourcePath("PG:other", dir), "PG:other");
}

TEST_F(SourcePaths, RemoteSourceWithoutReaderNamesTheUrl) {
  setRemoteReader(nullptr);
  try {
    readTextFile("http://127.0.0.1:1/cameras.json", 1024, "cameras file");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("http://127.0.0.1:1/cameras.json"), std::string::npos) << e.what();
  }
}

RemoteCache gLastCache = RemoteCache::No;
std::string fakeReader(const std::string& path, std::uint64_t, const std::string&, RemoteCache cache) {
  gLastCache = cache;
  return "fetched " + path;
}

TEST_F(SourcePaths, RemoteSourceGoesThroughTheReader) {
  setRemoteReader(&fakeReader);
  EXPECT_EQ(readTextFile("https://h/x.json", 1024, "x"), "fetched https://h/x.json");
  const std::vector<std::uint8_t> bytes = readFileBytes("/vsicurl/http://h/p.las");
  EXPECT_EQ(std::string(bytes.begin(), bytes.end()), "fetched /vsicurl/http://h/p.las");
  EXPECT_EQ(gLastCache, RemoteCache::No);
  const std::vector<std::uint8_t> image = readInputBytes("https://h/a.jpg", 1024, "image", RemoteCache::Yes);
  EXPECT_EQ(std::string(image.begin(), image.end()), "fetched https://h/a.jpg");
  EXPECT_EQ(gLastCache, RemoteCache::Yes);
  setRemoteReader(nullptr);
}

TEST_F(SourcePaths, HttpUrls) {
  EXPECT_TRUE(isHttpUrl("http://h/a.jpg"));
  EXPECT_TRUE(isHttpUrl("HTTPS://h/a.jpg"));
  EXPECT_FALSE(isHttpUrl("/vsicurl/http://h/a.jpg"));
  EXPECT_FALSE(isHttpUrl("ftp://h/a.jpg"));
  EXPECT_FALSE(isHttpUrl("http:/h"));
  EXPECT_FALSE(isHttpUrl("img/http://x.jpg"));
}

}  // namespace
}  // namespace hv
