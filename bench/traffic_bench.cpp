// Traffic benchmark: a benchmark, not a test. Frame time at 1280x720 of a demo street view with 0,
// 100 and 1,000 vehicles on the ground in front of it (and with traffic off), each count on a
// renderer of its own, as the median of steady frames; the ratios are against 0 vehicles, measured
// in the same process, because these shared machines are noisy from one run to the next. The
// vehicles are drawn instanced (render/gl/vehicles_pass.cpp): their cost should be a small
// fraction of the image-based pass (the 2013 paper's traffic, docs/traffic.md).
// Usage: traffic_bench [--keep DIR]. Results: docs/performance.md ("Traffic").

#include "hv/demo/demo_city.h"
#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/renderer.h"
#include "hv/render/vehicles.h"
#include "hv/traffic/lift.h"
#include "hv/traffic/trajectories.h"
#include "hv/traffic/vehicle_model.h"
#include "hv/util/diagnostics.h"

#include "bench_common.h"

#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace hv::bench;

namespace {

constexpr int kCounts[] = {0, 100, 1000};  // the first is the ratio baseline
constexpr int kWarmupFrames = 2;           // images, depth maps, shader variants
constexpr int kFrameRepeats = 7;
constexpr double kTime = 5.0;  // seconds: every vehicle is on the road (samples at 0 and 10)

// `count` vehicles parked on the ground 6 to 90 m in front of the view, within its horizontal field
// of view, in the scene frame, at random headings (seeded: the same vehicles on every run).
hv::Trajectories vehiclesInFront(const hv::Camera& view, int count) {
  hv::Trajectories t;
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> depth(6.0, 90.0), side(-0.5, 0.5), heading(0.0, 360.0);
  const glm::dvec3 forward = view.rayDirection(view.principal);
  glm::dvec2 f(forward.x, forward.y);
  f = glm::length(f) > 0.0 ? glm::normalize(f) : glm::dvec2(0.0, 1.0);
  const glm::dvec2 right(f.y, -f.x);
  const double halfWidth = 0.5 * view.width / view.focal.x;  // tan of the half field of view
  for (int i = 0; i < count; ++i) {
    hv::Trajectory v;
    v.id = "bench" + std::to_string(i);
    v.type = "passenger";
    v.size = hv::vehicleSizeOf(v.type);
    const double d = depth(rng);
    const glm::dvec2 xy = glm::dvec2(view.center) + d * f + 2.0 * side(rng) * halfWidth * d * right;
    const double a = heading(rng);
    v.samples = {{0.0, xy, a}, {10.0, xy, a}};
    t.vehicles.push_back(std::move(v));
  }
  t.tBegin = 0.0;
  t.tEnd = count > 0 ? 10.0 : 0.0;
  return t;
}

Timing steadyFrame(hv::Scene scene, const hv::Camera& view, bool enabled, hv::Diagnostics& diag) {
  hv::render::RenderSettings settings;
  settings.traffic.enabled = enabled;
  settings.traffic.time = kTime;
  hv::render::Renderer renderer(scene, settings, diag);
  for (int i = 0; i < kWarmupFrames; ++i) renderer.render(view);
  std::vector<Timing> t;
  for (int i = 0; i < kFrameRepeats; ++i) t.push_back(measure([&] { renderer.render(view); }));
  return median(t);
}

int run(const fs::path& dir) {
  auto context = hv::gpu::createHeadlessContext();
  const hv::gpu::GlLimits l = hv::gpu::queryLimits();
  std::printf("histoview traffic benchmark\n");
  std::printf("  GL %s | %s; CPUs %d; load average %s (at start)\n", l.vendor.c_str(), l.renderer.c_str(),
              cpuCount(), loadAverage().c_str());
  hv::demo::DemoOptions options;
  hv::demo::DemoSummary summary;
  const double genMs = timeMs([&] { summary = hv::demo::generate(options, (dir / "city").string()); });
  std::printf("  demo city generated in %.0f ms (not timed below): %d buildings, %d photos\n", genMs,
              summary.buildings, summary.photos);
  hv::Diagnostics diag;
  hv::Scene scene = hv::loadScene(summary.scenePath, diag);
  hv::CameraFileOptions o;
  o.requireImages = false;
  o.checkImageFiles = false;
  const auto views = hv::readCameraFile(summary.viewsPath, o, diag);
  if (views.empty()) throw std::runtime_error(summary.viewsPath + ": no view");
  const hv::Camera view = crop720p(views.front().camera);
  std::printf("\nFrame time at %dx%d, view %s (median of %d frames after %d warm-up, a renderer per row)\n",
              view.width, view.height, view.id.c_str(), kFrameRepeats, kWarmupFrames);
  std::printf("  %-22s %10s %10s %9s %10s\n", "vehicles", "wall ms", "cpu ms", "vs 0", "+ms/1000");
  // The demo's glTF models (scene.json traffic.models), when SUMO ran; else the box with wheels.
  const std::shared_ptr<const hv::VehicleModels> models = scene.traffic ? scene.traffic->models : nullptr;
  std::printf("  vehicle model: %s\n", models ? "the demo's glTF car" : "the built-in box with wheels");
  Timing base;
  for (int n : kCounts) {
    hv::Trajectories traffic = vehiclesInFront(view, n);
    traffic.models = models;
    scene.traffic = std::make_shared<const hv::Trajectories>(std::move(traffic));
    const Timing t = steadyFrame(scene, view, true, diag);
    if (n == 0) base = t;
    const double per1000 = n > 0 ? (t.wall - base.wall) * 1000.0 / n : 0.0;
    std::printf("  %-22d %10.1f %10.1f %8.2fx %10.1f\n", n, t.wall, t.cpu, t.wall / base.wall, per1000);
  }
  // The CPU part of the cost: sampling and lifting every vehicle (the frame builder's part).
  {
    const hv::MeshTerrainHeight terrain(scene.terrain);
    std::vector<double> t;
    std::size_t shown = 0;
    for (int i = 0; i < kFrameRepeats; ++i)
      t.push_back(timeMs([&] { shown = hv::render::vehicleInstances(*scene.traffic, terrain, kTime, scene.origin).size(); }));
    std::printf("  of which, on the CPU: sampling and lifting the %zu vehicles on the terrain, %.2f ms\n", shown,
                median(t));
  }
  const Timing off = steadyFrame(scene, view, false, diag);
  std::printf("  %-22s %10.1f %10.1f %8.2fx\n", "1000, traffic off", off.wall, off.cpu, off.wall / base.wall);
  std::printf("load average now %s\n", loadAverage().c_str());
  if (!diag.ok()) {
    std::printf("%zu input error(s): figures may be off\n", diag.errors.size());
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  WorkDir dir;
  if (argc == 3 && std::strcmp(argv[1], "--keep") == 0) {
    dir.path = argv[2];
    dir.keep = true;
  } else if (argc == 1) {
    dir.path = fs::temp_directory_path() / ("hv-traffic-bench-" + std::to_string(::getpid()));
  } else {
    std::fprintf(stderr, "usage: traffic_bench [--keep DIR]\n");
    return 2;
  }
  try {
    return run(dir.path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
