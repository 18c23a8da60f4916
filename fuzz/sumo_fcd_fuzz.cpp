// Fuzz target: SUMO floating car data (hv::parseSumoFcd): trajectories or an InputError naming the
// line and attribute, never a crash; every sample finite.
#include "fuzz_util.h"
#include "hv/io/native/sumo_fcd.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("sumo_fcd", [&] {
    hv::Diagnostics diag;
    const hv::Trajectories t = hv::parseSumoFcd(text, "fcd.xml", diag);
    for (const hv::Trajectory& v : t.vehicles)
      for (const hv::TrajectorySample& s : v.samples)
        if (!std::isfinite(s.xy.x) || !std::isfinite(s.xy.y) || !std::isfinite(s.t)) {
          std::fprintf(stderr, "sumo_fcd: BUG: a non-finite sample\n");
          std::abort();
        }
  });
  return 0;
}
