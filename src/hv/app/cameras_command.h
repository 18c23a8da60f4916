#pragma once

namespace CLI {
class App;
}

namespace hv::app {

// `histoview cameras convert SCENE.json -o cameras.json`: the scene's cameras, whatever their
// format and CRS, in the scene frame as a native cameras.json.
void addCamerasCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
