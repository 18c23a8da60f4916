// The subcommands of the histoview executable (render, eval, info, check, harmonize, fly, view, demo, cameras,
// catalog, pose, path, init, web-export, settings).
#pragma once

namespace CLI {
class App;
}

namespace hv::app {

// Adds every subcommand to `app`; each runs from its callback and records its exit code.
void registerCommands(CLI::App& app);
int exitCode();

}  // namespace hv::app
