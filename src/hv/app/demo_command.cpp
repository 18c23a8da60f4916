// `histoview demo`: the main job on the embedded demo city. Generates the city (deterministic, no
// download), renders its held-out views with the full method, and evaluates blend against the
// baselines on the ground truth.
#include "hv/app/demo_command.h"

#include "hv/app/harmonize_command.h"
#include "hv/app/traffic_frames.h"

#include "hv/session/session.h"

#include "hv/demo/demo_city.h"
#include "hv/eval/evaluate.h"
#include "hv/gpu/context.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"

#include "hv/image/native/png_write.h"
#include "hv/session/session.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

namespace hv::app {

namespace fs = std::filesystem;

namespace {

struct DemoCommandOptions {
  std::string out = "demo-output";
  demo::DemoOptions demo;
  int k = 8;
  bool generateOnly = false;
  bool harmonize = false;
  int trafficFrames = TrafficFramesOptions{}.frames;  // 0: none
};

// `histoview harmonize` on the generated city: corrections.json beside scene.json, which then names
// it ("colour"). The city's era casts are what it corrects (docs/demo-city.md).
void harmonizeCity(const demo::DemoSummary& city) {
  const auto t0 = std::chrono::steady_clock::now();
  Diagnostics diag;
  const Scene scene = loadScene(city.scenePath, diag);
  const HarmonizeRun run = harmonizeScene(scene, ibr::HarmonizeSettings{}, 1024, diag);
  const fs::path dir = fs::path(city.scenePath).parent_path();
  std::ofstream(dir / "corrections.json") << colourCorrectionsJson(run.entries);
  nlohmann::json doc = nlohmann::json::parse(std::ifstream(city.scenePath));
  doc["colour"] = "corrections.json";
  std::ofstream(city.scenePath) << doc.dump(2) << "\n";
  std::cout << "  colour corrections: " << run.pairs << " overlap pairs, rms colour difference " << std::setprecision(2)
            << run.result.rmsBefore * 255.0 << " -> " << run.result.rmsAfter * 255.0 << " /255 ("
            << std::setprecision(1) << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()
            << " s), " << (dir / "corrections.json").string() << "\n";
}

int runDemo(const DemoCommandOptions& o) {
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const std::string cityDir = (fs::path(o.out) / "city").string();
  std::cout << "generating the demo city in " << cityDir << "\n";
  const demo::DemoSummary city =
      demo::generate(o.demo, cityDir, [](const std::string& line) { std::cout << "  " << line << "\n"; });
  std::cout << "  " << city.buildings << " buildings, " << city.photos << " photographs, " << city.views
            << " held-out views (" << std::fixed << std::setprecision(1)
            << std::chrono::duration<double>(clock::now() - t0).count() << " s)\n";
  if (o.harmonize) harmonizeCity(city);
  if (o.generateOnly) return 0;

  Diagnostics diag;
  const Scene scene = loadScene(city.scenePath, diag);
  CameraFileOptions viewOpts;
  viewOpts.requireImages = false;
  viewOpts.checkImageFiles = false;
  const std::vector<Photo> views = readCameraFile(city.viewsPath, viewOpts, diag);
  auto context = gpu::createHeadlessContext();
  render::RenderSettings settings;
  settings.blend.k = o.k;
  // The renders show what the methods cover, on black as in the papers: no shaded surfaces, no sky.
  settings.background = glm::dvec3(0.0);
  settings.untextured.shading = false;
  settings.untextured.sky = false;
  // Scored against views without traffic (docs/traffic.md: `render --time` shows it).
  settings.traffic.enabled = false;
  render::Renderer renderer(scene, settings, diag);

  const std::string renderDir = (fs::path(o.out) / "renders").string();
  fs::create_directories(renderDir);
  std::cout << "rendering " << views.size() << " views (K = " << o.k << ") into " << renderDir << "\n";
  for (const Photo& v : views) {
    const render::RenderOutput out = renderer.render(v.camera);
    const Image8 rgb = rgbOf(out.rgba);
    const std::string path = (fs::path(renderDir) / (v.camera.id + ".png")).string();
    writePng(path, rgb);
    std::cout << "  " << path << "  (" << std::setprecision(0) << renderer.stats().lastFrameMs << " ms)\n";
  }

  std::cout << "evaluating against the ground truth (" << city.truthDir << ")\n";
  eval::EvalOptions opt;
  opt.truthDir = city.truthDir;
  opt.methods = {eval::Method::Blend, eval::Method::Nearest, eval::Method::NoOcclusion};
  const eval::EvalReport report = eval::evaluate(renderer, views, opt, diag);
  std::cout << eval::formatTable(report);
  if (o.harmonize) {
    // The same blend with each photograph's own colours, for comparison.
    render::RenderSettings uncorrected = settings;
    uncorrected.blend.colourCorrection = false;
    render::Renderer plain(scene, uncorrected, diag);
    eval::EvalOptions plainOpt = opt;
    plainOpt.methods = {eval::Method::Blend};
    std::cout << "blend without the colour corrections\n"
              << eval::formatTable(eval::evaluate(plain, views, plainOpt, diag));
  }
  const std::string jsonPath = (fs::path(o.out) / "eval.json").string();
  std::ofstream(jsonPath) << eval::toJson(report).dump(2) << "\n";

  // Hybrid rendering: the same views with the simulated lidar scan drawn as textured
  // sprites over the mesh. Trees and parked cars stand in today's city only; the views (like the
  // photographs) do not show them, so they are hidden here.
  const std::string pointDir = (fs::path(o.out) / "renders-points").string();
  fs::create_directories(pointDir);
  render::RenderSettings pointSettings = settings;
  pointSettings.points.enabled = true;
  pointSettings.points.hideTransient = true;
  render::Renderer pointRenderer(scene, pointSettings, diag);
  std::cout << "\nrendering the views with the lidar scan as textured point sprites (" << scene.points.size()
            << " points; trees and cars hidden) into " << pointDir << "\n";
  for (const Photo& v : views) {
    const render::RenderOutput out = pointRenderer.render(v.camera);
    const std::string path = (fs::path(pointDir) / (v.camera.id + ".png")).string();
    writePng(path, rgbOf(out.rgba));
    std::cout << "  " << path << "  (" << std::setprecision(0) << pointRenderer.stats().lastFrameMs << " ms, "
              << pointRenderer.stats().pointsDrawn << " sprites)\n";
  }
  eval::EvalOptions pointOpt = opt;
  pointOpt.methods = {eval::Method::Blend};
  const eval::EvalReport pointReport = eval::evaluate(pointRenderer, views, pointOpt, diag);
  std::cout << "evaluating mesh + points (blend)\n" << eval::formatTable(pointReport);
  const std::string pointJson = (fs::path(o.out) / "eval-points.json").string();
  std::ofstream(pointJson) << eval::toJson(pointReport).dump(2) << "\n";

  // The traffic driving through the streets, drawn over the old photographs (docs/traffic.md).
  std::string framesLine;
  if (o.trafficFrames > 0 && scene.traffic) {
    render::RenderSettings trafficSettings;
    trafficSettings.blend.k = o.k;
    render::Renderer trafficRenderer(scene, trafficSettings, diag);
    TrafficFramesOptions frames;
    frames.frames = o.trafficFrames;
    const std::string dir = (fs::path(cityDir) / "traffic").string();
    std::cout << "\n";
    std::vector<Camera> photos;
    for (const Photo& p : scene.photos) photos.push_back(p.camera);
    if (writeTrafficFrames(trafficRenderer, *scene.traffic, MeshTerrainHeight(scene.terrain), frames, dir, photos) > 0)
      framesLine = "\ntraffic: " + (fs::path(dir) / "frames").string() + "/";
  } else if (o.trafficFrames > 0) {
    std::cout << "\nno traffic frames: the city has no traffic (SUMO did not run)\n";
  }

  std::cout << "\nscene:   " << city.scenePath << "\nrenders: " << renderDir << "/, " << pointDir
            << "/\nreports: " << jsonPath << ", " << pointJson << framesLine << "\ndone in " << std::setprecision(1)
            << std::chrono::duration<double>(clock::now() - t0).count() << " s\n";
  return diag.ok() ? 0 : 1;
}

}  // namespace

void addDemoCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("demo", "generate the demo city, render its held-out views and evaluate them");
  auto o = std::make_shared<DemoCommandOptions>();
  cmd->add_option("--out", o->out, "output directory")->capture_default_str();
  cmd->add_option("--seed", o->demo.seed, "city seed (deterministic)")->capture_default_str();
  auto* buildings = cmd->add_option("--buildings", o->demo.buildings, "number of buildings")
                        ->check(CLI::Range(1, 500))
                        ->capture_default_str();
  cmd->add_option("--blocks", o->demo.blocks,
                  "a large city of about this many blocks (6 lots each, 90 % built): ground truth, photographs "
                  "and lidar around the centre, DTM as a Cloud-Optimized GeoTIFF, footprints as a GeoPackage")
      ->check(CLI::Range(1, 20000))
      ->excludes(buildings);
  cmd->add_option("--photos", o->demo.photos, "number of photographs")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  cmd->add_option("--views", o->demo.views, "number of held-out views")
      ->check(CLI::Range(1, 1000))
      ->capture_default_str();
  cmd->add_option("--k", o->k, "images blended per pixel")->check(CLI::PositiveNumber)->capture_default_str();
  cmd->add_flag("--generate-only", o->generateOnly, "only write the city (scene, photographs, truth)");
  cmd->add_flag("--harmonize", o->harmonize,
                "also estimate the photographs' colour corrections (corrections.json, named by scene.json) and "
                "evaluate the blend with and without them (not yet the default: on the demo city the estimate "
                "is not yet reliable, docs/design.md)");
  cmd->add_option("--traffic-frames", o->trafficFrames,
                  "frames of the traffic driving through the streets, rendered last into city/traffic/frames/ "
                  "(0: none)")
      ->check(CLI::Range(0, 10000))
      ->capture_default_str();
  cmd->add_flag_callback(
      "--no-traffic-frames", [o] { o->trafficFrames = 0; }, "no traffic frames (--traffic-frames 0)");
  setAction(*cmd, exitCode, [o] { return runDemo(*o); });
}

}  // namespace hv::app
