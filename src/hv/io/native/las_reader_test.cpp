// LAS reader and writer on files made here: hand-packed records (offsets typed from the ASPRS
// LAS 1.4 R15 tables, independently of the reader's layout table), writer round trips for every
// point format, and broken files that must give InputError naming the field.
#include "hv/io/native/las_reader.h"
#include "hv/io/native/las_writer.h"
#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

namespace hv {
namespace {

// A little-endian byte buffer written at explicit offsets.
struct Bytes {
  std::string b;
  explicit Bytes(std::size_t n) : b(n, '\0') {}
  template <typename T>
  void at(std::size_t off, T v) {
    if (b.size() < off + sizeof(T)) b.resize(off + sizeof(T), '\0');
    std::memcpy(b.data() + off, &v, sizeof(T));  // the test machines are little-endian
  }
  void text(std::size_t off, const char* s) { std::memcpy(b.data() + off, s, std::strlen(s)); }
};

PointCloud parse(const std::string& bytes, const std::string& name = "test.las") {
  return parseLas(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), name);
}

// LAS 1.2, point format 3 (34 bytes), two points, scale 0.01 / offset (1000, 2000, 10).
Bytes format3File() {
  Bytes f(227);
  f.text(0, "LASF");
  f.at<std::uint8_t>(24, 1);
  f.at<std::uint8_t>(25, 2);
  f.at<std::uint16_t>(94, 227);        // header size
  f.at<std::uint32_t>(96, 227);        // offset to point data
  f.at<std::uint32_t>(100, 0);         // VLRs
  f.at<std::uint8_t>(104, 3);          // point format
  f.at<std::uint16_t>(105, 34);        // record length
  f.at<std::uint32_t>(107, 2);         // legacy count
  f.at<double>(131, 0.01), f.at<double>(139, 0.01), f.at<double>(147, 0.01);
  f.at<double>(155, 1000.0), f.at<double>(163, 2000.0), f.at<double>(171, 10.0);
  for (int i = 0; i < 2; ++i) {
    const std::size_t r = 227 + 34 * std::size_t(i);
    f.at<std::int32_t>(r + 0, 12345 + i);
    f.at<std::int32_t>(r + 4, -500);
    f.at<std::int32_t>(r + 8, 250);
    f.at<std::uint16_t>(r + 12, std::uint16_t(300 + i));
    f.at<std::uint8_t>(r + 15, std::uint8_t(0x80 | (i ? 6 : 2)));  // withheld flag + class
    f.at<double>(r + 20, 1.5);                                     // GPS time
    f.at<std::uint16_t>(r + 28, 1000), f.at<std::uint16_t>(r + 30, 2000), f.at<std::uint16_t>(r + 32, 65535);
  }
  return f;
}

TEST(LasReader, Format3ScaleOffsetRgbAndClassFlags) {
  const PointCloud c = parse(format3File().b);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_NEAR(c.positions[0].x, 1000.0 + 123.45, 1e-9);
  EXPECT_NEAR(c.positions[1].x, 1000.0 + 123.46, 1e-9);
  EXPECT_NEAR(c.positions[0].y, 2000.0 - 5.0, 1e-9);
  EXPECT_NEAR(c.positions[0].z, 12.5, 1e-9);
  EXPECT_EQ(c.intensity[1], 301);
  EXPECT_EQ(c.classification[0], 2);  // the withheld bit is not part of the class
  EXPECT_EQ(c.classification[1], 6);
  ASSERT_TRUE(c.fields().rgb);
  EXPECT_EQ(c.rgb[0], glm::u16vec3(1000, 2000, 65535));
  EXPECT_FALSE(c.fields().normals);
  EXPECT_TRUE(c.crs.empty());
}

// Colours written as 8-bit values in the 16-bit fields (every channel under 256) are widened
// ×257; a file with one channel above 255 is left as it is (the test above).
TEST(LasReader, EightBitColoursInSixteenBitFieldsAreWidened) {
  Bytes f = format3File();
  for (int i = 0; i < 2; ++i) {
    const std::size_t r = 227 + 34 * std::size_t(i);
    f.at<std::uint16_t>(r + 28, 10), f.at<std::uint16_t>(r + 30, 0), f.at<std::uint16_t>(r + 32, std::uint16_t(255 - i));
  }
  const PointCloud c = parse(f.b);
  EXPECT_EQ(c.rgb[0], glm::u16vec3(2570, 0, 65535));
  EXPECT_EQ(c.rgb[1], glm::u16vec3(2570, 0, 254 * 257));
}

TEST(LasReader, Las14Format6ExtendedClassCount64ExtraBytesAndWkt) {
  const std::string wkt = "PROJCS[\"test\"]";
  const std::size_t vlr = 375, vlrLen = wkt.size() + 1, points = vlr + 54 + vlrLen, rec = 30 + 4;  // 4 extra bytes
  Bytes f(points);
  f.text(0, "LASF");
  f.at<std::uint8_t>(24, 1);
  f.at<std::uint8_t>(25, 4);
  f.at<std::uint16_t>(6, 16);  // global encoding: WKT
  f.at<std::uint16_t>(94, 375);
  f.at<std::uint32_t>(96, std::uint32_t(points));
  f.at<std::uint32_t>(100, 1);
  f.at<std::uint8_t>(104, 6);
  f.at<std::uint16_t>(105, std::uint16_t(rec));
  f.at<std::uint32_t>(107, 0);  // legacy count 0 for formats 6-10
  f.at<std::uint64_t>(247, 3);  // 64-bit count
  for (int k = 0; k < 3; ++k) f.at<double>(131 + 8 * std::size_t(k), 0.001);
  f.text(vlr + 2, "LASF_Projection");
  f.at<std::uint16_t>(vlr + 18, 2112);
  f.at<std::uint16_t>(vlr + 20, std::uint16_t(vlrLen));
  f.text(vlr + 54, wkt.c_str());
  for (int i = 0; i < 3; ++i) {
    const std::size_t r = points + rec * std::size_t(i);
    f.at<std::int32_t>(r + 0, 1000 * i);
    f.at<std::int32_t>(r + 4, 2000);
    f.at<std::int32_t>(r + 8, -3000);
    f.at<std::uint16_t>(r + 12, 7);
    f.at<std::uint8_t>(r + 15, 0xFF);                   // flags byte: not the class
    f.at<std::uint8_t>(r + 16, std::uint8_t(40 + i));  // extended classes above 31
    f.at<std::uint32_t>(r + 30, 0xDEADBEEF);            // extra bytes
  }
  const PointCloud c = parse(f.b);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.crs, wkt);
  EXPECT_FALSE(c.fields().rgb);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(c.positions[size_t(i)].x, i, 1e-12);
    EXPECT_NEAR(c.positions[size_t(i)].z, -3.0, 1e-12);
    EXPECT_EQ(c.classification[size_t(i)], 40 + i);
    EXPECT_EQ(c.intensity[size_t(i)], 7);
  }
}

