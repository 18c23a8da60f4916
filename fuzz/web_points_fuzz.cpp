// Fuzz target: the browser's point file (points.bin, hv::parseWebPoints), then the chunk
// organisation and a selection on what it read, as the web scene reader and the point pass do.
#include "fuzz_util.h"
#include "hv/io/web_scene.h"
#include "point_cloud_checks.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("web_points", [&] {
    // A Lambert-93-sized origin, as a real export has: the offsets are added to it in double.
    hv::PointCloud cloud = hv::parseWebPoints(data, size, {651000.0, 6862000.0, 0.0}, "fuzz.bin");
    hv::fuzz::organiseAndSelect(cloud, [](hv::PointCloud& c) { (void)hv::subsampleChunks(c, c.size() / 2); });
  });
  return 0;
}
