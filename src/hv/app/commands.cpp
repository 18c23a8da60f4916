#include "hv/app/commands.h"

#include "hv/app/cameras_command.h"
#include "hv/app/catalog_command.h"
#include "hv/app/check_command.h"
#include "hv/app/demo_command.h"
#include "hv/app/init_command.h"
#include "hv/app/eval_command.h"
#include "hv/app/fly_command.h"
#include "hv/app/harmonize_command.h"
#include "hv/app/layers_command.h"
#include "hv/session/outputs.h"
#include "hv/app/points_tiles_command.h"
#include "hv/app/pose_command.h"
#include "hv/app/render_command.h"
#include "hv/app/settings_command.h"
#include "hv/app/view_command.h"
#include "hv/app/web_export_command.h"
#include "hv/app/path_command.h"

#include <CLI/CLI.hpp>

namespace hv::app {

namespace {
int g_exit = 0;
}

void registerCommands(CLI::App& app) {
  app.footer(exitStatusHelp());
  addInitCommand(app, g_exit);
  addInfoCommand(app, g_exit);
  addCheckCommand(app, g_exit);
  addHarmonizeCommand(app, g_exit);
  addLayersCommand(app, g_exit);
  addRenderCommand(app, g_exit);
  addEvalCommand(app, g_exit);
  addFlyCommand(app, g_exit);
  addPathCommand(app, g_exit);
  addViewCommand(app, g_exit);
  addDemoCommand(app, g_exit);
  addCamerasCommand(app, g_exit);
  addCatalogCommand(app, g_exit);
  addPoseCommand(app, g_exit);
  addWebExportCommand(app, g_exit);
  addPointsTilesCommand(app, g_exit);
  addSettingsCommand(app, g_exit);
}

int exitCode() { return g_exit; }

}  // namespace hv::app