PointCloud sampleCloud(bool rgb, int maxClass) {
  PointCloud c;
  c.crs = "EPSG:2154";
  c.resize(50, {.intensity = true, .classification = true, .rgb = rgb});
  for (std::size_t i = 0; i < c.size(); ++i) {
    c.positions[i] = {651000.0 + 0.123 * double(i), 6862000.0 - 0.5 * double(i), 35.0 + 0.001 * double(i)};
    c.intensity[i] = std::uint16_t(100 * i);
    c.classification[i] = std::uint8_t(i % std::size_t(maxClass + 1));
    if (rgb) c.rgb[i] = {std::uint16_t(i), std::uint16_t(1000 + i), std::uint16_t(65535 - i)};
  }
  return c;
}

TEST(LasWriter, RoundTripsEveryPointFormat) {
  for (int format = 0; format <= 10; ++format) {
    for (int minor : {2, 4}) {
      if (format >= 6 && minor == 2) continue;
      SCOPED_TRACE("format " + std::to_string(format) + ", LAS 1." + std::to_string(minor));
      const bool formatHasRgb = format == 2 || format == 3 || format == 5 || format == 7 || format == 8 || format == 10;
      const PointCloud in = sampleCloud(true, format >= 6 ? 200 : 31);
      const PointCloud out = parse(lasBytes(in, {.minorVersion = minor, .pointFormat = format}));
      ASSERT_EQ(out.size(), in.size());
      EXPECT_EQ(out.crs, "EPSG:2154");
      EXPECT_EQ(out.fields().rgb, formatHasRgb);
      for (std::size_t i = 0; i < in.size(); ++i) {
        EXPECT_NEAR(glm::length(out.positions[i] - in.positions[i]), 0.0, 1e-3);
        EXPECT_EQ(out.intensity[i], in.intensity[i]);
        EXPECT_EQ(out.classification[i], in.classification[i]);
        if (formatHasRgb) EXPECT_EQ(out.rgb[i], in.rgb[i]);
      }
    }
  }
}

