#include "hv/io/geojson_footprints.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hv {
namespace {

TEST(GeoJsonFootprints, PolygonsPartsAndSkippedFeatures) {
  const std::string text = R"({"type": "FeatureCollection", "features": [
    {"type": "Feature", "id": "b1", "properties": {"height": 18.5, "from": "1900"},
     "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [4, 0], [4, 3], [0, 0]], [[1, 1], [2, 1], [2, 2]]]}},
    {"type": "Feature", "id": 7, "properties": {"height": "12"},
     "geometry": {"type": "MultiPolygon", "coordinates": [[[[10, 0], [11, 0], [11, 1]]], [[[20, 0], [21, 0], [21, 1, 5]]]]}},
    {"type": "Feature", "id": "p", "properties": {"height": 3}, "geometry": {"type": "Point", "coordinates": [0, 0]}},
    {"type": "Feature", "id": "nh", "properties": {}, "geometry": {"type": "Polygon", "coordinates": [[[0, 0], [1, 0], [1, 1]]]}},
    {"type": "Feature", "properties": {"height": 1}, "geometry": null}],
    "links": [{"rel": "self", "href": "a"}, {"rel": "next", "href": "http://x/items?offset=5"}]})";
  GeoJsonFootprintFields fields;
  fields.validFrom = "from";
  Diagnostics diag;
  const GeoJsonFootprintPage page = parseGeoJsonFootprints(text, fields, "page.json", diag);
  EXPECT_EQ(page.features, 5u);
  EXPECT_EQ(page.next, "http://x/items?offset=5");
  ASSERT_EQ(page.footprints.size(), 3u);
  EXPECT_EQ(page.footprints[0].id, "b1");
  ASSERT_EQ(page.footprints[0].rings.size(), 2u);
  EXPECT_EQ(page.footprints[0].rings[0].size(), 4u);  // as given (closing point kept: extrusion cleans it)
  EXPECT_EQ(page.footprints[0].rings[1][2], glm::dvec2(2, 2));
  EXPECT_EQ(*page.footprints[0].height, 18.5);
  EXPECT_EQ(*page.footprints[0].validFrom, "1900");
  EXPECT_EQ(page.footprints[1].id, "7.0");
  EXPECT_EQ(page.footprints[2].id, "7.1");
  EXPECT_EQ(*page.footprints[2].height, 12.0);
  EXPECT_EQ(page.footprints[2].rings[0][2], glm::dvec2(21, 1));
  ASSERT_EQ(diag.warnings.size(), 3u);
  EXPECT_NE(diag.warnings[0].find("page.json: feature p: geometry 'Point', expected Polygon or MultiPolygon"),
            std::string::npos);
  EXPECT_NE(diag.warnings[1].find("page.json: feature nh: no usable height"), std::string::npos);
  EXPECT_NE(diag.warnings[2].find("page.json: feature 4: no geometry"), std::string::npos);
}

TEST(GeoJsonFootprints, RefusesWhatIsNotAFeatureCollection) {
  Diagnostics diag;
  EXPECT_THROW(parseGeoJsonFootprints("{", {}, "a.json", diag), InputError);
  try {
    parseGeoJsonFootprints(R"({"type": "Feature"})", {}, "a.json", diag);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.json: expected a GeoJSON FeatureCollection"), std::string::npos);
  }
}

TEST(AaiGrid, HeaderValuesAndNoData) {
  const Heightfield h = parseAaiGrid(
      "ncols 3\nnrows 2\nxllcorner 100\nyllcorner 200\ncellsize 2\nNODATA_value -9999\n 1 2 3\n4 -9999 6.5\n", "g.asc");
  EXPECT_EQ(h.cols, 3);
  EXPECT_EQ(h.rows, 2);
  EXPECT_EQ(h.originX, 100.0);
  EXPECT_EQ(h.originY, 204.0);  // the north edge: yllcorner + 2 rows of 2 m
  EXPECT_EQ(h.cellX, 2.0);
  EXPECT_EQ(h.cellY, -2.0);
  EXPECT_EQ(h.at(0, 0), 1.0f);
  EXPECT_EQ(h.at(2, 1), 6.5f);
  EXPECT_TRUE(std::isnan(h.at(1, 1)));
  // Sample (0, 1) (south-west) at its cell's centre.
  EXPECT_EQ(h.samplePosition(0, 1), glm::dvec2(101.0, 201.0));
  const Heightfield c = parseAaiGrid("NCOLS 1\nNROWS 1\nXLLCENTER 1\nYLLCENTER 1\nDX 2\nDY 4\n7", "c.asc");
  EXPECT_EQ(c.originX, 0.0);
  EXPECT_EQ(c.originY, 3.0);
}

TEST(AaiGrid, Refusals) {
  auto message = [](const std::string& text) {
    try {
      parseAaiGrid(text, "g.asc");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2 3").find("g.asc: values: 3 of 4 read"),
            std::string::npos);
  EXPECT_NE(message("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1 2").find("more than ncols x nrows"),
            std::string::npos);
  EXPECT_NE(message("ncols 0\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n1").find("ncols, nrows"),
            std::string::npos);
  EXPECT_NE(message("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize -1\n1").find("cellsize"), std::string::npos);
  EXPECT_NE(message("ncols 1\nnrows 1\nfoo 3\n1").find("unknown keyword 'foo'"), std::string::npos);
}

}  // namespace
}  // namespace hv
