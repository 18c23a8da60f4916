// `histoview points-tiles IN OUT_DIR`: a point cloud (LAS or PLY) as an OGC 3D Tiles 1.0 tileset
// of pnts tiles (hv/io/tiles3d.h, writePointTiles), earth-centred (EPSG:4978) with an
// east-north-up root transform, for a server to publish and `"points": {"tileset": …}` to read
// (docs/formats.md, "Points from 3D Tiles").
#pragma once

#include <cstddef>
#include <string>

namespace CLI {
class App;
}

namespace hv::app {

struct PointsTilesOptions {
  std::string input;  // .las or .ply
  std::string out;    // the folder: tileset.json and the tiles
  std::string crs;    // the cloud's CRS when it declares none (or to override it)
  std::size_t pointsPerTile = 20000;
};

// Writes the tileset; returns the exit status.
int runPointsTiles(const PointsTilesOptions& options);

void addPointsTilesCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
