// A web scene made by the page from services alone, without `web-export` (docs/services.md, "In
// the browser"): its manifest (hv/io/web_scene.h) may then have
//   "terrain": {"grid": "services/dtm.asc"}   an ESRI ASCII grid in the scene frame (a WCS answer),
//                                              meshed by the native loader's rule
//                                              (hv/scene/scene_frame.h terrainFromGrid), replacing
//                                              any "terrain" mesh;
// and no "origin" (nor meshes or points, which are stored relative to it): the origin and up are
// then those the native loader gives the same data (hv/scene/scene_frame.h settleUp, dataOrigin).
// The page asks the module for them (webSceneFrameJson) before it fetches the layers stored
// relative to the origin (3D Tiles points), and writes them into the manifest it hands the viewer.
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <nlohmann/json.hpp>

#include <string>

namespace hv {

// The manifest's "terrain" entry (above) into scene.terrain or scene.terrainTiles; `dir` is the
// manifest's folder. Throws InputError naming the field or the grid's file.
void readWebTerrainGrid(const nlohmann::json& entry, const std::string& dir, Scene& scene);

// Once the cameras are read: the terrain tiles meshed for them; then, unless `originGiven` (an
// export's manifest), up (as declared, else by the rule) and the origin by the native rules.
void settleWebSceneFrame(Scene& scene, bool originGiven, bool upDeclared, const std::string& manifestPath,
                         Diagnostics& diag);

// {"origin": [x, y, z], "up": [x, y, z], "terrainExtent": [minX, minY, maxX, maxY] (absent without
// terrain), "bounds": {"lo", "hi"}}: what the page needs of a scene without an export; the
// terrain extent is the rectangle `web-export` writes (hv/app/web_export_extras.h).
nlohmann::json webSceneFrameJson(const Scene& scene);

}  // namespace hv
