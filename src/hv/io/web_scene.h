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
//                    "cameras": "cameras.json"}
//   NAME.bin        V*3 float32 positions relative to `origin` (render frame), then T*3 uint32
//                   indices, then (when "tags") T uint32 triangle tags; little-endian, no header.
//   cameras.json    the native camera file (hv/io/cameras_json.h), image paths relative to it.
//
// Positions are stored relative to the origin in float32, as the renderer uploads them, so
// reading back gives the world positions to float precision of the local coordinates.
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <string>

namespace hv {

inline constexpr const char* kWebSceneManifest = "scene_web.json";

// Writes scene_web.json, the meshes and cameras.json into `dir` (which must exist). The photos'
// imagePath / maskPath are written as given, relative to `dir` when they lie inside it: the
// caller copies the image files first and passes photos that point at the copies. Throws
// std::runtime_error naming the file when a write fails.
void writeWebScene(const Scene& scene, const std::vector<Photo>& photos, const std::string& dir);

struct WebSceneOptions {
  // The browser fetches images after the scene: do not require their files to exist yet.
  bool checkImageFiles = true;
};

// Reads a web scene from its manifest path (files beside it). A bad mesh or camera is reported in
// `diag` and left out; throws InputError when the manifest cannot be read or parsed.
Scene readWebScene(const std::string& manifestPath, const WebSceneOptions& options, Diagnostics& diag);

}  // namespace hv
