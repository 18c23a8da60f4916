// The render settings' widgets in the viewer's panel, made from the settings schema
// (render/settings_schema.h): a checkbox per boolean, a slider over the entry's usual span (with
// an "auto" box where the renderer derives the value), a combo of the spellings, a colour editor,
// and a text field (applied on Enter) for lists and dates. Live settings apply from the next frame;
// a setting read when the renderer is made asks for a new renderer once its edit is finished.
#pragma once

#include "hv/render/settings_schema.h"

#include <functional>
#include <map>
#include <optional>
#include <string>

namespace hv::viewer {

class SettingsPanel {
 public:
  struct Result {
    bool changed = false;                           // a live setting changed
    std::optional<render::RenderSettings> rebuild;  // a new renderer with these settings
    std::string error;                              // a text field's value was refused
  };
  // Draws the widgets of the settings of `group` for `settings` (the renderer's). `disabled`:
  // settings the scene has no use for (a geometry layer it lacks), drawn greyed out.
  void drawGroup(const std::string& group, render::RenderSettings& settings, Result& result,
                 const std::function<bool(const render::Setting&)>& disabled = {});

 private:
  // Edits `target`; true when it changed. `committed`: the edit is finished (a slider released).
  bool widget(const render::Setting& s, render::RenderSettings& target, bool& committed, std::string& error);

  std::map<std::string, std::string> text_;  // text fields being edited, by setting name
  render::RenderSettings staged_;            // the settings read at construction, while edited
  std::string editing_;                      // the one being edited in staged_ ("" for none)
};

}  // namespace hv::viewer
