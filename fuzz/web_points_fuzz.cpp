// Fuzz target: the browser's point file (points.bin, hv::parseWebPoints), then the chunk
// organisation and a selection on what it read, as the web scene reader and the point pass do.
#include "fuzz_util.h"
#include "hv/io/web_scene.h"
#include "hv/points/chunks.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("web_points", [&] {
    // A Lambert-93-sized origin, as a real export has: the offsets are added to it in double.
    hv::PointCloud cloud = hv::parseWebPoints(data, size, {651000.0, 6862000.0, 0.0}, "fuzz.bin");
    if (!cloud.consistent()) std::abort();
    hv::organizeChunks(cloud, {.maxPointsPerChunk = 64});
    (void)hv::subsampleChunks(cloud, cloud.size() / 2);
    const hv::Aabb b = cloud.bounds();
    if (b.empty() || !(glm::length(b.size()) < 1e9)) return;
    const hv::Camera view = hv::lookAtCamera("v", b.center() + glm::dvec3(1.0, -50.0, 20.0), b.center(), 64, 48, 50.0);
    (void)hv::selectChunks(cloud, view, 100);
  });
  return 0;
}
