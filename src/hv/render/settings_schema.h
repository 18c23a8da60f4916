// The renderer's user-facing settings as data: every field of RenderSettings that a person may
// set is declared once here — its name, type, range or spellings, unit, one line of help, whether
// it applies live or needs a new renderer — with accessors that read and write it on a
// RenderSettings. Defaults are not written here: they are a default-constructed RenderSettings's.
// The command line (session/session.cpp), the desktop viewer's panel, the browser's generic setter
// (apps/web/hv_web.cpp, web/histoview.js) and the README's option table (`histoview settings
// --markdown`) are all driven by this one table, so a new setting is one RenderSettings field
// plus one entry in settingsSchema() (settings_schema.cpp).
#pragma once

#include "hv/render/settings.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

namespace hv::render {

enum class SettingType {
  Bool,      // text: true | false (also on/off, yes/no, 1/0); on the command line --NAME / --no-NAME
  Int,       // a whole number within [min, max]
  Double,    // a number within the range; "auto" where autoValue is set
  Enum,      // one of `spellings`
  IntList,   // comma-separated whole numbers, each within [min, max]; "" for none
  TextList,  // comma-separated words (each one of `spellings` when there are any); "" for none
  Colour,    // R,G,B with components in 0-255 (stored in [0, 1])
  Date,      // an ISO 8601 date (hv/util/dates.h), or "" for an open end
};

// When a change reaches the picture.
enum class SettingApply {
  Live,    // from the next frame (Renderer::settings())
  Reload,  // read when the renderer is made: a viewer makes a new one
};

// A setting's value. Bool, Int (whole numbers of any width), Double; Enum and Date: the text
// (spelling, "YYYY-MM-DD" or ""); IntList; TextList; Colour in [0, 1].
using SettingValue = std::variant<bool, std::int64_t, double, std::string, std::vector<std::int64_t>,
                                  std::vector<std::string>, glm::dvec3>;

struct Setting {
  std::string name;   // as on the command line without "--": "k", "depth-size", "point-filter"
  SettingType type = SettingType::Bool;
  std::string group;  // the panel section and the README table's heading: "Blending", "Points", ...
  std::string help;   // one line
  std::string unit;   // "scene units", "px", "ms", "MiB"; "" when the value has none
  SettingApply apply = SettingApply::Live;
  // Int, Double (and the items of an IntList): the accepted range, inclusive unless minExclusive.
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool minExclusive = false;
  // Sliders (viewer, page): the usual span within the range, and whether it is logarithmic.
  double sliderMin = 0.0, sliderMax = 1.0;
  bool logarithmic = false;
  // Double: the text "auto" stands for this value (which the renderer replaces by one derived
  // from the scene, e.g. its extent); such settings accept it outside the range.
  std::optional<double> autoValue;
  std::vector<std::string> spellings;  // Enum: its values in order; TextList: the allowed items
  std::function<SettingValue(const RenderSettings&)> get;
  // Writes a value already checked against the type and range (parseSettingValue); throws
  // std::invalid_argument when it conflicts with another setting (--from after --to).
  std::function<void(RenderSettings&, const SettingValue&)> set;
};

// Every user-facing setting, grouped (entries of a group are contiguous), in the order panels
// and the README show them and the command line applies them.
const std::vector<Setting>& settingsSchema();
// The group names in order of first appearance.
std::vector<std::string> settingGroups();
// nullptr when no setting has that name.
const Setting* findSetting(std::string_view name);
// Throws std::invalid_argument naming the unknown setting.
const Setting& setting(std::string_view name);

// What the setting accepts, for messages and help: "a whole number >= 1", "one of array, naive".
std::string expectedText(const Setting& s);
// Text -> value, checked. Throws std::invalid_argument "--NAME: expected ..., got 'TEXT'".
SettingValue parseSettingValue(const Setting& s, const std::string& text);
// Value -> text, the form parseSettingValue reads back to the same value.
std::string settingValueText(const Setting& s, const SettingValue& value);

// Sets one setting from text (parse, check, write); throws std::invalid_argument naming the
// option, the text and what was expected, or the unknown name.
void setFromText(RenderSettings& settings, std::string_view name, const std::string& text);
std::string toText(const RenderSettings& settings, std::string_view name);
// The default as text: a default-constructed RenderSettings's value.
std::string defaultText(const Setting& s);

// "bool", "int", "double", "enum", "int-list", "text-list", "colour", "date".
const char* typeName(SettingType type);

// The schema as a JSON array for the browser page and `histoview settings --json`: per setting
// name, type, group, help, unit, live, min/max (null when unbounded), minExclusive, sliderMin,
// sliderMax, logarithmic, auto, spellings, default and the value in `current`.
std::string settingsJson(const RenderSettings& current);
// The README's option table (`histoview settings --markdown`): one table per group.
std::string settingsMarkdown();

}  // namespace hv::render
