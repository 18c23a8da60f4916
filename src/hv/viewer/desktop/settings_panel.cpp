#include "hv/viewer/desktop/settings_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>

namespace hv::viewer {

namespace {

using render::Setting;
using render::SettingType;

std::string tooltip(const Setting& s) {
  std::string t = "--" + s.name + ": " + s.help;
  if (!s.unit.empty()) t += " (" + s.unit + ")";
  t += "\ndefault " + (render::defaultText(s).empty() ? std::string("none") : render::defaultText(s));
  if (s.apply == render::SettingApply::Reload) t += "; changing it makes a new renderer";
  return t;
}

// The slider's span within the accepted range.
void sliderSpan(const Setting& s, double& lo, double& hi) {
  lo = std::max(s.sliderMin, s.min);
  hi = std::min(s.sliderMax, s.max);
}

}  // namespace

bool SettingsPanel::widget(const Setting& s, render::RenderSettings& target, bool& committed, std::string& error) {
  const char* label = s.name.c_str();
  const render::SettingValue value = s.get(target);
  bool changed = false;
  ImGuiSliderFlags flags = ImGuiSliderFlags_AlwaysClamp | (s.logarithmic ? ImGuiSliderFlags_Logarithmic : 0);
  switch (s.type) {
    case SettingType::Bool: {
      bool v = std::get<bool>(value);
      if (ImGui::Checkbox(label, &v)) s.set(target, v), changed = committed = true;
      break;
    }
    case SettingType::Int: {
      double lo, hi;
      sliderSpan(s, lo, hi);
      const std::int64_t ilo = std::int64_t(std::ceil(lo)), ihi = std::int64_t(std::floor(hi));
      std::int64_t v = std::get<std::int64_t>(value);
      if (ImGui::SliderScalar(label, ImGuiDataType_S64, &v, &ilo, &ihi, "%lld", flags)) {
        s.set(target, std::clamp(v, ilo, ihi));
        changed = true;
      }
      committed |= ImGui::IsItemDeactivatedAfterEdit();
      break;
    }
    case SettingType::Double: {
      double lo, hi;
      sliderSpan(s, lo, hi);
      double v = std::get<double>(value);
      ImGui::PushID(label);
      bool isAuto = s.autoValue && v == *s.autoValue;
      if (s.autoValue) {
        if (ImGui::Checkbox("auto", &isAuto)) {
          // Leaving auto starts in the middle of the usual span.
          v = isAuto ? *s.autoValue : s.logarithmic && lo > 0 ? std::sqrt(lo * hi) : 0.5 * (lo + hi);
          s.set(target, v);
          changed = committed = true;
        }
        ImGui::SameLine();
      }
      ImGui::BeginDisabled(isAuto);
      double shown = isAuto ? lo : v;
      if (ImGui::SliderScalar(label, ImGuiDataType_Double, &shown, &lo, &hi, isAuto ? "auto" : "%.3g", flags)) {
        if (s.minExclusive && shown <= s.min) shown = std::nextafter(s.min, hi);
        s.set(target, shown);
        changed = true;
      }
      committed |= ImGui::IsItemDeactivatedAfterEdit();
      ImGui::EndDisabled();
      ImGui::PopID();
      break;
    }
    case SettingType::Enum: {
      const std::string& current = std::get<std::string>(value);
      if (ImGui::BeginCombo(label, current.c_str())) {
        for (const std::string& spelling : s.spellings)
          if (ImGui::Selectable(spelling.c_str(), spelling == current) && spelling != current) {
            s.set(target, spelling);
            changed = committed = true;
          }
        ImGui::EndCombo();
      }
      break;
    }
    case SettingType::Colour: {
      const glm::dvec3 c = std::get<glm::dvec3>(value);
      float rgb[3] = {float(c.r), float(c.g), float(c.b)};
      if (ImGui::ColorEdit3(label, rgb)) {
        s.set(target, glm::dvec3(rgb[0], rgb[1], rgb[2]));
        changed = true;
      }
      committed |= ImGui::IsItemDeactivatedAfterEdit();
      break;
    }
    case SettingType::IntList:
    case SettingType::TextList:
    case SettingType::Date: {
      // Edited as text, applied on Enter (an unfinished date or list is not a value yet).
      char buf[512];
      const std::string text = render::settingValueText(s, value);
      const auto it = text_.find(s.name);
      std::snprintf(buf, sizeof buf, "%s", (it != text_.end() ? it->second : text).c_str());
      if (ImGui::InputText(label, buf, sizeof buf)) text_[s.name] = buf;
      const bool enter = ImGui::IsItemDeactivatedAfterEdit();
      if (!ImGui::IsItemActive() && !enter) text_.erase(s.name);
      if (enter) {
        text_.erase(s.name);
        try {
          s.set(target, render::parseSettingValue(s, buf));
          changed = committed = true;
          error.clear();
        } catch (const std::invalid_argument& e) {
          error = e.what();
        }
      }
      break;
    }
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", tooltip(s).c_str());
  return changed;
}

void SettingsPanel::drawGroup(const std::string& group, render::RenderSettings& settings, Result& result,
                              const std::function<bool(const render::Setting&)>& disabled) {
  for (const Setting& s : render::settingsSchema()) {
    if (s.group != group) continue;
    ImGui::BeginDisabled(disabled && disabled(s));
    bool committed = false;
    if (s.apply == render::SettingApply::Live) {
      result.changed |= widget(s, settings, committed, result.error);
    } else {
      // Edited on a copy until the edit is finished: a new renderer per slider step would be slow.
      if (editing_ != s.name) s.set(staged_, s.get(settings));
      if (widget(s, staged_, committed, result.error)) editing_ = s.name;
      if (committed) {
        render::RenderSettings next = result.rebuild.value_or(settings);
        s.set(next, s.get(staged_));
        result.rebuild = next;
        editing_.clear();
      }
    }
    ImGui::EndDisabled();
  }
}

}  // namespace hv::viewer
