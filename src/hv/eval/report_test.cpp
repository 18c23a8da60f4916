#include "hv/eval/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace hv::eval {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

EvalReport sampleReport() {
  EvalReport r;
  r.methods = {"blend", "nearest"};
  r.rows = {
      {"v01", "blend", 30.0, 0.90, 0.95, 0.80},  {"v01", "nearest", 26.0, 0.80, 0.97, 0.80},
      {"v02", "blend", 32.0, 0.94, 0.85, 0.70},  {"v02", "nearest", 25.0, 0.78, 0.90, 0.70},
      {"v03", "blend", kInf, 1.00, 1.00, 0.90},  {"v03", "nearest", 27.5, 0.82, 0.92, 0.90},
  };
  return r;
}

TEST(Report, MeansExcludeInfinitePsnrAndCountIt) {
  const auto means = methodMeans(sampleReport());
  ASSERT_EQ(means.size(), 2u);
  const MethodMean& b = means.at("blend");
  EXPECT_DOUBLE_EQ(b.psnr, 31.0);  // (30 + 32) / 2, the identical view left out
  EXPECT_EQ(b.infinitePsnr, 1u);
  EXPECT_EQ(b.views, 3u);
  EXPECT_DOUBLE_EQ(b.ssim, (0.90 + 0.94 + 1.00) / 3);  // SSIM 1 is a number: it stays in
  EXPECT_DOUBLE_EQ(b.coverage, (0.95 + 0.85 + 1.00) / 3);
  EXPECT_DOUBLE_EQ(b.scored, (0.80 + 0.70 + 0.90) / 3);
  const MethodMean& n = means.at("nearest");
  EXPECT_DOUBLE_EQ(n.psnr, (26.0 + 25.0 + 27.5) / 3);
  EXPECT_EQ(n.infinitePsnr, 0u);

  const auto psnr = meanPsnr(sampleReport());
  EXPECT_DOUBLE_EQ(psnr.at("blend"), 31.0);
  EXPECT_DOUBLE_EQ(psnr.at("nearest"), (26.0 + 25.0 + 27.5) / 3);
}

TEST(Report, AllInfiniteMeanIsInfiniteAndUnscoredViewsAreLeftOut) {
  EvalReport r;
  r.methods = {"self"};
  r.rows = {{"a", "self", kInf, 1.0, 1.0, 1.0}, {"b", "self", kInf, 1.0, 0.5, 0.5},
            {"c", "self", kNaN, kNaN, 0.0, 0.0}};
  const MethodMean m = methodMeans(r).at("self");
  EXPECT_TRUE(std::isinf(m.psnr));
  EXPECT_EQ(m.infinitePsnr, 2u);
  EXPECT_EQ(m.unscored, 1u);
  EXPECT_DOUBLE_EQ(m.ssim, 1.0);
  EXPECT_DOUBLE_EQ(m.coverage, 0.5);  // coverage is known even where nothing was scored

  const nlohmann::json j = toJson(r);
  EXPECT_EQ(j["mean"]["self"]["psnr"], "inf");
  EXPECT_TRUE(j["views"][2]["psnr"].is_null());
  EXPECT_TRUE(j["views"][2]["ssim"].is_null());
  EXPECT_EQ(j["mean"]["self"]["unscored"], 1);

  const std::string table = formatTable(r);
  EXPECT_NE(table.find("n/a"), std::string::npos) << table;
  EXPECT_NE(table.find("no scored pixel"), std::string::npos) << table;
}

TEST(Report, MethodWithoutRowsHasNaNMeans) {
  EvalReport r;
  r.methods = {"blend", "unused"};
  r.rows = {{"v", "blend", 20.0, 0.5, 1.0, 1.0}};
  const auto means = methodMeans(r);
  EXPECT_EQ(means.at("unused").views, 0u);
  EXPECT_TRUE(std::isnan(means.at("unused").psnr));
  EXPECT_TRUE(toJson(r)["mean"]["unused"]["psnr"].is_null());
}

