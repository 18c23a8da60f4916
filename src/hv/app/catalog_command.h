#pragma once

namespace CLI {
class App;
}

namespace hv::app {

// `histoview catalog load SOURCE postgresql://... [--table NAME]`: any camera collection histoview
// reads (a scene.json's cameras, whatever their format, or a native cameras.json) into a PostGIS
// table (docs/catalog.md).
void addCatalogCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
