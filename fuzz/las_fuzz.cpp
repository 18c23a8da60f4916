// Fuzz target: LAS reader (hv::parseLas), then the chunk organisation and a selection on what it
// read, as scene loading does.
#include "fuzz_util.h"
#include "hv/io/native/las_reader.h"
#include "point_cloud_checks.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("las", [&] {
    hv::PointCloud cloud = hv::parseLas(data, size, "fuzz.las");
    hv::fuzz::organiseAndSelect(cloud);
  });
  return 0;
}
