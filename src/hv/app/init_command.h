// `histoview init FOLDER`: a scene.json from what a folder holds (cameras of any format the
// scene loader reads, a DTM, footprints or CityJSON, a mesh, a point cloud), saying what it found
// and what it guessed.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hv::app {

struct InitResult {
  nlohmann::json scene;             // scene.json, paths relative to `sceneDir`
  std::vector<std::string> report;  // one line per finding or guess, for the user
};

// Looks through `folder` (three levels deep, hidden folders skipped) and makes the scene.json that
// would sit in `sceneDir`. Never throws for what it finds: a file it cannot read is reported and
// passed over.
InitResult initScene(const std::string& folder, const std::string& sceneDir);

void addInitCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
