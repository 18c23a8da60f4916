#pragma once

namespace CLI {
class App;
}

namespace hv::app {

// `histoview path tour SCENE -o PATH.json`: a walk that visits the photographs in street order
// (focus + context at each); `histoview path orbit SCENE --around X,Y,Z -o PATH.json`: one turn
// around a point. Both write the camera path `fly --path` reads (hv/io/camera_path_json.h).
void addPathCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
