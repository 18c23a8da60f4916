// `histoview view SCENE`: the desktop viewer (hv/viewer/viewer.h).
#pragma once

namespace CLI {
class App;
}

namespace hv::app {

void addViewCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
