#include "hv/app/commands.h"

#include "hv/app/render_command.h"

#include <CLI/CLI.hpp>

namespace hv::app {

namespace {
int g_exit = 0;
}

void registerCommands(CLI::App& app) {
  addInfoCommand(app, g_exit);
  addRenderCommand(app, g_exit);
}

int exitCode() { return g_exit; }

}  // namespace hv::app
