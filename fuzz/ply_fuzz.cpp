// Fuzz target: PLY point reader (hv::parsePlyPoints), then the chunk organisation and a selection
// on what it read, as scene loading does.
#include "fuzz_util.h"
#include "hv/io/native/ply_points.h"
#include "point_cloud_checks.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("ply", [&] {
    hv::PointCloud cloud = hv::parsePlyPoints(data, size, "fuzz.ply");
    hv::fuzz::organiseAndSelect(cloud);
  });
  return 0;
}
