// The viewer panel's Timeline section (docs/viewer.md): the photographs' dates as a histogram
// under a slider, the time window (the render settings `from`/`to`) dragged by either end or as a
// whole, "play" walking it through time, and the undated photographs listed apart. The arithmetic
// is hv/viewer/timeline.h; this draws it and writes the window into the render settings.
#pragma once

#include "hv/render/settings.h"
#include "hv/scene/scene.h"
#include "hv/viewer/timeline.h"

#include <string>

namespace hv::viewer {

class TimelinePanel {
 public:
  explicit TimelinePanel(const Scene& scene);

  const PhotoDates& dates() const { return dates_; }
  const DateHistogram& histogram() const { return histogram_; }
  const TimelineAxis& axis() const { return axis_; }
  PlaySettings& play() { return play_; }
  TimelinePlayer& player() { return player_; }

  // The window from two slider positions "A:B" (fractions of the axis, 0 <= A <= B <= 1), as the
  // command line's --timeline gives it. Throws std::invalid_argument saying what was expected.
  DateInterval windowAtPositions(const std::string& positions) const;
  // A line on what `window` selects: its days and how many dated photographs it holds.
  std::string describe(const DateInterval& window) const;

  // Starts play from the window in `settings` (a window over the whole timeline becomes its first bar).
  void startPlay(render::RenderSettings& settings);
  // Advances play by `seconds`; true when it moved the window in `settings`.
  bool step(double seconds, render::RenderSettings& settings);

  struct Result {
    bool changed = false;  // the window in the settings changed
    int chosen = -1;       // an undated photograph picked in the list
  };
  Result draw(render::RenderSettings& settings);

 private:
  PhotoDates dates_;
  DateHistogram histogram_;
  TimelineAxis axis_;
  PlaySettings play_;
  TimelinePlayer player_;
  std::vector<std::string> ids_;
  enum class Drag { None, Start, End, Whole } drag_ = Drag::None;
  DateInterval dragBase_;     // the window when the drag began
  std::int64_t dragDay_ = 0;  // the day under the mouse when it began
};

}  // namespace hv::viewer
