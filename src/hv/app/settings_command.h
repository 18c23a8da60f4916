// `histoview settings [--markdown | --json]`: the render settings (render/settings_schema.h) as
// the README's option table or as the JSON the browser page reads.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace hv::app {

void addSettingsCommand(CLI::App& app, int& exitCode);

// What the command prints: the markdown table (README.md, between <!-- settings:begin --> and
// <!-- settings:end -->), or with `json` the schema with defaults, indented.
std::string settingsCommandOutput(bool json);

}  // namespace hv::app
