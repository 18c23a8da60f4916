#include "hv/io/tiles3d.h"

#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <set>
#include <tuple>

namespace hv {
namespace {

template <typename T>
void put(std::string& s, const T& v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

// A pnts tile by hand (3D Tiles 1.0, Point Cloud: a 28-byte header, then the feature table's JSON
// and binary body, then the batch table's).
std::string pnts(std::string json, const std::string& binary, const std::string& batch = "") {
  while ((28 + json.size()) % 8) json.push_back(' ');
  std::string out = "pnts";
  put(out, std::uint32_t(1));
  put(out, std::uint32_t(28 + json.size() + binary.size() + batch.size()));
  put(out, std::uint32_t(json.size()));
  put(out, std::uint32_t(binary.size()));
  put(out, std::uint32_t(batch.size()));
  put(out, std::uint32_t(0));
  return out + json + binary + batch;
}

std::string message(const std::string& bytes) {
  try {
    parsePnts(bytes, "http://h/t/r0.pnts");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Pnts, QuantizedPositionsRelativeToCentre) {
  std::string bin;
  for (std::uint16_t q : {0, 0, 0, 65535, 65535, 65535, 32768, 16384, 0}) put(bin, q);
  const std::string bytes =
      pnts(R"({"POINTS_LENGTH":3,"RTC_CENTER":[1000,2000,3000],"QUANTIZED_VOLUME_OFFSET":[-10,-20,-30],)"
           R"("QUANTIZED_VOLUME_SCALE":[100,200,300],"POSITION_QUANTIZED":{"byteOffset":0}})",
           bin);
  const PntsTile t = parsePnts(bytes, "t.pnts");
  ASSERT_EQ(t.points.size(), 3u);
  // centre + offset + q * scale / 65535
  EXPECT_NEAR(t.points.positions[0].x, 990.0, 1e-9);
  EXPECT_NEAR(t.points.positions[0].y, 1980.0, 1e-9);
  EXPECT_NEAR(t.points.positions[0].z, 2970.0, 1e-9);
  EXPECT_NEAR(t.points.positions[1].x, 1090.0, 1e-9);
  EXPECT_NEAR(t.points.positions[1].y, 2180.0, 1e-9);
  EXPECT_NEAR(t.points.positions[1].z, 3270.0, 1e-9);
  EXPECT_NEAR(t.points.positions[2].x, 990.0 + 50.000762951094835, 1e-9);
  EXPECT_NEAR(t.points.positions[2].y, 1980.0 + 50.000762951094835, 1e-9);
  EXPECT_NEAR(t.points.positions[2].z, 2970.0, 1e-9);
  EXPECT_TRUE(t.points.rgb.empty());
  EXPECT_TRUE(t.points.normals.empty());
}

TEST(Pnts, GlobalsFromTheBinaryBody) {
  std::string bin;
  for (float f : {5.0f, 6.0f, 7.0f}) put(bin, f);    // RTC_CENTER at byte 0
  for (float f : {1.5f, -2.0f, 0.25f}) put(bin, f);  // POSITION at byte 12
  const PntsTile t = parsePnts(
      pnts(R"({"POINTS_LENGTH":1,"RTC_CENTER":{"byteOffset":0},"POSITION":{"byteOffset":12}})", bin), "t.pnts");
  ASSERT_EQ(t.points.size(), 1u);
  EXPECT_EQ(t.points.positions[0], glm::dvec3(6.5, 4.0, 7.25));
}

TEST(Pnts, OctahedralNormals) {
  // Values of the specification's decoding worked by hand: (255,128) folds to +x (just below the
  // equator), (191,64) lies in the upper half, (64,200) folds, (255,0) is -z.
  std::string bin;
  for (int i = 0; i < 4; ++i) put(bin, float(i)), put(bin, 0.0f), put(bin, 0.0f);
  for (std::uint8_t b : {255, 128, 191, 64, 64, 200, 255, 0}) put(bin, b);
  const PntsTile t = parsePnts(
      pnts(R"({"POINTS_LENGTH":4,"POSITION":{"byteOffset":0},"NORMAL_OCT16P":{"byteOffset":48}})", bin), "t.pnts");
  ASSERT_EQ(t.points.normals.size(), 4u);
  const glm::dvec3 want[] = {{0.9999922500745928, 0.0, -0.003936977362498383},
                             {0.7070958212643368, -0.7070958212643368, 0.005567683632002632},
                             {-0.648485264833694, 0.7546010354428438, -0.10022045001975269},
                             {0.0, 0.0, -1.0}};
  for (int i = 0; i < 4; ++i)
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(t.points.normals[std::size_t(i)][a], want[i][a], 1e-6) << i << " " << a;
  // Encoding then decoding comes back within the 8-bit grid.
  for (const glm::vec3 n : {glm::vec3(0, 0, 1), glm::vec3(0.6f, -0.8f, 0), glm::vec3(-0.48f, 0.6f, -0.64f)}) {
    std::uint8_t x, y;
    octEncode16P(n, x, y);
    EXPECT_GT(glm::dot(octDecode16P(x, y), n), 0.9998f);
  }
}

TEST(Pnts, ColoursAndFloatNormals) {
  std::string bin;
  for (int i = 0; i < 4; ++i) put(bin, float(i)), put(bin, 1.0f), put(bin, 2.0f);      // 0..47
  for (std::uint16_t c : {0xF800, 0x07E0, 0x001F, 0x8410}) put(bin, c);                // 48..55
  for (std::uint8_t c : {255, 0, 0, 0, 128, 0, 0, 0, 1, 10, 20, 30}) put(bin, c);      // 56..67
  for (int i = 0; i < 4; ++i) put(bin, 0.0f), put(bin, 0.0f), put(bin, float(2 + i));  // 68..115
  const PntsTile rgb565 = parsePnts(
      pnts(R"({"POINTS_LENGTH":4,"POSITION":{"byteOffset":0},"RGB565":{"byteOffset":48},"NORMAL":{"byteOffset":68}})",
           bin),
      "t.pnts");
  ASSERT_EQ(rgb565.points.rgb.size(), 4u);
  EXPECT_EQ(rgb565.points.rgb[0], glm::u16vec3(65535, 0, 0));
  EXPECT_EQ(rgb565.points.rgb[1], glm::u16vec3(0, 65535, 0));
  EXPECT_EQ(rgb565.points.rgb[2], glm::u16vec3(0, 0, 65535));
  EXPECT_EQ(rgb565.points.rgb[3], glm::u16vec3(33825, 33288, 33825));  // round(16/31, 32/63 x 65535)
  EXPECT_EQ(rgb565.points.normals[3], glm::vec3(0, 0, 1));             // normalised
  // RGB wins over RGB565 (the specification's precedence), 8 bits scaled by 257 as in LAS.
  const PntsTile rgb = parsePnts(
      pnts(R"({"POINTS_LENGTH":4,"POSITION":{"byteOffset":0},"RGB565":{"byteOffset":48},"RGB":{"byteOffset":56}})",
           bin),
      "t.pnts");
  EXPECT_EQ(rgb.points.rgb[0], glm::u16vec3(65535, 0, 0));
  EXPECT_EQ(rgb.points.rgb[1], glm::u16vec3(0, 128 * 257, 0));
  EXPECT_EQ(rgb.points.rgb[3], glm::u16vec3(10 * 257, 20 * 257, 30 * 257));
}

TEST(Pnts, BatchTableIsNamedAsIgnored) {
  std::string bin;
  put(bin, 1.0f), put(bin, 2.0f), put(bin, 3.0f);
  put(bin, std::uint8_t(0));
  while (bin.size() % 8) bin.push_back('\0');
  const PntsTile t = parsePnts(
      pnts(
          R"({"POINTS_LENGTH":1,"POSITION":{"byteOffset":0},"BATCH_ID":{"byteOffset":12,"componentType":"UNSIGNED_BYTE"},"BATCH_LENGTH":1,"WHATEVER":1})",
          bin, R"({"height":[3]}   )"),
      "t.pnts");
  ASSERT_EQ(t.notes.size(), 2u);
  EXPECT_NE(t.notes[0].find("ignored: WHATEVER"), std::string::npos);
  EXPECT_NE(t.notes[1].find("batchTable: ignored"), std::string::npos);
}

TEST(Pnts, ClassificationFromThePerPointBatchTable) {
  // Two points; the batch table (no BATCH_ID, so one entry a point) carries the ASPRS classes.
  std::string bin;
  for (float v : {1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f}) put(bin, v);
  const std::string ftJson = R"({"POINTS_LENGTH":2,"POSITION":{"byteOffset":0}})";
  auto tile = [&](std::string batchJson, const std::string& batchBin) {
    std::string t = pnts(ftJson, bin);  // 8-aligned: the batch table follows
    while ((t.size() + batchJson.size()) % 8) batchJson.push_back(' ');
    std::string out = t + batchJson + batchBin;
    const std::uint32_t total = std::uint32_t(out.size()), jl = std::uint32_t(batchJson.size()),
                        bl = std::uint32_t(batchBin.size());
    std::memcpy(out.data() + 8, &total, 4);
    std::memcpy(out.data() + 20, &jl, 4);
    std::memcpy(out.data() + 24, &bl, 4);
    return out;
  };
  const PntsTile bytes =
      parsePnts(tile(R"({"Classification":{"byteOffset":8,"componentType":"UNSIGNED_BYTE","type":"SCALAR"}})",
                     std::string("\0\0\0\0\0\0\0\0\x02\x06\0\0\0\0\0\0", 16)),
                "t.pnts");
  EXPECT_TRUE(bytes.notes.empty()) << bytes.notes[0];
  EXPECT_EQ(bytes.points.classification, (std::vector<std::uint8_t>{2, 6}));
  EXPECT_TRUE(bytes.points.consistent());
  std::string shorts;
  put(shorts, std::uint16_t(5)), put(shorts, std::uint16_t(9)), put(shorts, std::uint32_t(0));
  const PntsTile wide = parsePnts(
      tile(R"({"Classification":{"byteOffset":0,"componentType":"UNSIGNED_SHORT","type":"SCALAR"},"height":[1,2]})",
           shorts),
      "t.pnts");
  EXPECT_EQ(wide.points.classification, (std::vector<std::uint8_t>{5, 9}));
  ASSERT_EQ(wide.notes.size(), 1u);
  EXPECT_NE(wide.notes[0].find("batchTable: ignored: height"), std::string::npos) << wide.notes[0];
  const PntsTile array = parsePnts(tile(R"({"Classification":[17,1]})", ""), "t.pnts");
  EXPECT_EQ(array.points.classification, (std::vector<std::uint8_t>{17, 1}));

  // Malformed: named (URL, field, what was expected), the points still read without classes.
  auto noted = [&](const std::string& batchJson, const std::string& batchBin) {
    const PntsTile t = parsePnts(tile(batchJson, batchBin), "http://h/t/r0.pnts");
    EXPECT_EQ(t.points.size(), 2u);
    EXPECT_EQ(t.points.positions[1], glm::dvec3(4, 5, 6));
    EXPECT_TRUE(t.points.classification.empty());
    EXPECT_TRUE(t.points.consistent());
    return t.notes.size() == 1 ? t.notes[0] : "(" + std::to_string(t.notes.size()) + " notes)";
  };
  const std::string past = noted(
      R"({"Classification":{"byteOffset":7,"componentType":"UNSIGNED_BYTE","type":"SCALAR"}})", std::string(8, '\0'));
  EXPECT_NE(past.find("http://h/t/r0.pnts"), std::string::npos) << past;
  EXPECT_NE(past.find("batchTable.Classification"), std::string::npos) << past;
  EXPECT_NE(past.find("7 + 1·N (N = 2) = 9 bytes, past the batch table's binary body of 8 bytes"), std::string::npos)
      << past;
  EXPECT_NE(
      noted(R"({"Classification":{"byteOffset":0,"componentType":"FLOAT","type":"SCALAR"}})", std::string(8, '\0'))
          .find("expected an array of classes or {\"byteOffset\""),
      std::string::npos);
  EXPECT_NE(noted(R"({"Classification":[3]})", "").find("expected 2 classes"), std::string::npos);
  EXPECT_NE(noted(R"({"Classification":[3,256]})", "").find("point 1: expected an integer 0..255"), std::string::npos);
  EXPECT_NE(noted(R"({"Classification":{"byteOffset":0,"componentType":"SHORT","type":"SCALAR"}})",
                  std::string("\x01\0\xff\xff\0\0\0\0", 8))
                .find("point 1: expected a class 0..255, got -1"),
            std::string::npos);
  EXPECT_NE(noted(R"({"Classification":)", "").find("batchTable: expected a JSON object"), std::string::npos);
}

TEST(Pnts, BrokenTilesAreNamedWithTheFieldAndWhatWasExpected) {
  std::string bin(900, '\0');
  const std::string good = pnts(R"({"POINTS_LENGTH":75,"POSITION":{"byteOffset":0}})", bin);
  EXPECT_NO_THROW(parsePnts(good, "g"));
  EXPECT_EQ(message(pnts(R"({"POINTS_LENGTH":100,"POSITION":{"byteOffset":1200}})", bin)),
            "http://h/t/r0.pnts: featureTable.POSITION.byteOffset: 1200 + 12·N (N = 100) = 2400 bytes, past the "
            "binary body of 900 bytes");
  EXPECT_EQ(message(good.substr(0, 20)), "http://h/t/r0.pnts: header: expected 28 bytes at least, got 20");
  EXPECT_EQ(message("b3dm" + good.substr(4)),
            "http://h/t/r0.pnts: magic: expected \"pnts\" (a 3D Tiles Point Cloud), got \"b3dm\"");
  std::string v2 = good;
  v2[4] = 2;
  EXPECT_EQ(message(v2), "http://h/t/r0.pnts: version: expected 1, got 2");
  EXPECT_NE(message(good.substr(0, good.size() - 8))
                .find("byteLength: " + std::to_string(good.size()) + " bytes, but the tile has " +
                      std::to_string(good.size() - 8)),
            std::string::npos);
  std::string overflow = good;
  const std::uint32_t huge = 0xFFFFFFF0u;
  std::memcpy(overflow.data() + 16, &huge, 4);
  EXPECT_NE(message(overflow).find("header: 28 + "), std::string::npos);
  EXPECT_NE(message(pnts(R"({"POINTS_LENGTH":1})", bin)).find("featureTable.POSITION: expected POSITION or "),
            std::string::npos);
  EXPECT_NE(message(pnts(R"({"POSITION":{"byteOffset":0}})", bin)).find("featureTable.POINTS_LENGTH: expected"),
            std::string::npos);
  EXPECT_NE(message(pnts(R"({"POINTS_LENGTH":-3,"POSITION":{"byteOffset":0}})", bin)).find("POINTS_LENGTH"),
            std::string::npos);
  EXPECT_NE(
      message(
          pnts(R"({"POINTS_LENGTH":1,"POSITION_QUANTIZED":{"byteOffset":0},"QUANTIZED_VOLUME_OFFSET":[0,0,0]})", bin))
          .find("featureTable.QUANTIZED_VOLUME_SCALE: expected 3 numbers"),
      std::string::npos);
  EXPECT_NE(message(pnts(R"({"POINTS_LENGTH":1,"POSITION":{"byteOffset":0},"RTC_CENTER":[1,2]})", bin))
                .find("featureTable.RTC_CENTER: expected 3 numbers"),
            std::string::npos);
  EXPECT_NE(message(pnts(R"({"POINTS_LENGTH":1,"POSITION":{"byteOffset":"0"}})", bin))
                .find("featureTable.POSITION: expected {\"byteOffset\": n}"),
            std::string::npos);
  EXPECT_NE(message(pnts(R"({"POINTS_LENGTH":1,)", bin)).find("featureTable: expected a JSON object"),
            std::string::npos);
  EXPECT_NE(message(pnts(R"({"POINTS_LENGTH":1000000000,"POSITION":{"byteOffset":0}})", bin))
                .find("1000000000 points cannot fit"),
            std::string::npos);
  std::string nan(12, '\0');
  const float inf = INFINITY;
  std::memcpy(nan.data() + 4, &inf, 4);
  EXPECT_NE(message(pnts(R"({"POINTS_LENGTH":1,"POSITION":{"byteOffset":0}})", nan)).find("point 0: expected finite"),
            std::string::npos);
  EXPECT_NE(message(pnts(R"({"POINTS_LENGTH":1,"POSITION":{"byteOffset":0},"NORMAL":{"byteOffset":0}})",
                         std::string(12, '\0')))
                .find("NORMAL: point 0: expected a non-zero"),
            std::string::npos);
}

const char* kTileset = R"({
  "asset": {"version": "1.0"},
  "geometricError": 500,
  "root": {
    "transform": [1,0,0,0, 0,1,0,0, 0,0,1,0, 100,200,300,1],
    "boundingVolume": {"box": [0,0,0, 10,0,0, 0,20,0, 0,0,2]},
    "geometricError": 100,
    "refine": "ADD",
    "content": {"uri": "r.pnts"},
    "children": [
      {"boundingVolume": {"sphere": [1,2,3,4]}, "geometricError": 10,
       "transform": [2,0,0,0, 0,2,0,0, 0,0,2,0, 5,0,0,1], "content": {"url": "sub/a.pnts?v=1"},
       "children": [{"boundingVolume": {"sphere": [0,0,0,1]}, "geometricError": 0, "refine": "REPLACE",
                     "content": {"uri": "../b.pnts"}}]},
      {"boundingVolume": {"region": [0.1, 0.8, 0.1002, 0.8001, 10, 50]}, "geometricError": 5,
       "content": {"uri": "more/tileset.json"}}
    ]
  }
})";

TEST(Tileset, TransformsComposeAndVolumesBecomeSpheres) {
  const Tiles3dTileset ts = parseTileset(kTileset, "http://h:8/data/city/tileset.json?key=1");
  EXPECT_EQ(ts.version, "1.0");
  EXPECT_EQ(ts.geometricError, 500.0);
  ASSERT_EQ(ts.tiles.size(), 4u);
  const Tiles3dTile& root = ts.tiles[0];
  EXPECT_EQ(root.content, "http://h:8/data/city/r.pnts");
  EXPECT_EQ(root.refine, TileRefine::Add);
  EXPECT_EQ(root.bounds.centre, glm::dvec3(100, 200, 300));
  EXPECT_NEAR(root.bounds.radius, std::sqrt(100.0 + 400.0 + 4.0), 1e-9);  // the box's corner
  ASSERT_EQ(root.children.size(), 2u);
  const Tiles3dTile& a = ts.tiles[std::size_t(root.children[0])];
  EXPECT_EQ(a.path, "root.children[0]");
  EXPECT_EQ(a.refine, TileRefine::Add);  // inherited
  EXPECT_EQ(a.content, "http://h:8/data/city/sub/a.pnts?v=1");
  // root * child: x -> 2x + 5 + 100
  EXPECT_EQ(a.bounds.centre, glm::dvec3(2 + 105, 4 + 200, 6 + 300));
  EXPECT_EQ(a.bounds.radius, 8.0);
  EXPECT_EQ(glm::dvec3(a.transform * glm::dvec4(1, 1, 1, 1)), glm::dvec3(107, 202, 302));
  const Tiles3dTile& b = ts.tiles[std::size_t(a.children[0])];
  EXPECT_EQ(b.refine, TileRefine::Replace);
  EXPECT_EQ(b.content, "http://h:8/data/b.pnts");  // relative to the tileset file, not to a tile
  EXPECT_EQ(b.depth, 2);
  const Tiles3dTile& r = ts.tiles[std::size_t(root.children[1])];
  EXPECT_TRUE(r.external);
  // A region is earth-centred whatever the transform: its centre near the ECEF of its middle.
  const glm::dvec3 mid = wgs84ToEcef(0.1001, 0.80005, 30.0);
  EXPECT_LT(glm::length(r.bounds.centre - mid), 5.0);
  EXPECT_GT(r.bounds.radius, 20.0);
  EXPECT_LT(r.bounds.radius, 800.0);  // 0.0002 rad x 0.0001 rad: about 890 m x 640 m diagonal / 2
}

TEST(Tileset, ExternalTilesetsGraftUnderTheirTile) {
  Tiles3dTileset ts = parseTileset(kTileset, "/data/city/tileset.json");
  const int at = ts.tiles[0].children[1];
  const Tiles3dTile host = ts.tiles[std::size_t(at)];
  Tiles3dTileset sub = parseTileset(
      R"({"asset":{"version":"1.0"},"geometricError":5,"root":{"boundingVolume":{"sphere":[0,0,0,1]},"geometricError":1,
          "content":{"uri":"x.pnts"}}})",
      host.content, host.transform, host.refine, host.depth + 1);
  graftTileset(ts, at, std::move(sub));
  ASSERT_EQ(ts.tiles.size(), 5u);
  EXPECT_TRUE(ts.tiles[std::size_t(at)].content.empty());
  ASSERT_EQ(ts.tiles[std::size_t(at)].children.size(), 1u);
  const Tiles3dTile& g = ts.tiles[std::size_t(ts.tiles[std::size_t(at)].children[0])];
  EXPECT_EQ(g.parent, at);
  EXPECT_EQ(g.content, "/data/city/more/x.pnts");
  EXPECT_EQ(g.refine, TileRefine::Add);
  EXPECT_EQ(g.depth, 2);
  EXPECT_EQ(g.bounds.centre, glm::dvec3(100, 200, 300));  // the host's transform
}

