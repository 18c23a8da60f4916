// Fuzz target: glTF vehicle models (hv::parseGltfVehicle, through tinygltf): a model fitted to the
// unit box or an InputError saying what was expected, never a crash; every vertex finite and
// inside the unit box.
#include "fuzz_util.h"
#include "hv/io/native/gltf_model.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("gltf", [&] {
    const hv::VehicleModel m = hv::parseGltfVehicle(data, size, "model.gltf");
    if (m.vertices.empty() || m.vertices.size() % 3 != 0) {
      std::fprintf(stderr, "gltf: BUG: %zu vertices, not whole triangles\n", m.vertices.size());
      std::abort();
    }
    for (const hv::ModelVertex& v : m.vertices)
      for (int k = 0; k < 3; ++k) {
        const float lo = k == 2 ? -1e-4f : -0.5001f, hi = k == 2 ? 1.0001f : 0.5001f;
        if (!(v.local[k] >= lo && v.local[k] <= hi) || !std::isfinite(v.normal[k])) {
          std::fprintf(stderr, "gltf: BUG: a vertex outside the unit box or a non-finite normal\n");
          std::abort();
        }
      }
  });
  return 0;
}
