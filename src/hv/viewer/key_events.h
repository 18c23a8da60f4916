// Keyboard input as events, not as the state at frame time. A window system reports each press
// and release as it happens (GLFW's key callback, the page's keydown/keyup); a viewer that only
// looks at which keys are down once per frame loses every tap shorter than a frame, and at the
// low frame rates of a software renderer (4 fps: 250 ms frames) that is most taps. KeyEvents
// keeps what happened between two frames: a toggle fires once per press however short, and a
// movement key tapped between two frames still moves for one frame. Plain C++: key codes are the
// window system's integers.
#pragma once

#include <string>
#include <unordered_map>
#include <functional>

namespace hv::viewer {

class KeyEvents {
 public:
  // A key went down (`down`) or up. Repeats (a key held down) are not presses.
  void event(int key, bool down);

  // During a frame: how many times `key` went down since the previous endFrame().
  int presses(int key) const;
  bool pressed(int key) const { return presses(key) > 0; }
  // Down now, or pressed since the previous endFrame() (a tap moves for one frame).
  bool held(int key) const;

  // The frame consumed the events: presses start again from zero.
  void endFrame();
  // The window lost the focus: every key is up (no key left stuck down).
  void releaseAll();

 private:
  struct State {
    bool down = false;
    int presses = 0;
  };
  std::unordered_map<int, State> keys_;
};

// The first free name in the numbered series of `path`: "shot.png" gives "shot-001.png", then
// "shot-002.png"… skipping every name `exists` reports taken (so screenshots never overwrite one
// another). A path without an extension gets the number at its end.
std::string nextNumberedName(const std::string& path, const std::function<bool(const std::string&)>& exists);

}  // namespace hv::viewer
