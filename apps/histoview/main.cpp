// histoview: one executable, subcommands. Each subcommand's work lives in src/hv/app/; this file
// only declares the command line.
#include "hv/app/commands.h"

#include <CLI/CLI.hpp>

#include <iostream>

int main(int argc, char** argv) {
  CLI::App app{"histoview: walk through a city as its old photographs show it"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "histoview 0.1.0");
  hv::app::registerCommands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  return hv::app::exitCode();
}
