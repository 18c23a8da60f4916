// Minimal levelled logging to stderr. Quiet by default in tests (HV_LOG=debug|info|warn|error|off).
#pragma once

#include <string>

namespace hv::log {

enum class Level { Debug = 0, Info = 1, Warn = 2, Error = 3, Off = 4 };

void setLevel(Level level);
Level level();
void debug(const std::string& message);
void info(const std::string& message);
void warn(const std::string& message);
void error(const std::string& message);

}  // namespace hv::log
