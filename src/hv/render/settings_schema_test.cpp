#include "hv/render/settings_schema.h"

#include "hv/util/dates.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <set>
#include <stdexcept>
#include <string>

namespace hv::render {
namespace {

// A valid text other than the default, in the form toText writes (so it must read back as it is).
std::string otherText(const Setting& s) {
  const std::string def = defaultText(s);
  switch (s.type) {
    case SettingType::Bool: return def == "true" ? "false" : "true";
    case SettingType::Int: {
      const long long v = std::stoll(def);
      return std::to_string(double(v + 1) <= s.max ? v + 1 : v - 1);
    }
    case SettingType::Double:
      if (s.autoValue) return "0.5";
      if (s.max < 3.5) return def == "0.25" ? "0.125" : "0.25";  // a setting in [0, 1]
      return def == "2.5" ? "3.5" : "2.5";
    case SettingType::Enum: return s.spellings.front() == def ? s.spellings.back() : s.spellings.front();
    case SettingType::IntList: return "3,4";
    case SettingType::TextList: return s.spellings.empty() ? "a,b" : s.spellings.front();
    case SettingType::Colour: return "10,20,30";
    case SettingType::Date: return "1905-06-01";
  }
  return "";
}

std::string errorOf(const std::string& name, const std::string& text) {
  RenderSettings s;
  try {
    setFromText(s, name, text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SettingsSchema, NamesAreUniqueAndEntriesComplete) {
  std::set<std::string> names;
  for (const Setting& s : settingsSchema()) {
    EXPECT_TRUE(names.insert(s.name).second) << s.name << " declared twice";
    EXPECT_FALSE(s.help.empty()) << s.name;
    EXPECT_FALSE(s.group.empty()) << s.name;
    EXPECT_TRUE(s.get && s.set) << s.name;
    if (s.type == SettingType::Enum) EXPECT_GE(s.spellings.size(), 2u) << s.name;
    if (s.type == SettingType::Int || s.type == SettingType::Double) EXPECT_LT(s.sliderMin, s.sliderMax) << s.name;
  }
  // Groups are contiguous: each appears once in settingGroups().
  const auto groups = settingGroups();
  EXPECT_EQ(std::set<std::string>(groups.begin(), groups.end()).size(), groups.size());
}

TEST(SettingsSchema, EveryEntryRoundTripsTextSettingText) {
  for (const Setting& s : settingsSchema()) {
    for (const std::string& text : {defaultText(s), otherText(s)}) {
      RenderSettings r;
      setFromText(r, s.name, text);
      EXPECT_EQ(toText(r, s.name), text) << s.name;
    }
  }
}

// Each entry writes its own field: changing one leaves every other entry's text as it was, and
// writing the defaults back restores them all.
TEST(SettingsSchema, EntriesAreIndependentAndDefaultsRestoreThem) {
  const RenderSettings defaults;
  RenderSettings changed;
  for (const Setting& s : settingsSchema()) {
    RenderSettings one;
    setFromText(one, s.name, otherText(s));
    for (const Setting& other : settingsSchema())
      if (other.name != s.name) EXPECT_EQ(toText(one, other.name), defaultText(other)) << s.name << " changed " << other.name;
    setFromText(changed, s.name, otherText(s));
  }
  for (const Setting& s : settingsSchema()) EXPECT_NE(toText(changed, s.name), defaultText(s)) << s.name;
  for (const Setting& s : settingsSchema()) setFromText(changed, s.name, defaultText(s));
  for (const Setting& s : settingsSchema()) EXPECT_EQ(toText(changed, s.name), defaultText(s)) << s.name;
  // And the fields themselves are a default RenderSettings's again (read directly, not through
  // the schema).
  EXPECT_EQ(changed.blend.k, defaults.blend.k);
  EXPECT_EQ(changed.blend.sigma, defaults.blend.sigma);
  EXPECT_FALSE(changed.blend.window.has_value());
  EXPECT_EQ(changed.depthSize, defaults.depthSize);
  EXPECT_EQ(changed.memoryBudgetBytes, defaults.memoryBudgetBytes);
  EXPECT_EQ(changed.decodeMemoryBytes, defaults.decodeMemoryBytes);
  EXPECT_EQ(changed.points.keptClasses, defaults.points.keptClasses);
  EXPECT_EQ(changed.points.budget, defaults.points.budget);
  EXPECT_EQ(changed.background, defaults.background);
  EXPECT_EQ(changed.debug.view, defaults.debug.view);
  EXPECT_EQ(changed.binding, defaults.binding);
}

TEST(SettingsSchema, DefaultsAreADefaultRenderSettings) {
  // Independent values: the struct's initialisers as docs and the README state them.
  const RenderSettings d;
  auto def = [](const char* name) { return defaultText(setting(name)); };
  EXPECT_EQ(def("k"), std::to_string(d.blend.k));
  EXPECT_EQ(def("k"), "8");
  EXPECT_EQ(def("depth-size"), "1024");
  EXPECT_EQ(def("kept-classes"), "2,6,9,10,11,17");
  EXPECT_EQ(def("sigma"), "auto");
  EXPECT_EQ(def("background"), "0,0,0");
  EXPECT_EQ(def("memory-budget"), "1024");  // MiB: 1 << 30 bytes
  EXPECT_EQ(def("decode-memory"), "512");
  EXPECT_EQ(def("point-budget"), "2000000");
  EXPECT_EQ(def("point-radius-scale"), "0.75");
  EXPECT_EQ(def("from"), "");
  EXPECT_EQ(def("to"), "");
  EXPECT_EQ(def("masks"), "true");
  EXPECT_EQ(def("points"), "false");
  EXPECT_EQ(def("debug-view"), "picture");
  EXPECT_EQ(def("sprite-form"), "nprime");
  EXPECT_EQ(def("binding"), "array");
}

TEST(SettingsSchema, TextReachesTheRightField) {
  RenderSettings s;
  setFromText(s, "k", "3");
  EXPECT_EQ(s.blend.k, 3);
  setFromText(s, "sigma", "2.5");
  EXPECT_EQ(s.blend.sigma, 2.5);
  setFromText(s, "sigma", "auto");
  EXPECT_EQ(s.blend.sigma, RenderSettings{}.blend.sigma);
  setFromText(s, "memory-budget", "256");
  EXPECT_EQ(s.memoryBudgetBytes, std::size_t(256) << 20);
  setFromText(s, "background", "255, 0, 51");  // spaces around the components, as ever
  EXPECT_EQ(s.background, glm::dvec3(1.0, 0.0, 0.2));
  EXPECT_EQ(toText(s, "background"), "255,0,51");
  setFromText(s, "from", "1905");
  ASSERT_TRUE(s.blend.window);
  EXPECT_EQ(s.blend.window->first, daysFromCivil(1905, 1, 1));
  EXPECT_EQ(s.blend.window->last, DateInterval{}.last);
  setFromText(s, "to", "1910-06");
  EXPECT_EQ(s.blend.window->last, daysFromCivil(1910, 6, 30));
  setFromText(s, "from", "");
  setFromText(s, "to", "");
  EXPECT_FALSE(s.blend.window);  // both ends open: no window
  setFromText(s, "debug-view", "depth");
  EXPECT_EQ(s.debug.view, DebugView::DepthMap);
  setFromText(s, "point-filter", "class");
  EXPECT_EQ(s.points.filter, PointFilter::Classification);
  setFromText(s, "point-color", "intensity");
  EXPECT_EQ(s.points.color, PointColorMode::Intensity);
  setFromText(s, "blend-method", "nearest");
  EXPECT_EQ(s.blend.method, ibr::BlendMethod::Nearest);
  setFromText(s, "kept-classes", "2, 6");
  EXPECT_EQ(s.points.keptClasses, (std::vector<int>{2, 6}));
  setFromText(s, "kept-classes", "");
  EXPECT_TRUE(s.points.keptClasses.empty());
  setFromText(s, "exclude", "p1,p2");
  EXPECT_EQ(s.blend.exclude, (std::vector<std::string>{"p1", "p2"}));
  setFromText(s, "masks", "off");
  EXPECT_FALSE(s.blend.masks);
  setFromText(s, "distortion", "false");
  EXPECT_FALSE(s.layers.lensDistortion);
  setFromText(s, "points-in-depth-maps", "false");
  EXPECT_FALSE(s.points.keptInDepthMaps);
}

TEST(SettingsSchema, BadValuesNameTheOptionTheTextAndTheExpectation) {
  const std::string k = errorOf("k", "0");
  EXPECT_NE(k.find("--k: expected a whole number >= 1, got '0'"), std::string::npos) << k;
  EXPECT_NE(errorOf("k", "2.5").find("got '2.5'"), std::string::npos);
  EXPECT_NE(errorOf("k", "").find("--k"), std::string::npos);
  EXPECT_NE(errorOf("depth-size", "15").find("in 16-16384"), std::string::npos);
  const std::string filter = errorOf("point-filter", "classes");
  EXPECT_NE(filter.find("--point-filter: expected one of auto, class, epsilon, none, got 'classes'"), std::string::npos)
      << filter;
  EXPECT_NE(errorOf("mesh-offset", "-1").find("a number >= 0, or auto"), std::string::npos);
  EXPECT_NE(errorOf("frustum-depth", "0").find("a number > 0"), std::string::npos);
  EXPECT_NE(errorOf("masks", "maybe").find("--masks: expected true or false"), std::string::npos);
  EXPECT_NE(errorOf("background", "1,2").find("R,G,B"), std::string::npos);
  EXPECT_NE(errorOf("background", "1,2,300").find("'1,2,300'"), std::string::npos);
  EXPECT_NE(errorOf("kept-classes", "2,x").find("--kept-classes"), std::string::npos);
  EXPECT_NE(errorOf("kept-classes", "2,256").find("in 0-255"), std::string::npos);
  EXPECT_NE(errorOf("exclude", "a,,b").find("--exclude"), std::string::npos);
  const std::string date = errorOf("from", "1905-13");
  EXPECT_NE(date.find("--from: expected an ISO 8601 date"), std::string::npos) << date;
  EXPECT_NE(date.find("'1905-13'"), std::string::npos);
  EXPECT_NE(errorOf("sigma", "nan").find("--sigma"), std::string::npos);
  EXPECT_NE(errorOf("no-such-setting", "1").find("unknown setting 'no-such-setting'"), std::string::npos);

  // --from after --to: an empty window, refused; the settings keep the valid end.
  RenderSettings s;
  setFromText(s, "to", "1900");
  try {
    setFromText(s, "from", "1910");
    ADD_FAILURE() << "an empty time window was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("is after --to"), std::string::npos) << e.what();
  }
  EXPECT_EQ(toText(s, "from"), "");
  EXPECT_EQ(toText(s, "to"), "1900-12-31");
}

TEST(SettingsSchema, JsonListsEverySettingWithItsValue) {
  RenderSettings current;
  current.blend.k = 5;
  const auto j = nlohmann::json::parse(settingsJson(current));
  ASSERT_EQ(j.size(), settingsSchema().size());
  for (size_t i = 0; i < j.size(); ++i) {
    const Setting& s = settingsSchema()[i];
    EXPECT_EQ(j[i]["name"], s.name);
    EXPECT_EQ(j[i]["type"], typeName(s.type));
    EXPECT_EQ(j[i]["default"], defaultText(s));
    EXPECT_EQ(j[i]["live"], s.apply == SettingApply::Live);
    EXPECT_EQ(j[i]["help"], s.help);
  }
  EXPECT_EQ(j[0]["name"], "k");
  EXPECT_EQ(j[0]["value"], "5");
  EXPECT_EQ(j[0]["default"], "8");
  EXPECT_EQ(j[0]["max"], nullptr);  // unbounded
}

TEST(SettingsSchema, MarkdownHasARowPerSetting) {
  const std::string md = settingsMarkdown();
  for (const Setting& s : settingsSchema()) {
    const std::string option = s.type == SettingType::Bool ? "| `--[no-]" + s.name + "` |" : "| `--" + s.name + "` |";
    EXPECT_NE(md.find(option), std::string::npos) << s.name;
  }
  for (const std::string& group : settingGroups()) EXPECT_NE(md.find("**" + group + "**"), std::string::npos);
}

}  // namespace
}  // namespace hv::render
