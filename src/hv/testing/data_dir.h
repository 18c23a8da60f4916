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

// True under HISTOVIEW_REQUIRE_DATA=1: the datasets must be there (tools/test.sh sets it when the
// data folder exists), so a wrong path, a renamed file or a missing folder fails instead of passing
// as a skip.
inline bool dataRequired() {
  const char* env = std::getenv("HISTOVIEW_REQUIRE_DATA");
  return env && std::string(env) == "1";
}

}  // namespace hv::testing

// Ends the current test because real data is absent, saying why (`why`: a std::string): a skip,
// or a failure when the data is required (hv::testing::dataRequired).
#define HV_SKIP_WITHOUT_DATA(why)                                                         \
  do {                                                                                    \
    if (::hv::testing::dataRequired())                                                    \
      GTEST_FAIL() << (why) << " (HISTOVIEW_REQUIRE_DATA=1: the data must be there)";     \
    else                                                                                  \
      GTEST_SKIP() << (why);                                                              \
  } while (0)
