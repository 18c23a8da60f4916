// Fuzz target: control points for `histoview pose` (hv::pose::parseControlPoints, CSV u,v,x,y,z),
// then the solver on what was read, with a fixed first camera: whatever the points, the answer
// is a camera or an InputError saying what to add.
#include "fuzz_util.h"
#include "hv/pose/pose.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("gcp_csv", [&] {
    const auto points = hv::pose::parseControlPoints(text, "gcp.csv");
    for (const auto& p : points)
      if (!std::isfinite(p.pixel.x) || !std::isfinite(p.world.z)) {
        std::fprintf(stderr, "gcp_csv: BUG: a non-finite value read\n");
        std::abort();
      }
    if (points.size() > 200) return;  // the solver's cost is not what this target is for
    const hv::Camera start = hv::lookAtCamera("p", {0, -50, 10}, {0, 0, 5}, 640, 480, 600.0);
    hv::pose::PoseOptions o;
    o.maxIterations = 50;
    const auto r = hv::pose::solvePose(points, start, true, o);
    if (r.residuals.size() != points.size() || !std::isfinite(r.camera.center.x)) {
      std::fprintf(stderr, "gcp_csv: BUG: a camera with a non-finite centre or missing residuals\n");
      std::abort();
    }
  });
  return 0;
}
