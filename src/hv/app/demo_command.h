#pragma once

namespace CLI {
class App;
}

namespace hv::app {

void addDemoCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
