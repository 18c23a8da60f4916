// Fuzz target: a 3D Tiles tileset.json (hv::parseTileset), then grafted under its own first tile as
// an external tileset would be. What parses is a tree: parents before children, finite spheres.
#include "fuzz_util.h"
#include "hv/io/tiles3d.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  hv::fuzz::expectOnlyInputErrors("tileset", [&] {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    hv::Tiles3dTileset ts = hv::parseTileset(text, "http://127.0.0.1/t/tileset.json");
    if (ts.tiles.empty() || ts.tiles[0].parent != -1) __builtin_trap();
    for (std::size_t i = 0; i < ts.tiles.size(); ++i) {
      const hv::Tiles3dTile& t = ts.tiles[i];
      if (i > 0 && (t.parent < 0 || std::size_t(t.parent) >= i)) __builtin_trap();
      for (int c : t.children)
        if (c <= int(i) || std::size_t(c) >= ts.tiles.size()) __builtin_trap();
      if (!std::isfinite(t.geometricError) || t.geometricError < 0) __builtin_trap();
    }
    if (ts.tiles.size() < 1000) {
      const hv::Tiles3dTile root = ts.tiles[0];
      hv::Tiles3dTileset sub =
          hv::parseTileset(text, "http://127.0.0.1/t/sub/tileset.json", root.transform, root.refine, root.depth + 1);
      const std::size_t before = ts.tiles.size(), added = sub.tiles.size();
      hv::graftTileset(ts, 0, std::move(sub));
      if (ts.tiles.size() != before + added) __builtin_trap();
    }
  });
  return 0;
}
