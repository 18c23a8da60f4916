// The large demo city (DemoOptions::blocks): deterministic, its size as asked, its centre the same
// whatever the size, its DTM a tiled GeoTIFF with overviews on the fixed lattice, its footprints a
// GeoPackage with a spatial index; and the small city unchanged by it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "hv/demo/demo_city.h"
#include "hv/io/native/footprints.h"
#include "hv/io/native/raster.h"
#include "hv/util/diagnostics.h"

namespace hv::demo {
namespace {

namespace fs = std::filesystem;

fs::path freshDir(const std::string& name) {
  const fs::path p = fs::temp_directory_path() / ("hv_large_city_test_" + std::to_string(::getpid()) + "_" + name);
  fs::remove_all(p);
  fs::create_directories(p);
  return p;
}

std::string readBytes(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

// FNV-1a, 64 bits (Fowler, Noll, Vo): enough to tell two versions of a file apart.
std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ULL;
  return h;
}

std::map<std::string, std::string> readTree(const fs::path& root) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(root))
    if (e.is_regular_file()) out[fs::relative(e.path(), root).generic_string()] = readBytes(e.path());
  return out;
}

// A large city small enough for a test: the ground truth on the 3 x 3 blocks around the centre,
// cameras and lidar on the centre block's streets, few photographs, one ray per pixel.
DemoOptions largeOptions(int blocks) {
  DemoOptions o;
  o.blocks = blocks;
  o.photos = 6;
  o.views = 2;
  o.samplesPerAxis = 1;
  o.city.truthRadius = 1;
  o.city.surveyRadius = 0;
  return o;
}

// The small test city's files, hashed with the code as it was before large cities existed: the
// small city must not change (same options, same bytes); since then only its orthophoto was added
// (orthophoto.tif, named in scene.json). The figures hold for this platform's
// GDAL, zlib, libpng and Embree (Debian 12); another platform may need them recomputed, from the
// code of a commit where the small city is known to be right.
TEST(LargeCity, SmallCityUnchanged) {
  DemoOptions o;
  o.buildings = 8;
  o.photos = 6;
  o.views = 2;
  o.samplesPerAxis = 1;
  o.traffic.enabled = false;  // SUMO's files carry the date they were written (docs/traffic.md)
  const fs::path dir = freshDir("small");
  generate(o, dir.string());
  const std::map<std::string, std::uint64_t> expected = {
      {"buildings.geojson", 0x16cf04498a6b6181ULL}, {"cameras.json", 0xd05fc51301c6adf7ULL},
      {"dtm.tif", 0xb9719ce427865035ULL},           {"images/p0001.png", 0xd98d4f73cf8010f5ULL},
      {"images/p0002.png", 0x8941327f858e987eULL},  {"images/p0003.png", 0xee23c47a9a380ed8ULL},
      {"images/p0004.png", 0x4b9dace69a3aeaf3ULL},  {"images/p0005.png", 0xb087a55cfcb325beULL},
      {"images/p0006.png", 0x41e898d32d2439feULL},  {"masks/p0002.png", 0x2663787727becc63ULL},
      {"points.las", 0xff7ee0f9e9b439f1ULL},        {"points.ply", 0x7a428d1df1db616cULL},
      {"scene.json", 0x401d851dc8e16626ULL},        {"truth/v001.coverage.png", 0xa178b4bce4ab09c9ULL},
      {"truth/v001.png", 0x9bd7d873fd27e426ULL},    {"truth/v002.coverage.png", 0x384eb3e964dde824ULL},
      {"truth/v002.png", 0x4200d57f6a4dd415ULL},    {"views.json", 0x4d16b81cab4246a0ULL},
      {"orthophoto.tif", 0x84390d50c061ebc5ULL},
  };
  std::map<std::string, std::uint64_t> actual;
  for (const auto& [name, bytes] : readTree(dir)) actual[name] = fnv1a(bytes);
  EXPECT_EQ(actual.size(), expected.size());
  for (const auto& [name, h] : expected) {
    ASSERT_TRUE(actual.count(name)) << name << " is missing";
    EXPECT_EQ(actual[name], h) << name << " changed";
  }
  fs::remove_all(dir);
}

TEST(LargeCity, GridHasAboutTheBlocksAskedForAndIsRoughlySquare) {
  const CitySettings s;
  for (int n : {1, 9, 185, 1000, 18519}) {
    const BlockGrid g = blockGrid(s, n);
    const int blocks = g.nbx * g.nby;
    EXPECT_NEAR(blocks, n, std::max(1.0, 0.05 * n)) << n;
    const glm::dvec2 size = g.hi() - g.lo();
    EXPECT_NEAR(size.x / size.y, 1.0, n < 100 ? 0.6 : 0.1) << n;
    // Block (0, 0) is centred on the origin, whatever the size: the lattice is fixed.
    EXPECT_LE(g.i0, 0);
    EXPECT_GE(g.i0 + g.nbx - 1, 0);
    const glm::dvec2 c = g.blockCorner(0, 0) + 0.5 * glm::dvec2(g.blockW, g.blockD);
    EXPECT_NEAR(c.x, s.originXY.x, 1e-9);
    EXPECT_NEAR(c.y, s.originXY.y, 1e-9);
  }
  // 100k buildings: 18519 blocks x 6 lots x 90 % built, a city of 7-9 km a side.
  const BlockGrid big = blockGrid(s, 18519);
  EXPECT_GT(big.hi().x - big.lo().x, 7000.0);
  EXPECT_LT(big.hi().x - big.lo().x, 9000.0);
}