TEST(Report, JsonHasTheDocumentedFields) {
  const nlohmann::json j = toJson(sampleReport());
  EXPECT_EQ(j["methods"], nlohmann::json({"blend", "nearest"}));
  ASSERT_EQ(j["views"].size(), 6u);
  const auto& v0 = j["views"][0];
  EXPECT_EQ(v0["view"], "v01");
  EXPECT_EQ(v0["method"], "blend");
  EXPECT_DOUBLE_EQ(v0["psnr"].get<double>(), 30.0);
  EXPECT_DOUBLE_EQ(v0["ssim"].get<double>(), 0.90);
  EXPECT_DOUBLE_EQ(v0["coverage"].get<double>(), 0.95);
  EXPECT_DOUBLE_EQ(v0["scored"].get<double>(), 0.80);
  // JSON has no infinity: the identical view's PSNR is the string "inf".
  EXPECT_EQ(j["views"][4]["psnr"], "inf");
  const auto& mb = j["mean"]["blend"];
  EXPECT_DOUBLE_EQ(mb["psnr"].get<double>(), 31.0);
  EXPECT_DOUBLE_EQ(mb["ssim"].get<double>(), (0.90 + 0.94 + 1.00) / 3);
  EXPECT_DOUBLE_EQ(mb["coverage"].get<double>(), (0.95 + 0.85 + 1.00) / 3);
  EXPECT_EQ(mb["views"], 3);
  EXPECT_EQ(mb["infinite_psnr"], 1);
  EXPECT_TRUE(j["mean"].contains("nearest"));
  // The dump must be valid JSON (no bare inf / nan) and parse back to the same document.
  EXPECT_EQ(nlohmann::json::parse(j.dump()), j);
}

TEST(Report, TableListsEveryViewAndMethodWithMeans) {
  const std::string table = formatTable(sampleReport());
  for (const char* s :
       {"v01", "v02", "v03", "blend", "nearest", "mean", "PSNR dB", "SSIM", "coverage", "scored"})
    EXPECT_NE(table.find(s), std::string::npos) << s << "\n" << table;
  EXPECT_NE(table.find("30.00"), std::string::npos) << table;  // 2 decimals
  EXPECT_NE(table.find("0.9000"), std::string::npos) << table;  // 4 decimals
  EXPECT_NE(table.find("95.0 %"), std::string::npos) << table;  // coverage in percent
  EXPECT_NE(table.find("inf"), std::string::npos) << table;
  EXPECT_NE(table.find("31.00"), std::string::npos) << table;  // blend's mean PSNR
  EXPECT_NE(table.find("left out of the mean PSNR"), std::string::npos) << table;

  // Columns aligned: every data line has the same length, and the SSIM column ends at the same place.
  std::istringstream in(table);
  std::string line;
  std::vector<std::string> rows;
  while (std::getline(in, line))
    if (line.rfind("v0", 0) == 0 || line.rfind("mean", 0) == 0) rows.push_back(line);
  ASSERT_EQ(rows.size(), 8u) << table;  // 6 view rows + 2 means
  for (const auto& r : rows) {
    EXPECT_EQ(r.size(), rows[0].size()) << table;
    EXPECT_EQ(r.find(" %"), rows[0].find(" %")) << table;
  }
  std::printf("%s", table.c_str());
}

TEST(Report, MethodsOnlyInRowsAreIncluded) {
  EvalReport r;
  r.methods = {"blend"};
  r.rows = {{"v", "blend", 20.0, 0.5, 1.0, 1.0}, {"v", "no-occlusion", 18.0, 0.4, 1.0, 1.0}};
  EXPECT_EQ(orderedMethods(r), (std::vector<std::string>{"blend", "no-occlusion"}));
  EXPECT_EQ(meanPsnr(r).size(), 2u);
  EXPECT_NE(formatTable(r).find("no-occlusion"), std::string::npos);
}

TEST(Report, SeamColumnOnlyWhenMeasured) {
  EvalReport r = sampleReport();
  EXPECT_EQ(formatTable(r).find("seam"), std::string::npos);
  EXPECT_TRUE(toJson(r)["views"][0]["seam"].is_null());
  // Seams on blend's rows only (one view without a border): the mean is over the measured ones.
  r.rows[0].seam = 3.0;
  r.rows[2].seam = 5.5;
  const std::string table = formatTable(r);
  EXPECT_NE(table.find("seam"), std::string::npos) << table;
  EXPECT_NE(table.find("4.25"), std::string::npos) << table;  // blend's mean seam
  const MethodMean blend = methodMeans(r).at("blend");
  EXPECT_DOUBLE_EQ(blend.seam, 4.25);
  EXPECT_TRUE(std::isnan(methodMeans(r).at("nearest").seam));
  const nlohmann::json j = toJson(r);
  EXPECT_DOUBLE_EQ(j["views"][0]["seam"].get<double>(), 3.0);
  EXPECT_DOUBLE_EQ(j["mean"]["blend"]["seam"].get<double>(), 4.25);
  EXPECT_TRUE(j["mean"]["nearest"]["seam"].is_null());
}

}  // namespace
}  // namespace hv::eval
