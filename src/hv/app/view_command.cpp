#include "hv/app/view_command.h"

#include "hv/viewer/desktop/viewer.h"

#include <CLI/CLI.hpp>

#include <memory>

namespace hv::app {

void addViewCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand(
      "view", std::string("open the desktop viewer: walk or fly through the scene, photographs blended live") +
                  (viewer::available() ? "" : " (not in this build: needs GLFW and Dear ImGui)"));
  auto o = std::make_shared<viewer::ViewerOptions>();
  o->view.size = "1280x720";
  addViewOptions(*cmd, o->view, false);
  cmd->get_option("--size")->description("window size WxH (default 1280x720)");
  cmd->add_option("--views", o->view.viewsPath, "view cameras that --camera may name (cameras.json schema)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--camera", o->camera,
                  "start at this camera: a view of --views, else a photograph (default: an overview)");
  cmd->add_option("--debug", o->view.debug,
                  "start in a debug view: count (contributing images), weight:ID (photograph ID's share of each "
                  "pixel) or depth:ID (photograph ID's depth map)")
      ->check(app::debugValue());
  cmd->add_option("--screenshot", o->screenshot,
                  "write the view to this PNG (with --exit-after-converge: once converged, then exit)");
  cmd->add_flag("--screenshot-ui", o->screenshotUi, "the screenshot includes the control panel");
  cmd->add_flag("--exit-after-converge", o->exitAfterConverge,
                "exit once the view has converged (every selected image resident, depth maps current)");
  cmd->add_option("--frames", o->frames, "stop after N frames (a safety cap for tests)")->check(CLI::PositiveNumber);
  cmd->add_flag("--print-frame-times", o->printFrameTimes, "print each frame's time, and a summary at exit");
  cmd->add_flag("--redraw", o->redraw, "render every frame even when nothing changed (to measure frame times)");
  cmd->add_flag("--walk", o->walk, "start walking (default: flying)");
  cmd->add_flag("--hide-panel", o->hidePanel, "start with the control panel hidden (H toggles it)");
  cmd->add_option("--moving-scale", o->movingScale,
                  "render resolution while moving, as a fraction of the window's (default 0.5)")
      ->check(CLI::Range(0.1, 1.0));
  setAction(*cmd, exitCode, [o] { return viewer::run(*o); });
}

}  // namespace hv::app