TEST(Tileset, UriResolution) {
  EXPECT_EQ(resolveTileUri("http://h/a/b/tileset.json", "c/d.pnts"), "http://h/a/b/c/d.pnts");
  EXPECT_EQ(resolveTileUri("http://h/a/b/tileset.json", "../../x.pnts"), "http://h/x.pnts");
  EXPECT_EQ(resolveTileUri("http://h/a/b/tileset.json", "/x.pnts"), "http://h/x.pnts");
  EXPECT_EQ(resolveTileUri("http://h/a/tileset.json", "https://o/y.pnts"), "https://o/y.pnts");
  EXPECT_EQ(resolveTileUri("data/tileset.json", "./t/0.pnts"), "data/t/0.pnts");
  EXPECT_EQ(resolveTileUri("tileset.json", "../0.pnts"), "../0.pnts");
  EXPECT_EQ(resolveTileUri("/srv/tileset.json", "/abs/0.pnts"), "/abs/0.pnts");
}

std::string tilesetMessage(const std::string& text) {
  try {
    parseTileset(text, "http://h/tileset.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Tileset, BrokenTilesetsAreNamed) {
  const std::string head = R"({"asset":{"version":"1.0"},"geometricError":1,"root":)";
  EXPECT_EQ(tilesetMessage(R"({"geometricError":1,"root":{}})"),
            "http://h/tileset.json: asset: expected an object with the version (\"1.0\")");
  EXPECT_EQ(tilesetMessage(R"({"asset":{"version":"2.0"},"geometricError":1,"root":{}})"),
            "http://h/tileset.json: asset.version: expected \"1.0\" (or \"0.0\", \"1.1\"), got \"2.0\"");
  EXPECT_NE(tilesetMessage(R"({"asset":{"version":"1.0"},"root":{}})").find("geometricError: expected a number >= 0"),
            std::string::npos);
  EXPECT_EQ(
      tilesetMessage(head + R"({"geometricError":1,"refine":"ADD","boundingVolume":{"sphere":[0,0,0,1]},
      "children":[{"geometricError":0,"boundingVolume":{"sphere":[0,0,0,1]}},{"geometricError":0,"boundingVolume":{"cone":1}}]}})"),
      "http://h/tileset.json: root.children[1].boundingVolume: expected box (12 numbers), region (6) or sphere (4), "
      "got {\"cone\":1}");
  EXPECT_NE(tilesetMessage(head + R"({"geometricError":1,"boundingVolume":{"box":[1,2,3]}}})")
                .find("root.boundingVolume.box: expected 12 numbers"),
            std::string::npos);
  EXPECT_NE(
      tilesetMessage(
          head +
          R"({"geometricError":1,"boundingVolume":{"sphere":[0,0,0,1]},"transform":[1,0,0,1, 0,1,0,0, 0,0,1,0, 0,0,0,1]}})")
          .find("root.transform: expected an affine matrix"),
      std::string::npos);
  EXPECT_NE(tilesetMessage(head + R"({"geometricError":1,"boundingVolume":{"sphere":[0,0,0,1]},"refine":"MERGE"}})")
                .find("root.refine: expected \"ADD\" or \"REPLACE\""),
            std::string::npos);
  EXPECT_NE(tilesetMessage(head + R"({"geometricError":1,"boundingVolume":{"sphere":[0,0,0,1]},"content":{"uri":3}}})")
                .find("root.content.uri: expected a URI"),
            std::string::npos);
  EXPECT_NE(tilesetMessage(head + R"({"geometricError":-1,"boundingVolume":{"sphere":[0,0,0,1]}}})")
                .find("root.geometricError: expected a number >= 0"),
            std::string::npos);
  EXPECT_NE(tilesetMessage(head + R"({"geometricError":1,"boundingVolume":{"region":[0,1,0.1,0.9,0,1]}}})")
                .find("root.boundingVolume.region: expected west, south"),
            std::string::npos);
  EXPECT_NE(tilesetMessage("[1,2").find("expected a 3D Tiles tileset (JSON)"), std::string::npos);
  // Too deep a tree is refused, not walked.
  std::string deep = head;
  for (int i = 0; i < 80; ++i) deep += R"({"geometricError":1,"boundingVolume":{"sphere":[0,0,0,1]},"children":[)";
  deep += R"({"geometricError":1,"boundingVolume":{"sphere":[0,0,0,1]}})";
  for (int i = 0; i < 80; ++i) deep += "]}";
  deep += "}";
  EXPECT_NE(tilesetMessage(deep).find("deeper than 64 levels"), std::string::npos);
  // The root's missing refine is a note, REPLACE assumed.
  const Tiles3dTileset ts = parseTileset(head + R"({"geometricError":1,"boundingVolume":{"sphere":[0,0,0,1]}}})", "t");
  ASSERT_EQ(ts.notes.size(), 1u);
  EXPECT_EQ(ts.tiles[0].refine, TileRefine::Replace);
}