TEST(LasWriter, WktCrsAndImpossibleRequests) {
  PointCloud c = sampleCloud(false, 31);
  c.crs = "PROJCS[\"Lambert\"]";
  EXPECT_EQ(parse(lasBytes(c, {.minorVersion = 4})).crs, c.crs);
  EXPECT_THROW(lasBytes(c, {.minorVersion = 2, .pointFormat = 6}), std::invalid_argument);
  c.classification[3] = 40;
  EXPECT_THROW(lasBytes(c, {.pointFormat = 1}), std::invalid_argument);
  EXPECT_NO_THROW(lasBytes(c, {.minorVersion = 4, .pointFormat = 6}));
  c.positions[0].x = 1e12;  // does not fit in int32 at millimetres
  EXPECT_THROW(lasBytes(c, {.minorVersion = 4, .pointFormat = 6}), std::invalid_argument);
}

// The error must name the field and say what was expected.
void expectError(const std::string& bytes, const std::string& fieldAndWhat) {
  try {
    parse(bytes, "bad.las");
    ADD_FAILURE() << "no error, expected one mentioning " << fieldAndWhat;
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("bad.las"), std::string::npos) << m;
    EXPECT_NE(m.find(fieldAndWhat), std::string::npos) << m;
  }
}

TEST(LasReader, BrokenFilesAreInputErrors) {
  const std::string good = format3File().b;
  ASSERT_NO_THROW(parse(good));
  expectError("", "file signature");
  expectError("LASF", "public header block");
  expectError(good.substr(0, 200), "public header block");
  expectError(good.substr(0, good.size() - 1), "legacy number of point records");  // truncated points
  {
    Bytes f = format3File();
    f.at<std::uint8_t>(104, 3 | 0x80);  // LASzip's compressed bit
    expectError(f.b, "LAZ");
    f.at<std::uint8_t>(104, 11);
    expectError(f.b, "point data format");
  }
  {
    Bytes f = format3File();
    f.at<std::uint8_t>(104, 6);  // a 1.4 format in a 1.2 file
    expectError(f.b, "needs LAS 1.4");
  }
  {
    Bytes f = format3File();
    f.at<std::uint16_t>(94, 100);
    expectError(f.b, "header size");
    f.at<std::uint16_t>(94, 227);
    f.at<std::uint32_t>(96, 1u << 30);
    expectError(f.b, "offset to point data");
    f.at<std::uint32_t>(96, 200);
    expectError(f.b, "offset to point data");
  }
  {
    Bytes f = format3File();
    f.at<std::uint16_t>(105, 20);
    expectError(f.b, "point data record length");
    f.at<std::uint16_t>(105, 34);
    f.at<std::uint32_t>(107, 0xFFFFFFFFu);
    expectError(f.b, "legacy number of point records");
    f.at<std::uint32_t>(107, 2);
    f.at<double>(131, 0.0);
    expectError(f.b, "x scale factor");
  }
  {
    Bytes f = format3File();
    f.at<std::uint32_t>(100, 1);  // a VLR where the points start
    expectError(f.b, "variable length record 1 of 1");
    f.at<std::uint8_t>(24, 2);
    expectError(f.b, "version");
  }
}

TEST(LasReader, LazFilesAreRefusedWithAdvice) {
  const auto path = std::filesystem::temp_directory_path() / "hv-las-test-cloud.laz";
  {
    std::ofstream(path, std::ios::binary) << format3File().b;
  }
  try {
    readLas(path.string());
    ADD_FAILURE() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pdal translate"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
  EXPECT_THROW(readLas("/nonexistent/cloud.las"), InputError);
}

}  // namespace
}  // namespace hv
