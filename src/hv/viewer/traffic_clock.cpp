#include "hv/viewer/traffic_clock.h"

#include <algorithm>
#include <cmath>

namespace hv::viewer {

TrafficClock::TrafficClock(double begin, double end)
    : begin_(std::min(begin, end)), end_(std::max(begin, end)), time_(std::min(begin, end)) {}

void TrafficClock::seek(double t) {
  if (std::isfinite(t)) time_ = std::clamp(t, begin_, end_);
}

void TrafficClock::seekPosition(double position) {
  if (!std::isfinite(position)) return;
  seek(begin_ + std::clamp(position, 0.0, 1.0) * (end_ - begin_));
}

double TrafficClock::position() const { return end_ > begin_ ? (time_ - begin_) / (end_ - begin_) : 0.0; }

void TrafficClock::play() {
  if (!(end_ > begin_)) return;
  if (time_ >= end_) time_ = begin_;
  playing_ = true;
}

bool TrafficClock::step(double seconds, const TrafficPlaySettings& settings) {
  if (!playing_ || !(seconds > 0.0) || !(settings.rate > 0.0) || !std::isfinite(seconds * settings.rate)) return false;
  const double before = time_;
  const double t = time_ + seconds * settings.rate;
  if (t < end_) {
    time_ = t;
  } else if (settings.loop) {
    time_ = begin_ + std::fmod(t - begin_, end_ - begin_);
  } else {
    time_ = end_;
    playing_ = false;
  }
  return time_ != before;
}

}  // namespace hv::viewer
