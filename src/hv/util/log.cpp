#include "hv/util/log.h"

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <mutex>
#include <set>

namespace hv::log {
namespace {

Level levelFromEnv() {
  const char* v = std::getenv("HV_LOG");
  if (!v) return Level::Info;
  if (!std::strcmp(v, "debug")) return Level::Debug;
  if (!std::strcmp(v, "warn")) return Level::Warn;
  if (!std::strcmp(v, "error")) return Level::Error;
  if (!std::strcmp(v, "off")) return Level::Off;
  return Level::Info;
}

std::atomic<Level>& current() {
  static std::atomic<Level> l{levelFromEnv()};
  return l;
}

// Warnings and errors are printed once per run (each distinct message): a cause met again on every view or frame (a capped
// K, a photograph that will not decode) would otherwise bury the rest of the output.
void emit(Level l, const char* tag, const std::string& message) {
  if (l < current().load()) return;
  static std::mutex m;
  static std::set<std::string> printed;
  std::lock_guard lock(m);
  if (l >= Level::Warn && !printed.insert(std::string(tag) + message).second) return;
  std::cerr << tag << message << '\n';
}

}  // namespace

void setLevel(Level l) { current().store(l); }
Level level() { return current().load(); }
void debug(const std::string& m) { emit(Level::Debug, "debug: ", m); }
void info(const std::string& m) { emit(Level::Info, "", m); }
void warn(const std::string& m) { emit(Level::Warn, "warning: ", m); }
void error(const std::string& m) { emit(Level::Error, "error: ", m); }

}  // namespace hv::log