TEST(LargeCity, FootprintCountScalesWithBlocks) {
  DemoOptions o;
  for (int n : {9, 100, 1000}) {
    o.blocks = n;
    const BlockGrid g = blockGrid(o.city, n);
    std::size_t count = 0;
    std::set<std::string> ids;
    forEachFootprint(o, [&](const Footprint& fp) {
      ++count;
      ids.insert(fp.id);
      ASSERT_TRUE(fp.height.has_value());
      EXPECT_GE(*fp.height, o.city.minHeight);
      EXPECT_LE(*fp.height, o.city.maxHeight);
      for (const auto& ring : fp.rings)
        for (glm::dvec2 p : ring) {
          EXPECT_GT(p.x, g.lo().x);
          EXPECT_LT(p.x, g.hi().x);
          EXPECT_GT(p.y, g.lo().y);
          EXPECT_LT(p.y, g.hi().y);
        }
    });
    EXPECT_EQ(ids.size(), count) << "ids are unique";
    // Each of the 6 lots of a block is built with probability lotFill: binomial, 4 sigma.
    const double lots = 6.0 * g.nbx * g.nby, p = o.city.lotFill;
    EXPECT_NEAR(double(count), lots * p, 4.0 * std::sqrt(lots * p * (1.0 - p)) + 1.0) << n;
  }
}

struct TiffDirectory {
  std::uint32_t width = 0, height = 0, tileWidth = 0, tileHeight = 0, subfileType = 0;
};

// The image file directories of a classic little-endian TIFF, read by hand (TIFF 6.0, section 2).
std::vector<TiffDirectory> tiffDirectories(const std::string& b) {
  auto u16 = [&](std::size_t at) {
    return std::uint32_t(std::uint8_t(b[at])) | std::uint32_t(std::uint8_t(b[at + 1])) << 8;
  };
  auto u32 = [&](std::size_t at) { return u16(at) | u16(at + 2) << 16; };
  std::vector<TiffDirectory> out;
  if (b.size() < 8 || b.compare(0, 4, std::string("II*\0", 4)) != 0) return out;
  for (std::size_t at = u32(4); at != 0 && at + 2 <= b.size() && out.size() < 64;) {
    const std::uint32_t n = u16(at);
    TiffDirectory d;
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::size_t e = at + 2 + 12 * k;
      const std::uint32_t tag = u16(e), type = u16(e + 2);
      const std::uint32_t value = type == 3 ? u16(e + 8) : u32(e + 8);  // SHORT or LONG
      if (tag == 254) d.subfileType = value;
      if (tag == 256) d.width = value;
      if (tag == 257) d.height = value;
      if (tag == 322) d.tileWidth = value;
      if (tag == 323) d.tileHeight = value;
    }
    out.push_back(d);
    at = u32(at + 2 + 12 * n);
  }
  return out;
}

