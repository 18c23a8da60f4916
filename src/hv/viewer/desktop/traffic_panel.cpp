#include "hv/viewer/desktop/traffic_panel.h"

#include "hv/traffic/trajectories.h"

#include <imgui.h>

namespace hv::viewer {

TrafficPanel::TrafficPanel(const Scene& scene, const render::RenderSettings& settings) : traffic_(scene.traffic) {
  if (present()) clock_ = TrafficClock(traffic_->tBegin, traffic_->tEnd);
  clock_.seek(settings.traffic.time);
}

bool TrafficPanel::present() const { return traffic_ && !traffic_->vehicles.empty(); }

void TrafficPanel::toggle(const render::RenderSettings& settings) {
  if (!clock_.playing()) clock_.seek(settings.traffic.time);  // the settings panel may have moved it
  clock_.toggle();
}

bool TrafficPanel::step(double seconds, render::RenderSettings& settings) {
  if (!clock_.step(seconds, play_)) return false;
  settings.traffic.time = clock_.time();
  return true;
}

int TrafficPanel::vehiclesAt(double time) const {
  int n = 0;
  if (traffic_)
    for (const Trajectory& v : traffic_->vehicles) n += sampleTrajectory(v, time).has_value();
  return n;
}

bool TrafficPanel::draw(render::RenderSettings& settings) {
  if (!present()) {
    ImGui::TextDisabled("no traffic in this scene (scene.json \"traffic\")");
    return false;
  }
  bool changed = false;
  if (!clock_.playing()) clock_.seek(settings.traffic.time);
  if (ImGui::Button(clock_.playing() ? "pause (Y)" : "play (Y)")) toggle(settings);
  ImGui::SameLine();
  float t = float(clock_.time());
  if (ImGui::SliderFloat("time (s)", &t, float(clock_.begin()), float(clock_.end()), "%.1f")) {
    clock_.seek(t);
    settings.traffic.time = clock_.time();
    changed = true;
  }
  float rate = float(play_.rate);
  if (ImGui::SliderFloat("speed (x)", &rate, 0.1f, 20.0f, "%.2f", ImGuiSliderFlags_Logarithmic) && rate > 0.0f)
    play_.rate = rate;
  ImGui::SameLine();
  ImGui::Checkbox("loop", &play_.loop);
  ImGui::Text("%d of %zu vehicles on the road at %.1f s (%.1f .. %.1f s)%s", vehiclesAt(clock_.time()),
              traffic_->vehicles.size(), clock_.time(), clock_.begin(), clock_.end(),
              settings.traffic.enabled ? "" : "; the traffic is switched off");
  return changed;
}

}  // namespace hv::viewer
