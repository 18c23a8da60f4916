#include "hv/app/path_command.h"

#include "hv/io/camera_path_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/scene_scale.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"
#include "hv/viewer/tour.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

namespace hv::app {

namespace fs = std::filesystem;

namespace {

struct PathOptions {
  std::string scene;
  std::string out;
  std::string size = "1280x720";
  // tour
  std::optional<double> stepBack, speed;
  double holdSeconds = viewer::FocusContextSettings{}.holdSeconds;
  // orbit
  std::string around;
  bool local = false;
  std::optional<double> radius;
  viewer::OrbitSettings orbit;
};

void writePath(const std::string& file, const std::vector<PathKey>& keys) {
  const CameraPath path(keys);  // the checks fly makes when it reads the file
  const fs::path out = fs::absolute(file);
  if (out.has_parent_path()) fs::create_directories(out.parent_path());
  std::ofstream f(out);
  if (!f) throw std::runtime_error(file + ": cannot write");
  f << cameraPathJson(keys);
  if (!f) throw std::runtime_error(file + ": write failed");
  std::cout << "wrote " << file << ": " << keys.size() << " key cameras, " << std::fixed << std::setprecision(1)
            << path.endTime() - path.startTime() << " s (fly it: histoview fly SCENE --path " << file
            << " --out DIR)\n";
}

int runTour(const PathOptions& o) {
  const glm::ivec2 size = parseSize(o.size);
  Diagnostics diag;
  const Scene scene = loadScene(o.scene, diag);
  if (scene.photos.empty()) throw InputError(o.scene + ": no photograph to visit (a tour needs cameras)");
  std::vector<glm::dvec3> centres;
  for (const Photo& p : scene.photos) centres.push_back(p.camera.center);
  const std::vector<int> order = viewer::tourOrder(centres);
  std::vector<Camera> cameras;
  for (int i : order) cameras.push_back(scene.photos[size_t(i)].camera);
  const SceneScale scale = sceneScale(scene);
  for (const std::string& w : scale.warnings) std::cerr << "warning: " << o.scene << ": " << w << "\n";
  const viewer::ScaleDefaults defaults = viewer::scaleDefaults(scale.scale);
  viewer::TourSettings t;
  t.focus.up = scene.up;
  t.focus.holdSeconds = o.holdSeconds;
  t.focus.stepBack = o.stepBack.value_or(defaults.stepBack);
  t.speed = o.speed.value_or(defaults.speed);
  std::cout << "tour of " << cameras.size() << " photograph(s) in street order, " << std::setprecision(4)
            << viewer::pathLength(centres, order) << " units from first to last; step back " << t.focus.stepBack
            << ", speed " << t.speed << " units/s\n";
  writePath(o.out, viewer::focusContextKeys(cameras, size.x, size.y, t));
  return exitStatus(diag, 0);
}

int runOrbit(const PathOptions& o) {
  const glm::ivec2 size = parseSize(o.size);
  glm::dvec3 around = parseVec3("--around", o.around);
  Diagnostics diag;
  const Scene scene = loadScene(o.scene, diag);
  if (o.local) around += scene.origin;
  viewer::OrbitSettings s = o.orbit;
  s.radius = o.radius.value_or(viewer::scaleDefaults(sceneScale(scene).scale).orbitRadius);
  writePath(o.out, viewer::orbitKeys(around, scene.up, size.x, size.y, s));
  return exitStatus(diag, 0);
}

void commonOptions(CLI::App& cmd, PathOptions& o) {
  cmd.add_option("scene", o.scene, "scene.json")->required()->check(CLI::ExistingFile);
  cmd.add_option("-o,--out", o.out, "the camera path to write (PATH.json, read by fly --path)")->required();
  cmd.add_option("--size", o.size, "image size of the key cameras, WxH (default 1280x720)");
}

}  // namespace

void addPathCommand(CLI::App& app, int& exitCode) {
  auto* path = app.add_subcommand("path", "make a camera path for fly: a tour of the photographs, an orbit");
  path->require_subcommand(1);
  auto o = std::make_shared<PathOptions>();

  auto* tour = path->add_subcommand(
      "tour",
      "a walk through the photographs in street order: at each, its view (focus), then a step back "
      "(context)");
  commonOptions(*tour, *o);
  tour->add_option("--step-back", o->stepBack,
                   "context: distance stepped back from each photograph (default: "
                   "the scene's scale, as `info` prints it)")
      ->check(CLI::NonNegativeNumber);
  tour->add_option("--speed", o->speed,
                   "travel speed between photographs, scene units/s (default: half the "
                   "scene's scale per second)")
      ->check(CLI::PositiveNumber);
  tour->add_option("--hold", o->holdSeconds, "seconds spent at each photograph's view")->check(CLI::NonNegativeNumber);
  setAction(*tour, exitCode, [o] { return runTour(*o); });

  auto* orbit = path->add_subcommand("orbit", "one turn around a point, looking at it");
  commonOptions(*orbit, *o);
  orbit
      ->add_option("--around", o->around,
                   "the point looked at, X,Y,Z (scene CRS; with --local, the render "
                   "frame)")
      ->required();
  orbit->add_flag("--local", o->local, "--around is in the render frame (scene frame minus `info`'s origin)");
  orbit->add_option("--radius", o->radius, "horizontal distance from the point (default: twice the scene's scale)")
      ->check(CLI::PositiveNumber);
  orbit->add_option("--elevation", o->orbit.elevationDeg, "degrees above the point's horizon (default 30)")
      ->check(CLI::Range(-89.0, 89.0));
  orbit->add_option("--seconds", o->orbit.seconds, "time of one turn (default 24)")->check(CLI::PositiveNumber);
  orbit->add_option("--fov", o->orbit.fovDeg, "horizontal field of view, degrees (default 60)")
      ->check(CLI::Range(1.0, 170.0));
  setAction(*orbit, exitCode, [o] { return runOrbit(*o); });
}

}  // namespace hv::app
