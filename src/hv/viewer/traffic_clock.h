// The traffic's clock in the viewers (docs/traffic.md, "Playing the traffic"): the time of the
// render setting `time` (seconds on the simulation's clock, hv/traffic/trajectories.h) moved by
// play/pause at a rate of simulated seconds per wall-clock second, or set by a slider. Plain
// arithmetic, shared by the desktop viewer's panel and the page; the viewers write time() into the
// render settings.
//
// Conventions: the clock runs over the trajectories' span [begin, end] (their first and last
// sample); a slider position is a fraction of it (0 begin, 1 end). Time never leaves the span.
#pragma once

namespace hv::viewer {

struct TrafficPlaySettings {
  double rate = 1.0;  // simulated seconds per second of wall time (> 0)
  bool loop = true;   // at the end: start again from the beginning (else stop there)
};

class TrafficClock {
 public:
  TrafficClock() = default;
  // A clock over [begin, end] (swapped when given the wrong way round), at begin, paused.
  TrafficClock(double begin, double end);

  double begin() const { return begin_; }
  double end() const { return end_; }
  double time() const { return time_; }
  bool playing() const { return playing_; }

  // Moves to `t`, clamped to the span (a non-finite t is ignored).
  void seek(double t);
  // The slider: position in [0, 1] (clamped) <-> time.
  void seekPosition(double position);
  double position() const;

  // Starts playing; a clock at its end starts again from the beginning. A span of zero length
  // (one instant) has nothing to play: the clock stays paused.
  void play();
  void pause() { playing_ = false; }
  void toggle() { playing_ ? pause() : play(); }

  // Advances a playing clock by `seconds` of wall time x rate; returns true when the time moved.
  // Reaching the end stops there or (loop) carries on from the beginning, the overshoot kept.
  bool step(double seconds, const TrafficPlaySettings& settings);

 private:
  double begin_ = 0.0, end_ = 0.0, time_ = 0.0;
  bool playing_ = false;
};

}  // namespace hv::viewer
