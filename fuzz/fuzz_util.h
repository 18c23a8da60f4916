// Shared helpers for the fuzz targets in fuzz/ (libFuzzer entry points, also replayed over the
// seed corpora by fuzz/standalone_main.cpp in the normal build).
#pragma once

#include "hv/util/diagnostics.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>

namespace hv::fuzz {

// A private scratch directory for this process (created once, removed at normal exit), so that
// relative paths inside a fuzzed file resolve into it and parallel fuzzing jobs do not collide.
inline const std::filesystem::path& scratchDir() {
  static const std::filesystem::path dir = [] {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base && *base ? base : "/tmp") + "/hv-fuzz-XXXXXX";
    if (!::mkdtemp(pattern.data())) {
      std::perror("mkdtemp");
      std::abort();
    }
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(scratchDir(), ec);
    });
    return std::filesystem::path(pattern);
  }();
  return dir;
}

inline std::string writeScratch(const std::string& name, const std::uint8_t* data, size_t size) {
  const std::filesystem::path path = scratchDir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    std::abort();
  }
  return path.string();
}

inline std::string writeScratch(const std::string& name, const std::string& text) {
  return writeScratch(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
}

// The contract of the parsers: hv::InputError (documented) or nothing. Any other exception is a
// bug: report it and abort so that libFuzzer (or the corpus replay) flags the input.
template <typename F>
void expectOnlyInputErrors(const char* target, F&& body) {
  try {
    body();
  } catch (const hv::InputError&) {
    // documented behaviour for a file that cannot be read at all
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: BUG: exception other than hv::InputError escaped: %s\n", target, e.what());
    std::abort();
  } catch (...) {
    std::fprintf(stderr, "%s: BUG: non-std exception escaped\n", target);
    std::abort();
  }
}

}  // namespace hv::fuzz
