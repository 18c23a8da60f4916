// OGC 3D Tiles 1.0 point clouds (docs/formats.md, "Points from 3D Tiles"): the tileset
// (`tileset.json`: asset, geometricError, the tile tree with bounding volumes, transforms, refine
// and content) and the Point Cloud tile format (`pnts`: header, feature table JSON + binary).
// Parsing and writing only, bytes in and structures out; the fetching and the traversal by
// screen-space error are native (hv/io/native/points_tiles.h).
//
// Conventions: the tileset frame is the frame of the tileset's root before any tile transform
// (EPSG:4978, earth-centred, unless the scene says otherwise); a tile's `transform` maps its own
// frame into the tileset frame, composed down the tree (a child's is parent * its own, the 4x4
// matrices column-major as in the file). pnts positions are in the tile's frame with RTC_CENTER
// added (quantized ones decoded). Messages name the URL, the field and what was expected.
#pragma once

#include "hv/scene/point_cloud.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace hv {

enum class TileRefine { Add, Replace };

// A tile's bounding volume as a sphere in the tileset frame (boxes and spheres through the tile's
// transform; regions, which are longitude/latitude in radians and WGS84 heights, as they are).
struct TileSphere {
  glm::dvec3 centre{0.0};
  double radius = 0.0;
};

struct Tiles3dTile {
  int parent = -1;            // index in Tiles3dTileset::tiles; -1: the root
  std::vector<int> children;  // indices
  int depth = 0;              // the root is 0 (external tilesets continue the count)
  glm::dmat4 transform{1.0};  // tile frame -> tileset frame, composed down the tree
  TileSphere bounds;
  double geometricError = 0.0;
  TileRefine refine = TileRefine::Replace;
  std::string content;    // the content's URI resolved against the tileset's URL; "" : none
  bool external = false;  // the content is another tileset (a .json), grafted in its place when read
  std::string path;       // where the tile is in its file, for messages: "root.children[2]"
};

struct Tiles3dTileset {
  std::string url;      // where it was read from (messages, relative URIs)
  std::string version;  // asset.version
  double geometricError = 0.0;
  std::vector<Tiles3dTile> tiles;  // tiles[0] is the root; parents before children
  std::vector<std::string> notes;  // what was read leniently or ignored (for warnings)
};

// The most tiles a tileset (all its external tilesets together) may have, and the deepest tree.
inline constexpr std::size_t kMaxTiles3dTiles = 1'000'000;
inline constexpr int kMaxTiles3dDepth = 64;

// Parses a tileset.json read from `url`. `parentTransform`, `inheritedRefine` and `depth` place an
// external tileset under the tile that references it. Throws InputError naming the URL and the
// field ("…/tileset.json: root.children[1].boundingVolume: expected box (12 numbers), region (6)
// or sphere (4)").
Tiles3dTileset parseTileset(std::string_view text, const std::string& url,
                            const glm::dmat4& parentTransform = glm::dmat4(1.0),
                            TileRefine inheritedRefine = TileRefine::Replace, int depth = 0);

// Puts `sub` (an external tileset, parsed with the host tile's transform, refine and depth + 1)
// under host tile `at`, whose content it was: the tile keeps no content of its own.
void graftTileset(Tiles3dTileset& host, int at, Tiles3dTileset sub);

// A content URI against the URL (or local path) of the tileset that names it: absolute URIs and
// paths as they are, "/x" against the server, otherwise against the tileset's folder (its query
// dropped), "./" and "../" segments resolved.
std::string resolveTileUri(const std::string& base, const std::string& uri);

// The geocentric (EPSG:4978) position of WGS84 longitude, latitude (radians) and ellipsoidal height.
glm::dvec3 wgs84ToEcef(double lon, double lat, double height);

// A Point Cloud tile: the points in the tile's frame (positions, rgb 16-bit as LAS, normals when
// the tile has them, ASPRS classes from a per-point batch table's "Classification") and what was
// ignored (other batch table properties, unknown semantics).
struct PntsTile {
  PointCloud points;
  std::vector<std::string> notes;
};
// Throws InputError naming `url`, the field and what was expected ("…/r0.pnts:
// featureTable.POSITION.byteOffset: 1200 + 12·N (N = 100) = 2400 bytes, past the binary body of
// 900 bytes").
PntsTile parsePnts(std::string_view bytes, const std::string& url);

// NORMAL_OCT16P: two bytes of the octahedral encoding to a unit vector (Cigolle et al. 2014,
// "A survey of efficient representations for independent unit vectors").
glm::vec3 octDecode16P(std::uint8_t x, std::uint8_t y);
// The nearest encoding of a unit vector.
void octEncode16P(const glm::vec3& n, std::uint8_t& x, std::uint8_t& y);
// RGB565 to 16-bit channels (each scaled to 0..65535).
glm::u16vec3 rgb565To16(std::uint16_t c);

// Writing (histoview points-tiles): an ADD-refined tree of pnts tiles, each tile a sample of its
// node's points, the rest split among its children (octants, or quadrants where the node is
// flat), so that the whole tree holds every point once.
struct PointTilesOptions {
  std::size_t pointsPerTile = 20000;  // the most points a tile keeps; a node with more is split
  int maxDepth = 16;                  // a node this deep keeps all its points
};
struct PointTilesFile {
  std::string name;  // relative to the tileset's folder: "tileset.json", "r0.pnts", ...
  std::string bytes;
};
struct PointTilesWritten {
  std::vector<PointTilesFile> files;  // tileset.json first
  std::size_t tiles = 0;
  int depth = 0;
};
// `cloud` in a local frame that `rootTransform` maps into the tileset frame (e.g. east-north-up
// at the cloud's centre into EPSG:4978). Positions are written quantized (16 bits per axis over
// each tile's box), colours as RGB (8 bits), normals as NORMAL (float).
PointTilesWritten writePointTiles(const PointCloud& cloud, const glm::dmat4& rootTransform,
                                  const PointTilesOptions& options = {});
// One pnts tile of `cloud` (its own frame): RTC_CENTER the box's centre, POSITION_QUANTIZED over
// the box, RGB and NORMAL when the cloud has them.
std::string writePnts(const PointCloud& cloud);

}  // namespace hv
