// The web scene: what `histoview web-export` writes and the browser build reads (docs/web.md). A
// triangulated, library-free form of a Scene, so nothing on the reading side needs GDAL, GEOS,
// Embree or Assimp:
//
//   scene_web.json  {"format": "histoview-web", "version": 1, "crs": "...",
//                    "origin": [x, y, z], "up": [x, y, z],
//                    "bounds": {"lo": [x, y, z], "hi": [x, y, z]},          (world, informative)
//                    "meshes": [{"name": "terrain" | "buildings" | "mesh", "path": "terrain.bin",
//                                "vertices": V, "triangles": T, "tags": true | false}, ...],
//                    "buildingValidity": [[first, last], ...],            (days, hv/util/dates.h)
//                    "points": {"path": "points.bin", "count": N, "bytes": B},  (optional)
//                    "traffic": {"csv": "traffic.csv", "models": "vehicles.json",  (optional)
//                                "vehicles": V, "begin": t0, "end": t1},
//                    "cameras": "cameras.json",
//                    "buildings": {"geojson": ["buildings-0.json", ...], "height": "height",  (optional)
//                                  "base", "top", "validFrom", "validTo": attribute names (optional),
//                                  "dtm": "dtm.asc"}}
//                   "buildings" is not written by web-export: the page writes it when it fetched
//                   the footprints from a service (web/histoview.js, `?scene=`): GeoJSON pages in
//                   the scene's CRS, extruded by the portable LOD1 code (hv/scene/footprint.h) on
//                   the ESRI ASCII grid `dtm` (a WCS answer), replacing any "buildings" mesh.
//                   "geocentric", "terrainExtent" and "orthophoto" (with orthophoto.rgba): added by
//                   web-export for the page's service layers (hv/io/web_geocentric.h,
//                   hv/io/web_orthophoto.h, src/hv/app/web_export_extras.h).
//                   "terrain": {"grid": "dtm.asc"}, and no "origin": a service scene the page makes
//                   without an export (hv/io/web_scene_frame.h): the terrain meshed from the grid,
//                   the origin and up placed by the native loader's rules (hv/scene/scene_frame.h).
//   NAME.bin        V*3 float32 positions relative to `origin` (render frame), then T*3 uint32
//                   indices, then (when "tags") T uint32 triangle tags; little-endian, no header.
//   points.bin      the point cloud (scene.points, in the scene frame, normals as loaded), below.
//   traffic.csv     the scene's trajectories (hv/traffic/trajectories.h's CSV: t,id,x,y,angle,type),
//                   x, y the vehicle's centre in the scene frame (SUMO's front bumper already moved).
//   vehicles.json   {"car": {"source": "car.gltf", "vertices": [...]}, ...}: the glTF models as read
//                   (hv/traffic/vehicle_model.h), 10 float per vertex (local xyz, normal xyz,
//                   colour rgb, paint), three vertices per triangle; classes without one: the box.
//   cameras.json    the native camera file (hv/io/cameras_json.h), image paths relative to it.
//
// points.bin, little-endian, every array tightly packed, in this order:
//   offset 0   8 bytes   magic "HVPOINTS"
//          8   uint32    version (1)
//         12   uint32    fields: bit 0 normals, bit 1 intensity, bit 2 rgb, bit 3 classification
//         16   uint64    N, the number of points (< 2^32)
//         24   N*3 float32  positions relative to `origin`, as the meshes
//              N*3 int16    normals (bit 0) as snorm16: round(n * 32767); (0, 0, 0): none
//              N   uint16   intensity (bit 1)
//              N*3 uint8    rgb (bit 2): the 16-bit value / 257 (integer division, the 8 bits the
//                           point pass shows); read back as value * 257
//              N   uint8    ASPRS classification (bit 3)
// and nothing after. The arrays come largest element first, so each starts aligned to its size.
//
// Positions are stored relative to the origin in float32, as the renderer uploads them, so
// reading back gives the world positions to float precision of the local coordinates.
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace hv {

inline constexpr const char* kWebSceneManifest = "scene_web.json";
inline constexpr const char* kWebPointsFile = "points.bin";
inline constexpr const char* kWebTrafficFile = "traffic.csv";
inline constexpr const char* kWebVehiclesFile = "vehicles.json";

// points.bin (above) of `cloud`, positions relative to `origin`.
std::string webPointBytes(const PointCloud& cloud, const glm::dvec3& origin);
// Reads points.bin bytes back (positions: origin + the stored float32 offset; not organised into
// chunks). Throws InputError naming `name` and the field (magic, version, fields, count, an array
// that runs past the end, trailing bytes, a non-finite position).
PointCloud parseWebPoints(const std::uint8_t* data, std::size_t size, const glm::dvec3& origin,
                          const std::string& name);

// Writes scene_web.json, the meshes, points.bin (when the scene has points) and cameras.json into
// `dir` (which must exist). The photos'
// imagePath / maskPath are written as given, relative to `dir` when they lie inside it: the
// caller copies the image files first and passes photos that point at the copies. Throws
// std::runtime_error naming the file when a write fails.
void writeWebScene(const Scene& scene, const std::vector<Photo>& photos, const std::string& dir);

struct WebSceneOptions {
  // The browser fetches images after the scene: do not require their files to exist yet.
  bool checkImageFiles = true;
};

// Reads a web scene from its manifest path (files beside it). A bad mesh, point file or camera is
// reported in `diag` and left out; throws InputError when the manifest cannot be read or parsed.
// The points are organised into chunks (hv::organizeChunks), as the native loader leaves them.
Scene readWebScene(const std::string& manifestPath, const WebSceneOptions& options, Diagnostics& diag);

}  // namespace hv
