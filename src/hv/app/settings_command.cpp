#include "hv/app/settings_command.h"

#include "hv/session/session.h"
#include "hv/render/settings_schema.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

namespace hv::app {

std::string settingsCommandOutput(bool json) {
  if (json) return nlohmann::json::parse(render::settingsJson(render::RenderSettings{})).dump(2) + "\n";
  return render::settingsMarkdown();
}

void addSettingsCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand(
      "settings", "print the render settings (the options of render, eval, fly and view): a markdown table "
                  "(README.md) or JSON");
  auto json = std::make_shared<bool>(false);
  auto markdown = std::make_shared<bool>(false);
  auto* md = cmd->add_flag("--markdown", *markdown, "the README's option table (the default)");
  cmd->add_flag("--json", *json, "the schema as JSON: name, type, range or spellings, unit, help, default")
      ->excludes(md);
  setAction(*cmd, exitCode, [json] {
    std::cout << settingsCommandOutput(*json);
    return 0;
  });
}

}  // namespace hv::app
