#include "hv/io/native/footprints.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

class FootprintsIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_footprints_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    const std::string path = (dir_ / name).string();
    std::ofstream(path) << text;
    return path;
  }
  fs::path dir_;
};

std::string feature(int id, const std::string& properties, const std::string& geometry) {
  return R"({"type":"Feature","id":)" + std::to_string(id) + R"(,"properties":)" + properties +
         R"(,"geometry":)" + geometry + "}";
}

std::string collection(const std::vector<std::string>& features) {
  std::string out = R"({"type":"FeatureCollection","features":[)";
  for (size_t k = 0; k < features.size(); ++k) out += (k ? ",\n" : "\n") + features[k];
  return out + "\n]}\n";
}

const Footprint* byId(const std::vector<Footprint>& fps, const std::string& id) {
  const auto it = std::find_if(fps.begin(), fps.end(), [&](const Footprint& f) { return f.id == id; });
  return it == fps.end() ? nullptr : &*it;
}

bool anyWarningMentions(const Diagnostics& diag, const std::string& text) {
  return std::any_of(diag.warnings.begin(), diag.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

const std::string kSquare = R"({"type":"Polygon","coordinates":[[[70,0],[71,0],[71,1],[70,1],[70,0]]]})";

TEST_F(FootprintsIo, MixedLayerLoadsValidFeaturesAndWarnsAboutTheRest) {
  // Heights of several JSON types: OGR makes the column a string one, parsed as numbers here.
  const std::string path =
      write("buildings.geojson",
            collection({
                feature(1, R"({"height":12})",
                        R"({"type":"Polygon","coordinates":[[[0,0],[10,0],[10,10],[0,10],[0,0]]]})"),
                feature(2, R"({"height":"7.5"})",
                        R"({"type":"Polygon","coordinates":[[[20,0],[40,0],[40,20],[20,20],[20,0]],)"
                        R"([[25,5],[25,15],[35,15],[35,5],[25,5]]]})"),
                feature(3, R"({"height":4.25})",
                        R"({"type":"MultiPolygon","coordinates":[[[[50,0],[52,0],[52,2],[50,2],[50,0]]],)"
                        R"([[[60,0],[63,0],[63,3],[60,3],[60,0]]]]})"),
                feature(4, R"({"height":9})", R"({"type":"LineString","coordinates":[[0,0],[1,1]]})"),
                feature(5, R"({"name":"no height"})", kSquare),
                feature(6, R"({"height":null})", kSquare),
                feature(7, R"({"height":"tall"})", kSquare),
                feature(8, R"({"height":-3})", kSquare),
                feature(9, R"({"height":5})",
                        R"({"type":"Polygon","coordinates":[[[0,0],[1,1],[0,0],[1,1],[0,0]]]})"),
                feature(10, R"({"height":5})", "null"),
                feature(11, R"({"height":6})",
                        R"({"type":"Polygon","coordinates":[[[0,0,5],[2,0,5],[2,2,6],[0,2,6],[0,0,5]]]})"),
                feature(12, R"({"roof":130.5})", kSquare),
                feature(13, R"({"height":8})",
                        R"({"type":"Polygon","coordinates":[[[0,0],[2,2],[2,0],[0,2],[0,0]]]})"),
            }));
  FootprintFields fields;
  fields.top = "roof";
  Diagnostics diag;
  const std::vector<Footprint> fps = readFootprints(path, fields, diag);

  std::vector<std::string> ids;
  for (const auto& f : fps) ids.push_back(f.id);
  EXPECT_EQ(ids, (std::vector<std::string>{"1", "2", "3.0", "3.1", "11", "12", "13"}));

  const Footprint* f1 = byId(fps, "1");
  ASSERT_NE(f1, nullptr);
  ASSERT_EQ(f1->rings.size(), 1u);
  EXPECT_EQ(f1->rings[0],
            (std::vector<glm::dvec2>{{0, 0}, {10, 0}, {10, 10}, {0, 10}}));  // closing point dropped
  EXPECT_EQ(f1->height, 12.0);
  EXPECT_FALSE(f1->top.has_value());

  const Footprint* f2 = byId(fps, "2");
  ASSERT_NE(f2, nullptr);
  ASSERT_EQ(f2->rings.size(), 2u);
  EXPECT_EQ(f2->rings[1], (std::vector<glm::dvec2>{{25, 5}, {25, 15}, {35, 15}, {35, 5}}));
  EXPECT_EQ(f2->height, 7.5);

  ASSERT_NE(byId(fps, "3.1"), nullptr);
  EXPECT_EQ(byId(fps, "3.1")->rings[0][2], glm::dvec2(63, 3));
  EXPECT_EQ(byId(fps, "3.1")->height, 4.25);
  EXPECT_EQ(byId(fps, "11")->rings[0], (std::vector<glm::dvec2>{{0, 0}, {2, 0}, {2, 2}, {0, 2}}));
  const Footprint* f12 = byId(fps, "12");
  EXPECT_FALSE(f12->height.has_value());
  EXPECT_EQ(f12->top, 130.5);

  EXPECT_EQ(diag.warnings.size(), 7u);
  for (const int bad : {4, 5, 6, 7, 8, 9, 10})
    EXPECT_TRUE(anyWarningMentions(diag, "feature " + std::to_string(bad) + ":")) << "feature " << bad;
  EXPECT_TRUE(anyWarningMentions(diag, "'tall'"));
  for (const auto& w : diag.warnings) EXPECT_NE(w.find(path), std::string::npos) << w;

  // The self-intersecting footprint is read as given and rejected when extruded, by id.
  Diagnostics buildDiag;
  const Mesh m = buildLod1(fps, nullptr, buildDiag);
  EXPECT_FALSE(m.empty());
  EXPECT_TRUE(anyWarningMentions(buildDiag, "footprint 13:"));
  EXPECT_TRUE(anyWarningMentions(buildDiag, "Self-intersection"));
}

TEST_F(FootprintsIo, IntegerAndRealHeightColumns) {
  const std::string ints = write(
      "ints.geojson", collection({feature(1, R"({"h":12})", kSquare), feature(2, R"({"h":0})", kSquare)}));
  const std::string reals = write(
      "reals.geojson", collection({feature(1, R"({"h":12.75,"from":"1920-01-01","to":"1944-06"})", kSquare),
                                   feature(2, R"({"h":3})", kSquare)}));
  FootprintFields fields;
  fields.height = "h";
  fields.validFrom = "from";
  fields.validTo = "to";
  Diagnostics diag;
  const auto a = readFootprints(ints, fields, diag);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a[0].height, 12.0);
  ASSERT_EQ(diag.warnings.size(), 1u);  // h = 0 is not a height
  EXPECT_NE(diag.warnings[0].find("feature 2"), std::string::npos) << diag.warnings[0];

  const auto b = readFootprints(reals, fields, diag);
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b[0].height, 12.75);
  EXPECT_EQ(b[0].validFrom, "1920-01-01");  // OGR types this column as a date; read back as ISO
  EXPECT_EQ(b[0].validTo, "1944-06");
  EXPECT_FALSE(b[1].validFrom.has_value());
  EXPECT_EQ(b[1].height, 3.0);
}

TEST_F(FootprintsIo, BaseAndTopAttributes) {
  const std::string path =
      write("abs.geojson", collection({feature(1, R"({"height":10,"z0":"35.5","z1":50})", kSquare),
                                       feature(2, R"({"height":10,"z0":"low","z1":50})", kSquare)}));
  FootprintFields fields;
  fields.base = "z0";
  fields.top = "z1";
  Diagnostics diag;
  const auto fps = readFootprints(path, fields, diag);
  ASSERT_EQ(fps.size(), 1u);
  EXPECT_EQ(fps[0].base, 35.5);
  EXPECT_EQ(fps[0].top, 50.0);
  ASSERT_EQ(diag.warnings.size(), 1u);
  EXPECT_NE(diag.warnings[0].find("feature 2: z0"), std::string::npos) << diag.warnings[0];
}

TEST_F(FootprintsIo, MissingFileThrowsNamingThePath) {
  const std::string path = (dir_ / "nowhere.geojson").string();
  Diagnostics diag;
  try {
    readFootprints(path, FootprintFields{}, diag);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace hv
