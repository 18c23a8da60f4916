// PLY point reader on files written here: ASCII and both binary byte orders, optional fields,
// elements and list properties to skip, the writer round trip, and broken files.
#include "hv/io/native/ply_points.h"
#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>

namespace hv {
namespace {

PointCloud parse(const std::string& bytes) {
  return parsePlyPoints(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(), "test.ply");
}

TEST(PlyPoints, AsciiWithFacesBeforeAndAfterAndListsInsideVertices) {
  const std::string text =
      "ply\r\nformat ascii 1.0\r\ncomment crs EPSG:2154\r\n"
      "element camera 1\nproperty list uchar float values\nproperty int id\n"
      "element vertex 2\nproperty float x\nproperty float y\nproperty double z\n"
      "property list uchar int tags\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\n"
      "property float scalar_intensity\nproperty int scalar_classification\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "3 1.5 2.5 3.5 7\n"
      "1 2 3 2 9 9 255 0 128 12.4 6\n"
      "-1e2 0.5 651000.25 0 1 2 3 70000.0 300\n"
      "3 0 1 1\n";
  const PointCloud c = parse(text);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c.crs, "EPSG:2154");
  EXPECT_EQ(c.positions[0], glm::dvec3(1, 2, 3));
  EXPECT_EQ(c.positions[1], glm::dvec3(-100, 0.5, 651000.25));
  ASSERT_TRUE(c.fields().rgb && c.fields().intensity && c.fields().classification);
  EXPECT_FALSE(c.fields().normals);
  EXPECT_EQ(c.rgb[0], glm::u16vec3(65535, 0, 128 * 257));
  EXPECT_EQ(c.intensity[0], 12);
  EXPECT_EQ(c.intensity[1], 65535);  // clamped
  EXPECT_EQ(c.classification[0], 6);
  EXPECT_EQ(c.classification[1], 255);
}

// Binary: a face element before the vertices, ushort colours, normals.
std::string binaryFile(bool bigEndian) {
  std::string h = std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                  " 1.0\nelement face 2\nproperty list uchar int vertex_indices\n"
                  "element vertex 3\nproperty double x\nproperty double y\nproperty float z\n"
                  "property float nx\nproperty float ny\nproperty float nz\n"
                  "property ushort red\nproperty ushort green\nproperty ushort blue\nproperty short extra\n"
                  "end_header\n";
  auto put = [&](auto v) {
    char b[sizeof(v)];
    std::memcpy(b, &v, sizeof(v));
    if (bigEndian) std::reverse(b, b + sizeof(v));
    h.append(b, sizeof(v));
  };
  put(std::uint8_t(3)), put(0), put(1), put(2);
  put(std::uint8_t(1)), put(2);
  for (int i = 0; i < 3; ++i) {
    put(651000.0 + i), put(6862000.5), put(float(40 + i));
    put(0.0f), put(0.0f), put(1.0f);
    put(std::uint16_t(100 * i)), put(std::uint16_t(200)), put(std::uint16_t(300));
    put(std::int16_t(-1));
  }
  return h;
}

TEST(PlyPoints, BinaryBothByteOrders) {
  for (bool be : {false, true}) {
    SCOPED_TRACE(be ? "big endian" : "little endian");
    const PointCloud c = parse(binaryFile(be));
    ASSERT_EQ(c.size(), 3u);
    EXPECT_EQ(c.positions[2], glm::dvec3(651002.0, 6862000.5, 42.0));
    ASSERT_TRUE(c.fields().normals);
    EXPECT_EQ(c.normals[1], glm::vec3(0, 0, 1));
    EXPECT_EQ(c.rgb[2], glm::u16vec3(200, 200, 300));
    EXPECT_FALSE(c.fields().intensity);
  }
}

TEST(PlyPoints, WriterRoundTrip) {
  PointCloud in;
  in.crs = "EPSG:2154";
  in.resize(20, {.intensity = true, .classification = true, .rgb = true, .normals = true});
  for (std::size_t i = 0; i < in.size(); ++i) {
    in.positions[i] = {651000.123456 + double(i), 6862000.0, 38.25};
    in.normals[i] = glm::normalize(glm::vec3(1.0f, float(i), 2.0f));
    in.rgb[i] = glm::u16vec3(std::uint16_t(257 * i), 0, 65535);
    in.intensity[i] = std::uint16_t(i * 3);
    in.classification[i] = std::uint8_t(i);
  }
  const PointCloud out = parse(plyPointBytes(in));
  ASSERT_EQ(out.size(), in.size());
  EXPECT_EQ(out.crs, in.crs);
  EXPECT_EQ(out.positions, in.positions);  // doubles: exact
  EXPECT_EQ(out.normals, in.normals);
  EXPECT_EQ(out.rgb, in.rgb);  // multiples of 257 survive the 8-bit file
  EXPECT_EQ(out.intensity, in.intensity);
  EXPECT_EQ(out.classification, in.classification);
}

void expectError(const std::string& bytes, const std::string& what) {
  try {
    parse(bytes);
    ADD_FAILURE() << "no error, expected one mentioning " << what;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("test.ply"), std::string::npos) << e.what();
  }
}

TEST(PlyPoints, BrokenFilesAreInputErrors) {
  const std::string good = binaryFile(false);
  ASSERT_NO_THROW(parse(good));
  expectError("", "magic");
  expectError("ply\nformat ascii 1.0\n", "end_header");
  expectError("ply\nelement vertex 1\nproperty float x\nend_header\n", "format");
  expectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n",
              "x, y and z");
  expectError("ply\nformat ascii 1.0\nelement face 1\nproperty float q\nend_header\n1\n", "vertex");
  expectError("ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\n"
              "end_header\n1 2 3\n4 5\n",
              "truncated");
  expectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
              "end_header\n1 nan 3\n",
              "finite");
  expectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
              "end_header\n1 two 3\n",
              "expected a number");
  expectError("ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\nproperty float y\n"
              "property float z\nend_header\n",
              "truncated");
  expectError("ply\nformat ascii 1.0\nelement vertex -1\nend_header\n", "count");
  expectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n", "property type");
  expectError(good.substr(0, good.size() - 3), "element vertex");
  {
    std::string bad = good;  // the first face's list length 3 -> 250: past the end
    bad[bad.find("end_header\n") + 11] = char(250);
    expectError(bad, "element face");
  }
}

}  // namespace
}  // namespace hv
