// The render settings on the command line (session/session.cpp addViewOptions, renderSettings) and in
// the README (`histoview settings --markdown`): every entry of render/settings_schema.h reaches
// them.
#include "hv/session/session.h"
#include "hv/app/settings_command.h"
#include "hv/render/settings_schema.h"

#include <CLI/CLI.hpp>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <sstream>

namespace hv::app {
namespace {

const std::string kExistingFile = std::string(HV_SOURCE_DIR) + "/README.md";  // the scene argument

// Parses `args` (after the scene) as a subcommand with the view options; returns the settings.
render::RenderSettings parse(const std::vector<std::string>& args) {
  CLI::App app;
  ViewOptions o;
  addViewOptions(app, o, false);
  std::vector<std::string> argv{kExistingFile};
  argv.insert(argv.end(), args.begin(), args.end());
  std::vector<std::string> reversed(argv.rbegin(), argv.rend());  // CLI11 reads a reversed vector
  app.parse(reversed);
  return renderSettings(o);
}

std::string parseError(const std::vector<std::string>& args) {
  try {
    parse(args);
  } catch (const CLI::ParseError& e) {
    return e.what();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

// A valid text other than the default (the form toText writes back).
std::string otherText(const render::Setting& s) {
  using render::SettingType;
  const std::string def = render::defaultText(s);
  switch (s.type) {
    case SettingType::Bool: return def == "true" ? "false" : "true";
    case SettingType::Int: return std::to_string(std::stoll(def) + (double(std::stoll(def) + 1) <= s.max ? 1 : -1));
    case SettingType::Double:
      if (s.autoValue) return "0.5";
      if (s.max < 3.5) return def == "0.25" ? "0.125" : "0.25";  // a setting in [0, 1]
      return def == "2.5" ? "3.5" : "2.5";
    case SettingType::Enum: return s.spellings.front() == def ? s.spellings.back() : s.spellings.front();
    case SettingType::IntList: return "3,4";
    case SettingType::TextList: return "a,b";
    case SettingType::Colour: return "10,20,30";
    case SettingType::Date: return "1905-06-01";
  }
  return "";
}

TEST(ViewOptions, EveryRenderSettingIsACommandLineOption) {
  CLI::App app;
  ViewOptions o;
  addViewOptions(app, o, false);
  for (const render::Setting& s : render::settingsSchema()) {
    EXPECT_NO_THROW(app.get_option("--" + s.name)) << s.name;
    if (s.type == render::SettingType::Bool) EXPECT_NO_THROW(app.get_option("--no-" + s.name)) << s.name;
  }
  // And each one, given, reaches the RenderSettings.
  for (const render::Setting& s : render::settingsSchema()) {
    const std::string text = otherText(s);
    const std::vector<std::string> args =
        s.type == render::SettingType::Bool
            ? std::vector<std::string>{text == "true" ? "--" + s.name : "--no-" + s.name}
            : std::vector<std::string>{"--" + s.name, text};
    EXPECT_EQ(render::toText(parse(args), s.name), text) << s.name;
  }
}

TEST(ViewOptions, WithoutOptionsTheSettingsAreTheDefaults) {
  const render::RenderSettings s = parse({});
  for (const render::Setting& setting : render::settingsSchema())
    EXPECT_EQ(render::toText(s, setting.name), render::defaultText(setting)) << setting.name;
}

TEST(ViewOptions, TheOptionsOfEarlierVersionsKeepTheirMeaning) {
  const render::RenderSettings s =
      parse({"--k", "4", "--no-masks", "--no-distortion", "--hide", "terrain,mesh", "--no-points-in-depth-maps",
             "--no-eye-dome", "--kept-classes", "2,6", "--exclude", "a,b", "--from", "1905", "--to", "1910",
             "--background", "255,0,0", "--points", "--point-filter", "epsilon", "--sprite-form", "mat3",
             "--binding", "naive", "--frusta", "--mesh-offset", "0.25", "--dated-only", "--hide-transient"});
  EXPECT_EQ(s.blend.k, 4);
  EXPECT_FALSE(s.blend.masks);
  EXPECT_FALSE(s.layers.lensDistortion);
  EXPECT_FALSE(s.layers.terrain);
  EXPECT_TRUE(s.layers.buildings);
  EXPECT_FALSE(s.layers.mesh);
  EXPECT_FALSE(s.points.keptInDepthMaps);
  EXPECT_FALSE(s.points.eyeDome);
  EXPECT_EQ(s.points.keptClasses, (std::vector<int>{2, 6}));
  EXPECT_EQ(s.blend.exclude, (std::vector<std::string>{"a", "b"}));
  ASSERT_TRUE(s.blend.window);
  EXPECT_EQ(s.blend.window->first, daysFromCivil(1905, 1, 1));
  EXPECT_EQ(s.blend.window->last, daysFromCivil(1910, 12, 31));
  EXPECT_EQ(s.background, glm::dvec3(1.0, 0.0, 0.0));
  EXPECT_TRUE(s.points.enabled);
  EXPECT_EQ(s.points.filter, render::PointFilter::Epsilon);
  EXPECT_EQ(s.points.form, render::SpriteForm::Mat3);
  EXPECT_EQ(s.binding, render::Binding::Naive);
  EXPECT_TRUE(s.debug.frusta);
  EXPECT_EQ(s.points.meshOffset, 0.25);
  EXPECT_TRUE(s.blend.datedOnly);
  EXPECT_TRUE(s.points.hideTransient);
  // Repeated list options add up, as before.
  EXPECT_EQ(parse({"--exclude", "a", "--exclude", "b"}).blend.exclude, (std::vector<std::string>{"a", "b"}));
}

TEST(ViewOptions, AGivenBackgroundColourReplacesTheSkyUnlessTheSkyIsAskedFor) {
  const render::RenderSettings byDefault = parse({});
  EXPECT_TRUE(byDefault.untextured.sky);
  EXPECT_TRUE(byDefault.untextured.shading);
  const render::RenderSettings given = parse({"--background", "0,0,0"});
  EXPECT_FALSE(given.untextured.sky);
  EXPECT_TRUE(given.untextured.shading);  // surfaces stay shaded: --no-shading for the flat colour there
  EXPECT_TRUE(parse({"--background", "10,20,30", "--sky"}).untextured.sky);
  const render::RenderSettings off =
      parse({"--no-shading", "--no-sky", "--sun-azimuth", "90", "--sun-elevation", "30"});
  EXPECT_FALSE(off.untextured.shading);
  EXPECT_FALSE(off.untextured.sky);
  EXPECT_EQ(off.untextured.sunAzimuthDeg, 90.0);
  EXPECT_EQ(off.untextured.sunElevationDeg, 30.0);
  EXPECT_NE(parseError({"--sun-elevation", "95"}).find("0-90"), std::string::npos);
}

TEST(ViewOptions, BadValuesAreRefusedNamingTheOptionAndTheExpectation) {
  const std::string k = parseError({"--k", "0"});
  EXPECT_NE(k.find("--k"), std::string::npos) << k;
  EXPECT_NE(k.find("a whole number >= 1"), std::string::npos) << k;
  const std::string filter = parseError({"--point-filter", "classes"});
  EXPECT_NE(filter.find("one of auto, class, epsilon, none"), std::string::npos) << filter;
  EXPECT_NE(parseError({"--depth-size", "8"}).find("16-16384"), std::string::npos);
  EXPECT_NE(parseError({"--from", "1905-13"}).find("ISO 8601"), std::string::npos);
  EXPECT_NE(parseError({"--from", "1910", "--to", "1900"}).find("is after --to"), std::string::npos);
  EXPECT_NE(parseError({"--background", "1,2"}).find("R,G,B"), std::string::npos);
  EXPECT_NE(parseError({"--kept-classes", "2,x"}).find("whole numbers"), std::string::npos);
  EXPECT_NE(parseError({"--hide", "roofs"}).find("--hide"), std::string::npos);
}

TEST(SettingsCommand, JsonHasEverySettingForThePage) {
  const auto j = nlohmann::json::parse(settingsCommandOutput(true));
  ASSERT_EQ(j.size(), render::settingsSchema().size());
  for (size_t i = 0; i < j.size(); ++i) EXPECT_EQ(j[i]["name"], render::settingsSchema()[i].name);
}

// The README's option table is the command's output, so the documentation cannot drift from the
// schema: after a change, paste `histoview settings --markdown` between the markers.
TEST(SettingsCommand, TheReadmeTableIsTheCommandsOutput) {
  std::ifstream in(std::string(HV_SOURCE_DIR) + "/README.md");
  ASSERT_TRUE(in) << "README.md not found";
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string readme = buffer.str(), begin = "<!-- settings:begin -->\n", end = "<!-- settings:end -->";
  const size_t b = readme.find(begin), e = readme.find(end);
  ASSERT_NE(b, std::string::npos) << "README.md has no " << begin;
  ASSERT_NE(e, std::string::npos) << "README.md has no " << end;
  ASSERT_LT(b, e);
  EXPECT_EQ(readme.substr(b + begin.size(), e - b - begin.size()), settingsCommandOutput(false))
      << "README.md's settings table differs from `histoview settings --markdown`: paste the command's output "
         "between the markers";
}

}  // namespace
}  // namespace hv::app
