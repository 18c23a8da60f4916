// Fuzz target: CSV trajectories (hv::parseTrajectoriesCsv, t,id,x,y,angle,type), then each vehicle
// sampled and lifted onto a sloped plane: whatever the file, trajectories or an InputError, and
// finite poses.
#include "fuzz_util.h"
#include "hv/traffic/lift.h"
#include "hv/traffic/trajectories.h"
#include "hv/util/diagnostics.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("trajectories_csv", [&] {
    hv::Diagnostics diag;
    const hv::Trajectories t = hv::parseTrajectoriesCsv(text, "trajectories.csv", diag);
    hv::Mesh plane;
    plane.positions = {{-1e4, -1e4, -100}, {1e4, -1e4, 100}, {1e4, 1e4, 300}, {-1e4, 1e4, 100}};
    plane.triangles = {{0, 1, 2}, {0, 2, 3}};
    const hv::MeshTerrainHeight terrain(plane);
    for (const hv::Trajectory& v : t.vehicles) {
      if (v.samples.empty()) {
        std::fprintf(stderr, "trajectories_csv: BUG: a vehicle without samples\n");
        std::abort();
      }
      for (const double time : {v.samples.front().t, 0.5 * (v.samples.front().t + v.samples.back().t)}) {
        const auto g = hv::sampleTrajectory(v, time);
        if (!g) {
          std::fprintf(stderr, "trajectories_csv: BUG: no pose between the first and last sample\n");
          std::abort();
        }
        const auto pose = hv::liftOntoTerrain(*g, v.size, terrain);
        if (pose && (!std::isfinite(pose->position.z) || !std::isfinite(pose->pitch))) {
          std::fprintf(stderr, "trajectories_csv: BUG: a non-finite pose\n");
          std::abort();
        }
      }
    }
  });
  return 0;
}
