#pragma once

namespace CLI {
class App;
}

namespace hv::app {

void addEvalCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
