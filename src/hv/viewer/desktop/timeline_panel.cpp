#include "hv/viewer/desktop/timeline_panel.h"

#include <imgui.h>

#include <algorithm>
#include <stdexcept>

namespace hv::viewer {

namespace {

std::vector<std::string> photoDates(const Scene& scene) {
  std::vector<std::string> d;
  for (const Photo& p : scene.photos) d.push_back(p.date);
  return d;
}

const char* binName(std::int64_t yearsPerBin) {
  switch (yearsPerBin) {
    case 1:
      return "a bar per year";
    case 10:
      return "a bar per decade";
    case 100:
      return "a bar per century";
    default:
      return "a bar per millennium";
  }
}

}  // namespace

TimelinePanel::TimelinePanel(const Scene& scene)
    : dates_(readPhotoDates(photoDates(scene))), histogram_(dateHistogram(dates_)) {
  const DateInterval days = histogram_.days();
  axis_ = {days.first, days.last};
  for (const Photo& p : scene.photos) ids_.push_back(p.camera.id);
}

DateInterval TimelinePanel::windowAtPositions(const std::string& positions) const {
  const auto [a, b] = parseTimelinePositions(positions);
  if (dates_.dated.empty())
    throw std::invalid_argument("--timeline: no photograph of the scene has a date, so there is no timeline");
  return {axis_.dayAt(a), axis_.dayAt(b)};
}

std::string TimelinePanel::describe(const DateInterval& window) const {
  return formatDay(window.first) + " .. " + formatDay(window.last) + ": " +
         std::to_string(countInWindow(dates_, window)) + " of " + std::to_string(dates_.dated.size()) +
         " dated photographs";
}

void TimelinePanel::startPlay(render::RenderSettings& settings) {
  DateInterval w = windowOnAxis(settings.blend.window, axis_);
  const DateInterval firstBar =
      histogram_.counts.empty() ? DateInterval{axis_.first, axis_.last} : histogram_.binDays(0);
  player_.start(w, axis_, firstBar.last - firstBar.first + 1);
  settings.blend.window = w;
}

bool TimelinePanel::step(double seconds, render::RenderSettings& settings) {
  if (!player_.playing()) return false;
  DateInterval w = windowOnAxis(settings.blend.window, axis_);
  if (!player_.step(w, axis_, seconds, play_)) return false;
  settings.blend.window = w;
  return true;
}

TimelinePanel::Result TimelinePanel::draw(render::RenderSettings& settings) {
  Result result;
  if (!dates_.dated.empty()) {
    const DateInterval shown = windowOnAxis(settings.blend.window, axis_);
    const float width = std::max(60.0f, ImGui::GetContentRegionAvail().x), height = 56.0f;
    const ImVec2 p0 = ImGui::GetCursorScreenPos();
    ImGui::InvisibleButton("##timeline", ImVec2(width, height));
    const bool active = ImGui::IsItemActive(), activated = ImGui::IsItemActivated(), hovered = ImGui::IsItemHovered();
    ImDrawList* dl = ImGui::GetWindowDrawList();
    auto xOf = [&](std::int64_t day) { return p0.x + float(axis_.positionOf(day)) * width; };
    dl->AddRectFilled(p0, ImVec2(p0.x + width, p0.y + height), IM_COL32(28, 28, 32, 255));
    // The histogram: a bar per bin, bright where the bin meets the window.
    const int most = std::max(1, *std::max_element(histogram_.counts.begin(), histogram_.counts.end()));
    for (int i = 0; i < int(histogram_.counts.size()); ++i) {
      const DateInterval bin = histogram_.binDays(i);
      const float x0 = xOf(bin.first), x1 = i + 1 < int(histogram_.counts.size()) ? xOf(bin.last + 1) : p0.x + width;
      const float h = (height - 14.0f) * float(histogram_.counts[size_t(i)]) / float(most);
      const ImU32 colour = overlaps(bin, shown) ? IM_COL32(230, 170, 60, 255) : IM_COL32(110, 110, 120, 255);
      if (h > 0.0f) dl->AddRectFilled(ImVec2(x0 + 1.0f, p0.y + height - h), ImVec2(x1 - 1.0f, p0.y + height), colour);
    }
    // The window: a translucent band with a handle at each end.
    const float xa = xOf(shown.first), xb = std::max(xOf(shown.last), xa + 1.0f);
    dl->AddRectFilled(ImVec2(xa, p0.y), ImVec2(xb, p0.y + height), IM_COL32(120, 180, 255, 50));
    dl->AddRectFilled(ImVec2(xa - 2.0f, p0.y), ImVec2(xa + 1.0f, p0.y + height), IM_COL32(120, 180, 255, 255));
    dl->AddRectFilled(ImVec2(xb - 1.0f, p0.y), ImVec2(xb + 2.0f, p0.y + height), IM_COL32(120, 180, 255, 255));
    const float mouseX = ImGui::GetIO().MousePos.x;
    const std::int64_t day = axis_.dayAt((mouseX - p0.x) / width);
    if (activated) {
      // Within 6 pixels of a handle: that end (the nearer one); inside the band: the whole
      // window; elsewhere the nearer end jumps there.
      const float da = std::abs(mouseX - xa), db = std::abs(mouseX - xb);
      if (std::min(da, db) <= 6.0f)
        drag_ = da < db ? Drag::Start : Drag::End;
      else if (mouseX > xa && mouseX < xb)
        drag_ = Drag::Whole;
      else
        drag_ = da < db ? Drag::Start : Drag::End;
      dragBase_ = shown;
      dragDay_ = day;
      player_.stop();
    }
    if (active && drag_ != Drag::None) {
      DateInterval w = shown;
      if (drag_ == Drag::Start) w = moveWindowStart(shown, day, axis_);
      if (drag_ == Drag::End) w = moveWindowEnd(shown, day, axis_);
      if (drag_ == Drag::Whole) w = shiftWindow(dragBase_, day - dragDay_, axis_);
      if (w != shown || !settings.blend.window) {
        settings.blend.window = w;
        result.changed = true;
      }
    } else if (!active) {
      drag_ = Drag::None;
    }
    if (hovered && !active) ImGui::SetTooltip("%s", formatDay(day).c_str());
    const std::string first = formatDay(axis_.first).substr(0, 4), last = formatDay(axis_.last).substr(0, 4);
    ImGui::Text("%s", first.c_str());
    ImGui::SameLine(std::max(0.0f, width - ImGui::CalcTextSize(last.c_str()).x));
    ImGui::Text("%s", last.c_str());
    const DateInterval now = windowOnAxis(settings.blend.window, axis_);
    ImGui::TextWrapped("%s%s (%s)", describe(now).c_str(), settings.blend.window ? "" : ", no window set",
                       binName(histogram_.yearsPerBin));

    if (ImGui::Button(player_.playing() ? "pause" : "play")) {
      if (player_.playing()) {
        player_.stop();
      } else {
        startPlay(settings);
        result.changed = true;
      }
    }
    ImGui::SameLine();
    float speed = float(play_.yearsPerSecond);
    ImGui::SetNextItemWidth(120.0f);
    if (ImGui::SliderFloat("years/s", &speed, 0.1f, 100.0f, "%.1f", ImGuiSliderFlags_Logarithmic))
      play_.yearsPerSecond = speed;
    ImGui::SameLine();
    ImGui::Checkbox("loop", &play_.loop);
    ImGui::SameLine();
    if (ImGui::Button("all")) {
      player_.stop();
      settings.blend.window.reset();
      result.changed = true;
    }
  } else {
    ImGui::TextDisabled("no photograph has a date");
  }
  // Undated photographs pass any window unless dated-only.
  if (!dates_.undated.empty()) {
    const std::string label = std::to_string(dates_.undated.size()) + " undated photograph" +
                              (dates_.undated.size() == 1 ? "" : "s") +
                              (settings.blend.datedOnly ? " (left out: dated-only)" : " (shown in any window)");
    if (ImGui::TreeNode("undated", "%s", label.c_str())) {
      for (int i : dates_.undated)
        if (ImGui::Selectable(ids_[size_t(i)].c_str())) result.chosen = i;
      ImGui::TreePop();
    }
  }
  return result;
}

}  // namespace hv::viewer
