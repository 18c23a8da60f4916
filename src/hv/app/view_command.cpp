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
  cmd->add_flag("--map", o->map, "start with the map open (M toggles it)");
  cmd->add_option("--moving-scale", o->movingScale,
                  "render resolution while moving, as a fraction of the window's (default 0.5)")
      ->check(CLI::Range(0.1, 1.0));
  cmd->add_option("--timeline", o->timeline,
                  "set the time window (from/to) on the timeline: FROM:TO, positions along it from 0 (the first "
                  "day of its first bar) to 1 (the last day of its last)");
  cmd->add_option("--play", o->playYearsPerSecond, "play the timeline from its start at this many years per second")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--traffic-play", o->trafficRate,
                  "play the traffic from --time at this many simulated seconds per second (Y: play / pause)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--then-now", o->thenNow,
                "start in then and now at --camera (a photograph): the photograph over the render without it");
  cmd->add_option("--then-now-opacity", o->thenNowOpacity,
                  "then and now: the photograph's opacity over the render, 0..1 (implies --then-now)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--then-now-swipe", o->thenNowSwipe,
                  "then and now: the photograph left of a line at this fraction of its width, 0..1 (implies "
                  "--then-now)")
      ->check(CLI::Range(0.0, 1.0))
      ->excludes("--then-now-opacity");
  cmd->add_option("--pose-script", o->poseScript,
                  "pose mode's clicks from a file, run at the first frame: enter ID, photo U V (photograph pixels), "
                  "view X Y (window pixels of the first view), remove N, focal on|off, save PATH [replace], leave "
                  "(docs/viewer.md)")
      ->check(CLI::ExistingFile);
  setAction(*cmd, exitCode, [o] { return viewer::run(*o); });
}

}  // namespace hv::app
