// Where tests find the real datasets (never part of the repository): $HISTOVIEW_DATA, else
// ../shared/data beside the repository. Tests that need them skip, saying so, when absent.
#pragma once

#include <cstdlib>
#include <filesystem>
#include <string>

namespace hv::testing {

inline std::string dataDir() {
  if (const char* env = std::getenv("HISTOVIEW_DATA"); env && *env) return env;
#ifdef HV_SOURCE_DIR
  return (std::filesystem::path(HV_SOURCE_DIR) / ".." / "shared" / "data").lexically_normal().string();
#else
  return "../shared/data";
#endif
}

// The path of a dataset folder, or empty when it is not there.
inline std::string dataset(const std::string& name) {
  const auto p = std::filesystem::path(dataDir()) / name;
  return std::filesystem::is_directory(p) ? p.string() : std::string();
}

}  // namespace hv::testing
