// A loaded scene: the geometry (terrain, LOD1 buildings, meshes, a point cloud) and the
// photographs with their cameras.
// Everything is in the world frame (the scene CRS); `origin` is the render origin subtracted
// before anything goes to the GPU.
#pragma once

#include "hv/camera/camera.h"
#include "hv/scene/missing_sources.h"
#include "hv/scene/point_cloud.h"
#include "hv/scene/mesh.h"
#include "hv/util/dates.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace hv {

class TerrainQuadtree;   // hv/scene/terrain_quadtree.h
struct BuildingTileSet;  // hv/scene/building_tiles.h
struct Trajectories;    // hv/traffic/trajectories.h

// A photograph's colour correction (docs/design.md, "Photographs that agree in colour"): the colour
// c sampled from it (straight, not premultiplied, in [0, 1]) is shown as gain * c + offset, channel
// by channel, clamped to [0, 1]. Estimated from the overlaps between photographs
// (hv/ibr/colour_correction.h), read from the file scene.json names ("colour").
struct ColourCorrection {
  glm::dvec3 gain{1.0};
  glm::dvec3 offset{0.0};
  bool isIdentity() const { return gain == glm::dvec3(1.0) && offset == glm::dvec3(0.0); }
  glm::dvec3 apply(const glm::dvec3& c) const { return glm::clamp(gain * c + offset, 0.0, 1.0); }
};

struct Photo {
  Camera camera;
  std::string imagePath;  // absolute or relative to the working directory (resolved at load)
  std::string maskPath;   // empty: no mask
  std::string date;       // ISO 8601 as given; empty: undated
  ColourCorrection colour;  // identity unless scene.json names corrections
};

struct Scene {
  std::string path;        // scene.json
  std::string crs;         // the scene CRS: the world frame is it with linear units in metres (hv/io/georef.h)
  // The CRS each source was given in, for `histoview info`; a source absent here declared none
  // and is in the scene frame as it is.
  struct SourceCrs {
    std::string source;       // "terrain", "buildings", "mesh", "points", "cameras"
    std::string crs;          // as given: scene.json's `<source>.crs`, else the file's
    bool transformed = true;  // false: the scene has no CRS, so the source was taken as it is
  };
  std::vector<SourceCrs> sourceCrs;
  glm::dvec3 origin{0.0};  // render origin (world)
  glm::dvec3 up{0.0, 0.0, 1.0};
  Mesh terrain;
  // A DTM too large to mesh whole (hv/io/native/terrain_raster.h, kTerrainTilesAboveCells): its
  // quadtree of tiles, read on demand, for the views to select their own tiles; `terrain` then
  // holds the tiles selected for the photographs' cameras. Null for a DTM meshed whole. Shared by
  // copies of the scene; not thread-safe (TerrainQuadtree::tile reads and caches).
  std::shared_ptr<TerrainQuadtree> terrainTiles;
  struct TerrainTilesInfo {
    std::size_t tiles = 0;  // in `terrain`
    int coarsestLevel = 0, finestLevel = 0, maxLevel = 0, tileCells = 0;
    double tolerancePx = 0.0;
    std::size_t triangleBudget = 0;
    bool budgetLimited = false;
    std::string reads;  // where the levels are read from: "2 GDAL overviews", "a pyramid built in memory (7 levels)"
  } terrainTilesInfo;
  Mesh buildings;
  // Buildings read by tile (hv/io/native/footprints.h, readFootprintTiles): a regular grid over
  // the footprints' extent, each building owned by one tile. `tileOfBuilding[tag]` is the tile of
  // the building with that triangle tag; the frame builder makes each tile one geometry tile
  // (hv/render/geometry_tiles.h). Empty: no tiles (a scene made in memory), the frame builder's
  // own grid then.
  std::vector<std::uint32_t> tileOfBuilding;
  struct BuildingTilesInfo {
    std::size_t loaded = 0, total = 0;  // tiles read (holding buildings or not) / in the grid
    std::size_t streamed = 0;           // tiles in buildingTiles (0: not streamed)
    double tileSize = 0.0;              // in the source's units
    bool spatialFilter = true;          // read through OGR's spatial filter
    std::string note;                   // why not, when not
    std::string selection;              // which tiles were read
  } buildingTilesInfo;
  // Buildings too many to draw whole (a source with more tiles than the photographs see; the
  // loader's footprintTileSet, hv/io/native/footprints.h): every tile, read on demand, for the
  // renderer to stream per view (hv/render/building_stream.h); `buildings` then holds the tiles
  // the photographs' cameras see, for the CPU's uses (ray casts, layers, evaluation). Null: the
  // renderer draws `buildings`. Shared by copies of the scene.
  std::shared_ptr<const BuildingTileSet> buildingTiles;
  Mesh mesh;  // arbitrary geometry (scene.json "mesh"), e.g. a photogrammetric mesh
  // Points from a 3D Tiles tileset (hv/io/native/points_tiles.h): what was read; all zero for a
  // point file or none.
  struct PointTilesInfo {
    std::size_t tilesInTileset = 0;  // tiles known (the external tilesets read included)
    std::size_t tilesRead = 0;       // point tiles fetched and parsed
    std::size_t tilesKept = 0;       // of which in the cloud (a REPLACE-refined parent is not)
    std::size_t tilesFailed = 0;     // named and left out
    std::vector<std::pair<std::string, std::string>> failed;  // per tile left out: its URL, the message
    std::uint64_t bytes = 0;         // fetched: the tileset JSON and the tiles
    bool budgetLimited = false;      // a refinement was refused for the point budget
  } pointTilesInfo;
  // scene.json "points" (empty: none), organised into chunks (hv/scene/chunks.h) at load, in the
  // scene frame; `points.crs` keeps the CRS they were given in (the file's, or points.crs).
  PointCloud points;
  // When each building existed, indexed by the buildings mesh's triangle tags (open-ended by
  // default). A photograph does not texture a building that did not exist at its date.
  std::vector<DateInterval> buildingValidity;
  std::vector<Photo> photos;
  // scene.json "colour": the colour corrections file it names (resolved), empty when none.
  std::string colourPath;
  // scene.json "traffic" (docs/traffic.md): vehicle trajectories in the scene frame, null when
  // none; `trafficPath` the file they were read from.
  std::shared_ptr<const Trajectories> traffic;
  std::string trafficPath;
  // What was asked for and could not be read (hv/scene/missing_sources.h): filled by the loader
  // and, while frames render, by the streaming parts. Shared by copies of the scene; thread-safe.
  std::shared_ptr<MissingSources> missing = std::make_shared<MissingSources>();

  Aabb bounds() const;  // geometry and camera centres
  // Median distance from each camera centre to its nearest other centre: the scene's own scale
  // for default distances (sigma, depth bias). 1.0 when there are fewer than two cameras.
  double cameraSpacing() const;
};

}  // namespace hv