TEST(LargeCity, GeneratesDeterministicallyWithCogAndGeoPackage) {
  const DemoOptions o = largeOptions(9);
  const fs::path a = freshDir("large_a"), b = freshDir("large_b");
  const DemoSummary summary = generate(o, a.string());
  generate(o, b.string());
  const auto filesA = readTree(a), filesB = readTree(b);
  ASSERT_EQ(filesA.size(), filesB.size());
  for (const auto& [name, bytes] : filesA) {
    ASSERT_TRUE(filesB.count(name)) << name;
    EXPECT_TRUE(bytes == filesB.at(name)) << name << " differs between two runs";
  }
  EXPECT_TRUE(filesA.count("buildings.gpkg"));
  EXPECT_FALSE(filesA.count("buildings.geojson"));
  EXPECT_NE(filesA.at("scene.json").find("buildings.gpkg"), std::string::npos);
  EXPECT_EQ(summary.photos, 6);
  EXPECT_EQ(summary.views, 2);
  EXPECT_GT(summary.points, 10000u);  // the lidar scan of the central streets

  // The DTM: tiled 256 x 256, overviews halving down to at least 16 cells, read back by GDAL with
  // the lattice's georeferencing (4 m cells anchored at the city origin) and the terrain's values.
  const std::vector<TiffDirectory> dirs = tiffDirectories(filesA.at("dtm.tif"));
  ASSERT_GE(dirs.size(), 2u) << "no overview";
  const Heightfield dtm = readHeightfield((a / "dtm.tif").string());
  EXPECT_EQ(dirs[0].width, std::uint32_t(dtm.cols));
  EXPECT_EQ(dirs[0].height, std::uint32_t(dtm.rows));
  for (std::size_t k = 0; k < dirs.size(); ++k) {
    EXPECT_EQ(dirs[k].tileWidth, 256u) << k;
    EXPECT_EQ(dirs[k].tileHeight, 256u) << k;
    if (k == 0) continue;
    EXPECT_EQ(dirs[k].subfileType, 1u) << "overview " << k << " is a reduced-resolution image";
    EXPECT_EQ(dirs[k].width, (dirs[0].width + (1u << k) - 1) >> k) << k;
  }
  EXPECT_GE(std::max(dirs.back().width, dirs.back().height), 16u);
  EXPECT_EQ(dtm.cellX, 4.0);
  EXPECT_EQ(dtm.cellY, -4.0);
  EXPECT_NE(dtm.crs.find("2154"), std::string::npos) << dtm.crs;
  const double fx = (dtm.originX - o.city.originXY.x) / 4.0, fy = (dtm.originY - o.city.originXY.y) / 4.0;
  EXPECT_EQ(fx, std::round(fx)) << "DTM columns on the 4 m lattice";
  EXPECT_EQ(fy, std::round(fy)) << "DTM rows on the 4 m lattice";
  const BlockGrid g = blockGrid(o.city, o.blocks);
  EXPECT_LE(dtm.originX, g.lo().x - o.city.margin);
  EXPECT_GE(dtm.originX + dtm.cols * 4.0, g.hi().x + o.city.margin);
  EXPECT_GE(dtm.originY, g.hi().y + o.city.margin);
  EXPECT_LE(dtm.originY - dtm.rows * 4.0, g.lo().y - o.city.margin);
  const World world = buildWorld(o);
  for (int j = 0; j < dtm.rows; j += 7)
    for (int i = 0; i < dtm.cols; i += 5) {
      const glm::dvec2 p = dtm.samplePosition(i, j);
      ASSERT_NEAR(dtm.at(i, j), world.terrainZ(p.x, p.y), 1e-4) << i << ", " << j;
    }

  // The footprints: every one written, with the ground truth's ids and heights, and the R-tree.
  Diagnostics diag;
  const std::vector<Footprint> read = readFootprints((a / "buildings.gpkg").string(), FootprintFields{}, diag);
  std::size_t generated = 0;
  forEachFootprint(o, [&](const Footprint&) { ++generated; });
  EXPECT_EQ(read.size(), generated);
  EXPECT_EQ(std::size_t(summary.buildings), generated);
  EXPECT_NE(filesA.at("buildings.gpkg").find("rtree_buildings_geom"), std::string::npos) << "no spatial index";
  std::size_t matched = 0;
  for (const Building& bld : world.buildings)
    for (const Footprint& fp : read)
      if (fp.rings.size() == bld.rings.size() && fp.height && std::abs(*fp.height - bld.height) < 1e-9 &&
          std::abs(fp.rings[0][0].x - bld.rings[0][0].x) < 1e-6 &&
          std::abs(fp.rings[0][0].y - bld.rings[0][0].y) < 1e-6)
        ++matched;
  EXPECT_EQ(matched, world.buildings.size()) << "ground-truth buildings are footprints of the file";
  fs::remove_all(a);
  fs::remove_all(b);
}

// The centre of the city (its ground truth, so its photographs and views) does not depend on how
// large the city is, once the ground-truth zone fits in it: the benchmark compares cities of 1k and
// 100k buildings through the same photographs.
TEST(LargeCity, CentreIsTheSameWhateverTheSize) {
  const fs::path a = freshDir("centre_a"), b = freshDir("centre_b");
  generate(largeOptions(49), a.string());
  generate(largeOptions(100), b.string());
  const auto filesA = readTree(a), filesB = readTree(b);
  for (const auto& [name, bytes] : filesA) {
    // The whole city: they differ.
    if (name == "dtm.tif" || name == "buildings.gpkg" || name == "orthophoto.tif") continue;
    ASSERT_TRUE(filesB.count(name)) << name;
    const std::string& other = filesB.at(name);
    std::size_t at = 0;
    while (at < bytes.size() && at < other.size() && bytes[at] == other[at]) ++at;
    EXPECT_TRUE(bytes == other) << name << " differs between 49 and 100 blocks (sizes " << bytes.size() << ", "
                                << other.size() << ", first difference at byte " << at << ")";
  }
  EXPECT_LT(filesA.at("buildings.gpkg").size(), filesB.at("buildings.gpkg").size());
  fs::remove_all(a);
  fs::remove_all(b);
}

}  // namespace
}  // namespace hv::demo
