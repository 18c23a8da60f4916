#include "hv/io/web_scene_frame.h"

#include "hv/io/geojson_footprints.h"
#include "hv/scene/scene_frame.h"
#include "hv/util/log.h"

#include <cstdint>
#include <filesystem>
#include <vector>

namespace hv {

using json = nlohmann::json;

void readWebTerrainGrid(const json& entry, const std::string& dir, Scene& scene) {
  if (!entry.is_object() || !entry.contains("grid") || !entry["grid"].is_string())
    throw InputError("expected {\"grid\": \"dtm.asc\"} (an ESRI ASCII grid in the scene frame)");
  const std::string file = (std::filesystem::path(dir) / entry["grid"].get<std::string>()).string();
  const std::vector<std::uint8_t> bytes = readFileBytes(file);
  Heightfield dtm = parseAaiGrid(std::string(bytes.begin(), bytes.end()), file);
  const int cols = dtm.cols, rows = dtm.rows;
  scene.terrain = Mesh{};
  terrainFromGrid(scene, std::move(dtm), file);
  log::debug("terrain: " + file + ": " + std::to_string(cols) + "x" + std::to_string(rows) +
             (scene.terrainTiles ? " (tiles)" : ""));
}

void settleWebSceneFrame(Scene& scene, bool originGiven, bool upDeclared, const std::string& manifestPath,
                         Diagnostics& diag) {
  if (scene.terrainTiles) {
    try {
      meshTerrainTiles(scene);
    } catch (const InputError& e) {
      scene.terrainTiles.reset();
      scene.terrain = Mesh{};
      diag.error(manifestPath + ": terrain: " + e.what() + " (terrain left out)");
    }
  }
  if (originGiven) return;  // an export's manifest: its origin and up are the native loader's already
  settleUp(scene, upDeclared, manifestPath, diag);
  scene.origin = dataOrigin(scene);
}

json webSceneFrameJson(const Scene& scene) {
  auto v3 = [](const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); };
  json out = {{"origin", v3(scene.origin)}, {"up", v3(scene.up)}};
  if (const Aabb e = terrainExtent(scene); !e.empty()) out["terrainExtent"] = {e.lo.x, e.lo.y, e.hi.x, e.hi.y};
  if (const Aabb b = scene.bounds(); !b.empty()) out["bounds"] = {{"lo", v3(b.lo)}, {"hi", v3(b.hi)}};
  return out;
}

}  // namespace hv
