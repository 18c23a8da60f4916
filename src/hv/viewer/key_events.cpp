#include "hv/viewer/key_events.h"

#include <cstdio>
#include <stdexcept>

namespace hv::viewer {

void KeyEvents::event(int key, bool down) {
  State& s = keys_[key];
  if (down && !s.down) ++s.presses;
  s.down = down;
}

int KeyEvents::presses(int key) const {
  const auto it = keys_.find(key);
  return it == keys_.end() ? 0 : it->second.presses;
}

bool KeyEvents::held(int key) const {
  const auto it = keys_.find(key);
  return it != keys_.end() && (it->second.down || it->second.presses > 0);
}

void KeyEvents::endFrame() {
  for (auto it = keys_.begin(); it != keys_.end();) {
    it->second.presses = 0;
    it = it->second.down ? std::next(it) : keys_.erase(it);
  }
}

void KeyEvents::releaseAll() {
  for (auto& [key, s] : keys_) s.down = false;
}

std::string nextNumberedName(const std::string& path, const std::function<bool(const std::string&)>& exists) {
  const size_t slash = path.find_last_of('/');
  const size_t dot = path.find_last_of('.');
  const size_t nameStart = slash == std::string::npos ? 0 : slash + 1;
  const bool hasExt = dot != std::string::npos && dot > nameStart;  // ".hidden" is a name, not an extension
  const std::string stem = hasExt ? path.substr(0, dot) : path, ext = hasExt ? path.substr(dot) : "";
  for (int n = 1; n < 1000000; ++n) {
    char number[16];
    std::snprintf(number, sizeof number, "-%03d", n);
    const std::string name = stem + number + ext;
    if (!exists(name)) return name;
  }
  throw std::runtime_error("no free name left in the series " + stem + "-NNN" + ext);
}

}  // namespace hv::viewer
