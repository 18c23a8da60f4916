#pragma once

namespace CLI {
class App;
}

namespace hv::app {

void addInfoCommand(CLI::App& app, int& exitCode);
void addRenderCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
