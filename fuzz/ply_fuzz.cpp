// Fuzz target: PLY point reader (hv::parsePlyPoints), then the chunk organisation and a selection
// on what it read, as scene loading does.
#include "fuzz_util.h"
#include "hv/io/ply_points.h"
#include "hv/points/chunks.h"

#include <cstddef>
#include <cstdint>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("ply", [&] {
    hv::PointCloud cloud = hv::parsePlyPoints(data, size, "fuzz.ply");
    if (!cloud.consistent()) std::abort();
    hv::organizeChunks(cloud, {.maxPointsPerChunk = 64});
    const hv::Aabb b = cloud.bounds();
    // A camera needs room: at huge coordinates the look-at offset vanishes in rounding.
    if (b.empty() || !(glm::length(b.center()) < 1e9 && glm::length(b.size()) < 1e9)) return;
    const hv::Camera view = hv::lookAtCamera("v", b.center() + glm::dvec3(1.0, -50.0, 20.0), b.center(), 64, 48, 50.0);
    (void)hv::selectChunks(cloud, view, 100);
  });
  return 0;
}
