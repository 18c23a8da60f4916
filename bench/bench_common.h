// What the benchmarks share: wall and process-CPU timing, medians, a self-removing work
// directory, the process's resident memory, and the machine facts printed beside the figures.
// Header-only (each bench/*.cpp is its own executable).
#pragma once

#include "hv/camera/camera.h"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

namespace hv::bench {

// The frame every renderer benchmark measures.
inline constexpr int kFrameWidth = 1280, kFrameHeight = 720;

// A held-out view as a 1280x720 frame: scaled to 1280 wide (same aspect) and cropped to the middle
// 720 rows by moving the principal point, so the field of view is the view's horizontally.
inline Camera crop720p(const Camera& view) {
  const int fullHeight = kFrameWidth * view.height / view.width;
  Camera c = view.resized(kFrameWidth, fullHeight);
  const double cut = 0.5 * (fullHeight - kFrameHeight);
  c.height = kFrameHeight;
  c.principal.y -= cut;
  if (c.distortion) c.distortion->center.y -= cut;
  c.id += "@720p";
  return c;
}

using Clock = std::chrono::steady_clock;

inline double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// Process CPU time (every llvmpipe and decoder thread included). Other processes on a shared
// machine inflate wall time a lot (they take cores away) and CPU time much less, so the
// benchmarks print both.
inline double cpuMs() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec * 1e3 + ts.tv_nsec * 1e-6;
}

template <typename F>
double timeMs(F&& f) {
  const auto t0 = Clock::now();
  f();
  return msSince(t0);
}

struct Timing {
  double wall = 0.0, cpu = 0.0;  // ms
  Timing& operator+=(const Timing& o) {
    wall += o.wall;
    cpu += o.cpu;
    return *this;
  }
};

template <typename F>
Timing measure(F&& f) {
  const double c0 = cpuMs();
  const double wall = timeMs(f);
  return {wall, cpuMs() - c0};
}

inline double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

inline Timing median(const std::vector<Timing>& v) {
  std::vector<double> w, c;
  for (const auto& t : v) w.push_back(t.wall), c.push_back(t.cpu);
  return {median(w), median(c)};
}

// Generated scenes live in a temporary directory removed at exit unless kept.
struct WorkDir {
  std::filesystem::path path;
  bool keep = false;
  ~WorkDir() {
    if (keep || path.empty()) return;
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
};

// Like nproc: the CPUs this process may run on, not the machine's total.
inline int cpuCount() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof(set), &set) == 0) return CPU_COUNT(&set);
  return int(sysconf(_SC_NPROCESSORS_ONLN));
}

// A field of /proc/self/status in kB ("VmHWM:": this process's peak resident memory, "VmRSS:":
// its resident memory now); -1 when it is not there.
inline long residentKb(const char* field) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind(field, 0) == 0) return std::stol(line.substr(std::string(field).size()));
  return -1;
}

inline std::string loadAverage() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  if (!(f >> a >> b >> c)) return "unknown";
  return a + " " + b + " " + c;
}

}  // namespace hv::bench
