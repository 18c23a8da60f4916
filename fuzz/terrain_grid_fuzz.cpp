// Fuzz target: the terrain a service scene without an export meshes in the page (hv/io/web_scene_frame.h):
// an ESRI ASCII grid as a WCS answers it (parseAaiGrid, hv/io/geojson_footprints.h), then the
// native loader's rule (hv/scene/scene_frame.h terrainFromGrid) and the terrain's rectangle. A
// grid that parses gives a mesh whose indices are in range; a bad one is an InputError naming
// the grid, never a crash. Grids over 2^16 cells are parsed but not meshed (the quadtree's
// pyramid over a million cells would make each run slow; CPU test TerrainFromGrid covers it).
#include "fuzz_util.h"
#include "hv/io/geojson_footprints.h"
#include "hv/scene/scene_frame.h"

#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("terrain_grid", [&] {
    hv::Heightfield f = hv::parseAaiGrid(std::string(reinterpret_cast<const char*>(data), size), "dtm.asc");
    if (f.cols <= 0 || f.rows <= 0 || f.z.size() != std::size_t(f.cols) * std::size_t(f.rows)) __builtin_trap();
    if (f.z.size() > (std::size_t(1) << 16)) return;
    hv::Scene scene;
    hv::terrainFromGrid(scene, std::move(f), "dtm.asc");
    for (const glm::uvec3& t : scene.terrain.triangles)
      if (t.x >= scene.terrain.positions.size() || t.y >= scene.terrain.positions.size() ||
          t.z >= scene.terrain.positions.size())
        __builtin_trap();
    (void)hv::terrainExtent(scene);
  });
  return 0;
}
