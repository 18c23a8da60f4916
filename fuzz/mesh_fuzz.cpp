// Fuzz target: triangle meshes through Assimp (hv::readMesh), as PLY and as OBJ (Assimp picks its
// importer by the extension, then by the content).
#include "fuzz_util.h"
#include "hv/io/native/mesh_reader.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  for (const char* name : {"mesh.ply", "mesh.obj"}) {
    const std::string path = hv::fuzz::writeScratch(name, data, size);
    hv::fuzz::expectOnlyInputErrors("mesh", [&] {
      const hv::Mesh mesh = hv::readMesh(path);
      // The mesh only references its own vertices.
      for (const auto& t : mesh.triangles)
        for (int c = 0; c < 3; ++c)
          if (size_t(t[c]) >= mesh.positions.size()) {
            std::fprintf(stderr, "mesh: BUG: triangle index %u out of %zu vertices\n", unsigned(t[c]),
                         mesh.positions.size());
            std::abort();
          }
    });
  }
  return 0;
}