TEST(PointTilesWriter, EveryPointOnceAcrossTheTree) {
  // 3000 points on a 10 cm grid (distinct), colours and normals; the tree's points, each tile's
  // decoded through the root transform, are the same points within quantization.
  PointCloud cloud;
  cloud.resize(3000, PointFields{false, true, true, true});
  std::map<std::tuple<long, long, long>, std::uint8_t> classOf;
  std::uint64_t s = 12345;
  std::set<std::tuple<long, long, long>> cells;
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    std::tuple<long, long, long> cell;
    do {
      s = s * 6364136223846793005ull + 1442695040888963407ull;
      cell = {long((s >> 20) % 2000), long((s >> 40) % 1500), long((s >> 8) % 100)};
    } while (!cells.insert(cell).second);
    cloud.positions[i] = 0.1 * glm::dvec3(std::get<0>(cell), std::get<1>(cell), std::get<2>(cell));
    cloud.rgb[i] = glm::u16vec3(std::uint16_t(i % 256 * 257), 0, 65535);
    cloud.normals[i] = glm::vec3(0, 0, 1);
    cloud.classification[i] = classOf[cell] = std::uint8_t((std::get<0>(cell) * 7 + std::get<2>(cell)) % 19);
  }
  const glm::dmat4 root = glm::dmat4(glm::dvec4(0, 1, 0, 0), glm::dvec4(-1, 0, 0, 0), glm::dvec4(0, 0, 1, 0),
                                     glm::dvec4(4e6, 3e5, 4.8e6, 1));
  const PointTilesWritten w = writePointTiles(cloud, root, PointTilesOptions{200, 16});
  EXPECT_GT(w.tiles, 8u);
  std::map<std::string, std::string> files;
  for (const PointTilesFile& f : w.files) files[f.name] = f.bytes;
  const Tiles3dTileset ts = parseTileset(files.at("tileset.json"), "tileset.json");
  EXPECT_EQ(ts.tiles.size(), w.tiles);
  EXPECT_TRUE(ts.notes.empty());
  std::set<std::tuple<long, long, long>> seen;
  std::size_t total = 0;
  for (const Tiles3dTile& t : ts.tiles) {
    ASSERT_TRUE(files.count(t.content)) << t.content;
    const PntsTile p = parsePnts(files.at(t.content), t.content);
    total += p.points.size();
    EXPECT_EQ(p.points.normals.size(), p.points.size());
    ASSERT_EQ(p.points.classification.size(), p.points.size()) << t.content;
    EXPECT_TRUE(p.notes.empty()) << p.notes[0];
    // 28-byte header, feature table and batch table each on 8-byte boundaries.
    EXPECT_EQ(files.at(t.content).size() % 8, 0u);
    for (std::size_t i = 0; i < p.points.size(); ++i) {
      const glm::dvec3 world = glm::dvec3(t.transform * glm::dvec4(p.points.positions[i], 1.0));
      // Within the tile's bounding sphere.
      EXPECT_LE(glm::length(world - t.bounds.centre), t.bounds.radius + 1e-6);
      const glm::dvec3 local = glm::dvec3(glm::inverse(root) * glm::dvec4(world, 1.0)) * 10.0;
      const glm::dvec3 r = glm::round(local);
      EXPECT_LT(glm::length(local - r), 0.3);  // quantization: under 3 cm over a 200 m box
      seen.insert({long(r.x), long(r.y), long(r.z)});
      const std::tuple<long, long, long> cell{long(r.x), long(r.y), long(r.z)};
      EXPECT_EQ(p.points.classification[i], classOf[cell]);
    }
  }
  EXPECT_EQ(total, cloud.size());
  EXPECT_EQ(seen, cells);
}

}  // namespace
}  // namespace hv
