// The viewer panel's Traffic section (docs/traffic.md, "Playing the traffic"): play/pause (key Y)
// and a time slider over the trajectories' span, the speed and loop, and how many vehicles are on
// the road. The clock is hv/viewer/traffic_clock.h; this draws it and writes its time into the
// render setting `time` (RenderSettings::traffic.time).
#pragma once

#include "hv/render/settings.h"
#include "hv/scene/scene.h"
#include "hv/viewer/traffic_clock.h"

#include <memory>

namespace hv {
struct Trajectories;
}

namespace hv::viewer {

class TrafficPanel {
 public:
  // The clock over the scene's trajectories (none: the section says so and Y does nothing), at
  // the settings' time.
  TrafficPanel(const Scene& scene, const render::RenderSettings& settings);

  bool present() const;
  TrafficClock& clock() { return clock_; }
  TrafficPlaySettings& play() { return play_; }

  // Y: play from the settings' time, or pause.
  void toggle(const render::RenderSettings& settings);
  // Advances a playing clock by `seconds` of wall time; true when it moved the settings' time.
  bool step(double seconds, render::RenderSettings& settings);
  // Vehicles on the road (between their first and last sample) at `time`.
  int vehiclesAt(double time) const;

  // The section's rows; true when the settings' time changed.
  bool draw(render::RenderSettings& settings);

 private:
  std::shared_ptr<const Trajectories> traffic_;
  TrafficClock clock_;
  TrafficPlaySettings play_;
};

}  // namespace hv::viewer
