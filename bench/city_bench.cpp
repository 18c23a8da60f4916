// City-scale benchmark: a benchmark, not a test. Generates (or takes) two large demo cities, about
// 1k and 100k buildings (`histoview demo --blocks N`), whose centres are identical: the same
// photographs, the same held-out views, the same ground truth (docs/demo-city.md). For each city,
// in a child process of its own (so that its peak RSS is its own), it measures:
//   - generation: wall time and peak RSS (skipped when the city is already in --dir);
//   - load (`loadScene`, what `histoview info` does), EGL context, Renderer construction;
//   - on the same 4 street views at 1280x720, K = 8, progressive frames as a viewer renders them:
//     time to the first frame and to the converged frame (from process start for the first view,
//     from the move for the others), then the steady frame time (median of batch frames);
//   - triangles and tiles the view draws per frame (RenderStats::trianglesDrawn / tilesDrawn,
//     after geometry culling), peak RSS;
// and prints the large/small ratios, measured in the same run.
// Usage: city_bench [--dir DIR] [--blocks SMALL,LARGE]
//        city_bench --first CITY [MINPX]  (one city already generated: start to first frame by
//                   stage, then the building tiles each view draws; MINPX: --building-min-pixels)
//   --dir DIR: generate the cities into DIR/blocks<N>/ and keep them; a city already there is
//              reused (its generation is then not measured). Default: a temporary directory.
//   --blocks:  the two sizes (default 185,18519: 1,003 and 99,711 buildings).
// Results and how to read them: docs/performance.md ("City scale").

#include "hv/demo/demo_city.h"
#include "hv/gpu/context.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/renderer.h"
#include "hv/util/diagnostics.h"

#include "bench_common.h"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using namespace hv::bench;

// --- Tuning constants -------------------------------------------------------------------------
constexpr int kDefaultSmallBlocks = 185;    // 1,003 buildings
constexpr int kDefaultLargeBlocks = 18519;  // 99,711 buildings, 7.8 km x 7.8 km
constexpr int kPhotos = 64;                 // as the renderer benchmark's second city
constexpr int kViews = 4;                   // the first four held-out views (all at street level)
constexpr int kSteadyFrames = 5;            // batch frames per view once converged (median)
constexpr int kMaxProgressiveFrames = 400;  // per view, in case a view never converges
constexpr double kMaxConvergeMs = 180e3;

double statusMiB(const char* key) {  // a /proc/self/status figure in kB, as MiB
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind(key, 0) == 0) return std::atof(line.c_str() + std::strlen(key)) / 1024.0;
  return -1.0;
}
double hwmMiB() { return statusMiB("VmHWM:"); }  // this process image's peak RSS
double rssMiB() { return statusMiB("VmRSS:"); }  // its resident set now

void rule() { std::printf("%s\n", std::string(78, '-').c_str()); }

// A child reports "RESULT key value" lines; everything else it prints is passed through.
using Results = std::map<std::string, double>;
void result(const char* key, double value) { std::printf("RESULT %s %.6g\n", key, value); }

// --- Child: generation ------------------------------------------------------------------------
int childGenerate(const std::string& dir, int blocks) {
  hv::demo::DemoOptions o;
  o.blocks = blocks;
  o.photos = kPhotos;
  hv::demo::DemoSummary s;
  const Timing t = measure([&] {
    s = hv::demo::generate(o, dir, [](const std::string& line) {
      if (line.find("photograph ") == std::string::npos && line.find("view ") == std::string::npos)
        std::printf("    %s\n", line.c_str());
    });
  });
  result("generate_ms", t.wall);
  result("generate_cpu_ms", t.cpu);
  result("generate_hwm_mib", hwmMiB());
  result("buildings", s.buildings);
  return 0;
}

// --- Child: load, frames ----------------------------------------------------------------------
int childMeasure(const std::string& dir) {
  const auto start = Clock::now();
  hv::Diagnostics diag;
  const std::string scenePath = (fs::path(dir) / "scene.json").string();
  hv::Scene scene;
  const Timing load = measure([&] { scene = hv::loadScene(scenePath, diag); });
  const double hwmLoad = hwmMiB();
  hv::CameraFileOptions vo;
  vo.requireImages = false;
  vo.checkImageFiles = false;
  const auto views = hv::readCameraFile((fs::path(dir) / "views.json").string(), vo, diag);
  if (int(views.size()) < kViews) throw std::runtime_error(dir + ": fewer than 4 held-out views");
  std::unique_ptr<hv::gpu::Context> context;
  const double contextMs = timeMs([&] { context = hv::gpu::createHeadlessContext(); });
  std::unique_ptr<hv::render::Renderer> renderer;
  hv::render::RenderSettings settings;
  const Timing setup = measure([&] { renderer = std::make_unique<hv::render::Renderer>(scene, settings, diag); });
  const double hwmSetup = hwmMiB();
  const double sceneTriangles = double(scene.terrain.triangles.size() + scene.buildings.triangles.size());
  std::printf(
      "    load %.0f ms (%zu terrain + %zu building triangles, %zu photos), context %.0f ms, renderer %.0f ms\n",
      load.wall, scene.terrain.triangles.size(), scene.buildings.triangles.size(), scene.photos.size(), contextMs,
      setup.wall);
  result("load_ms", load.wall);
  result("load_cpu_ms", load.cpu);
  result("load_hwm_mib", hwmLoad);
  result("context_ms", contextMs);
  result("setup_ms", setup.wall);
  result("setup_cpu_ms", setup.cpu);
  result("setup_hwm_mib", hwmSetup);
  result("scene_triangles", sceneTriangles);

  std::vector<double> frameWall, frameCpu, firstMs, convergeMs, frames;
  double drawnTriangles = 0.0, drawnTiles = 0.0, buildingTiles = 0.0;
  for (int v = 0; v < kViews; ++v) {
    const hv::Camera view = crop720p(views[size_t(v)].camera);
    const auto moved = Clock::now();
    renderer->render(view, false, hv::render::FrameMode::Progressive);
    const double first = msSince(moved);
    int n = 1;
    while (!renderer->converged() && n < kMaxProgressiveFrames && msSince(moved) < kMaxConvergeMs) {
      renderer->render(view, false, hv::render::FrameMode::Progressive);
      ++n;
    }
    const double converged = msSince(moved);
    if (!renderer->converged()) std::printf("    warning: view %s did not converge\n", view.id.c_str());
    if (v == 0) {
      result("start_to_first_frame_ms", msSince(start) - converged + first);
      result("start_to_converged_ms", msSince(start));
    }
    std::vector<Timing> t;
    for (int i = 0; i < kSteadyFrames; ++i) t.push_back(measure([&] { renderer->render(view); }));
    const Timing m = median(t);
    const double tri = double(renderer->stats().trianglesDrawn), tiles = double(renderer->stats().tilesDrawn);
    drawnTriangles += tri / kViews;
    drawnTiles += tiles / kViews;
    buildingTiles += double(renderer->stats().buildingViewTiles) / kViews;
    std::printf(
        "    view %-10s first frame %8.0f ms, converged after %3d frames %8.0f ms, steady %8.1f ms (cpu %.1f)\n",
        view.id.c_str(), first, n, converged, m.wall, m.cpu);
    firstMs.push_back(first);
    convergeMs.push_back(converged);
    frames.push_back(n);
    frameWall.push_back(m.wall);
    frameCpu.push_back(m.cpu);
  }
  result("first_frame_ms", median(firstMs));
  result("converge_ms", median(convergeMs));
  result("converge_frames", median(frames));
  result("frame_ms", median(frameWall));
  result("frame_cpu_ms", median(frameCpu));
  result("triangles_drawn", drawnTriangles);
  result("tiles_drawn", drawnTiles);
  result("building_tiles_drawn", buildingTiles);
  result("peak_hwm_mib", hwmMiB());
  return diag.ok() ? 0 : 1;
}

// --- Start to first frame alone (--first CITY) --------------------------------------------------
// What a viewer opening the city waits for, stage by stage (wall and process CPU): loadScene,
// the EGL context, the Renderer's construction, and the first progressive frame of view v001 at
// 1280x720 (the first frame the viewer shows). For profiling and before/after comparisons of the
// start; the full benchmark above gives the rest.
int childFirst(const std::string& dir, double minPixels) {
  const auto start = Clock::now();
  hv::Diagnostics diag;
  hv::Scene scene;
  const Timing load = measure([&] { scene = hv::loadScene((fs::path(dir) / "scene.json").string(), diag); });
  const double rssLoad = rssMiB();
  hv::CameraFileOptions vo;
  vo.requireImages = false;
  vo.checkImageFiles = false;
  const auto views = hv::readCameraFile((fs::path(dir) / "views.json").string(), vo, diag);
  if (views.empty()) throw std::runtime_error(dir + ": no held-out view");
  std::unique_ptr<hv::gpu::Context> context;
  const Timing ctx = measure([&] { context = hv::gpu::createHeadlessContext(); });
  std::unique_ptr<hv::render::Renderer> renderer;
  hv::render::RenderSettings settings;
  if (minPixels >= 0.0) settings.buildingMinPixels = minPixels;
  const Timing setup = measure([&] { renderer = std::make_unique<hv::render::Renderer>(scene, settings, diag); });
  const double rssSetup = rssMiB();
  const hv::Camera view = crop720p(views[0].camera);
  const Timing first = measure([&] { renderer->render(view, false, hv::render::FrameMode::Progressive); });
  const double total = msSince(start);
  const auto& st = renderer->stats();
  std::printf("    RSS after load %.0f MiB, after the renderer %.0f MiB, after the first frame %.0f MiB (peak %.0f)\n",
              rssLoad, rssSetup, rssMiB(), hwmMiB());
  std::printf(
      "%s: load %.0f ms (cpu %.0f), context %.0f (cpu %.0f), renderer %.0f (cpu %.0f), first frame %.0f "
      "(cpu %.0f): start to first frame %.0f ms; view tiles drawn %d, triangles %zu; load average %s\n",
      dir.c_str(), load.wall, load.cpu, ctx.wall, ctx.cpu, setup.wall, setup.cpu, first.wall, first.cpu, total,
      int(st.tilesDrawn), std::size_t(st.trianglesDrawn), loadAverage().c_str());
  // The building tiles the views draw once converged (--building-min-pixels at `minPixels`).
  for (int v = 0; v < std::min(kViews, int(views.size())); ++v) {
    const hv::Camera c = crop720p(views[size_t(v)].camera);
    const Timing t = measure([&] { renderer->render(c); });  // a batch frame: converged
    const auto& s = renderer->stats();
    std::printf(
        "    view %s: converged %.0f ms (cpu %.0f), %d building tiles drawn, %lld triangles drawn, %d building tiles resident (%.0f MiB, "
        "terrain %d tiles %.0f MiB, depth and image arrays %.0f MiB); RSS %.0f MiB, peak %.0f MiB\n",
        c.id.c_str(), t.wall, t.cpu, s.buildingViewTiles, (long long)s.trianglesDrawn, s.buildingTilesResident,
        double(s.buildingBytes) / (1 << 20), s.terrainTilesResident, double(s.terrainBytes) / (1 << 20),
        double(s.sliceBytes) / (1 << 20), rssMiB(), hwmMiB());
  }
  return 0;
}

// --- Parent -----------------------------------------------------------------------------------
Results runChild(const std::vector<std::string>& args) {
  std::fflush(stdout);
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    close(fds[0]);
    dup2(fds[1], 1);
    dup2(fds[1], 2);
    close(fds[1]);
    std::vector<char*> argv{const_cast<char*>("city_bench")};
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    execv("/proc/self/exe", argv.data());
    std::perror("execv");
    _exit(127);
  }
  close(fds[1]);
  Results r;
  std::string pending;
  char buf[4096];
  auto flushLines = [&](bool all) {
    for (size_t nl; (nl = pending.find('\n')) != std::string::npos || (all && !pending.empty());) {
      const std::string line = nl == std::string::npos ? pending : pending.substr(0, nl);
      pending.erase(0, nl == std::string::npos ? pending.size() : nl + 1);
      if (line.rfind("RESULT ", 0) == 0) {
        std::istringstream in(line.substr(7));
        std::string key;
        double value = 0.0;
        if (in >> key >> value) r[key] = value;
      } else {
        std::printf("%s\n", line.c_str());
        std::fflush(stdout);
      }
    }
  };
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    pending.append(buf, size_t(n));
    flushLines(false);
  }
  flushLines(true);
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) r["failed"] = 1.0;
  return r;
}

int runParent(const fs::path& dir, int smallBlocks, int largeBlocks) {
  const auto t0 = Clock::now();
  std::printf("histoview city-scale benchmark\n");
  rule();
  std::printf("  CPUs %d, load average %s (start)\n", cpuCount(), loadAverage().c_str());
  std::printf("  cities: --blocks %d and %d, %d photographs, views 1-%d at %dx%d, K = 8, in %s\n", smallBlocks,
              largeBlocks, kPhotos, kViews, kFrameWidth, kFrameHeight, dir.string().c_str());
  rule();
  std::vector<Results> cities;
  for (int blocks : {smallBlocks, largeBlocks}) {
    const fs::path city = dir / ("blocks" + std::to_string(blocks)) / "city";
    Results r;
    if (fs::exists(city / "scene.json")) {
      std::printf("\ncity --blocks %d: taken from %s (generation not measured)\n", blocks, city.string().c_str());
    } else {
      std::printf("\ncity --blocks %d: generating into %s\n", blocks, city.string().c_str());
      r = runChild({"--generate", city.string(), std::to_string(blocks)});
      if (r.count("failed")) throw std::runtime_error("generation failed");
      std::printf("    generated in %.1f s, peak RSS %.0f MiB, %.0f buildings\n", r["generate_ms"] / 1e3,
                  r["generate_hwm_mib"], r["buildings"]);
    }
    std::printf("city --blocks %d: load and frames\n", blocks);
    const Results m = runChild({"--measure", city.string()});
    if (m.count("failed")) std::printf("    warning: the measuring process failed or reported errors\n");
    r.insert(m.begin(), m.end());
    cities.push_back(r);
  }
  const Results& a = cities[0];
  const Results& b = cities[1];
  std::printf("\nSummary (medians over views %d-%d; ratio = --blocks %d / --blocks %d, same run)\n", 1, kViews,
              largeBlocks, smallBlocks);
  rule();
  std::printf("  %-44s %12s %12s %9s\n", "", ("blocks " + std::to_string(smallBlocks)).c_str(),
              ("blocks " + std::to_string(largeBlocks)).c_str(), "ratio");
  auto row = [&](const char* label, const char* key, double scale, const char* fmt) {
    const bool has = a.count(key) && b.count(key);
    if (!has) {
      std::printf("  %-44s %12s %12s %9s\n", label, "-", "-", "-");
      return;
    }
    const double x = a.at(key) * scale, y = b.at(key) * scale;
    char sx[32], sy[32];
    std::snprintf(sx, sizeof sx, fmt, x);
    std::snprintf(sy, sizeof sy, fmt, y);
    if (x > 0 && y >= 0)
      std::printf("  %-44s %12s %12s %8.2fx\n", label, sx, sy, y / x);
    else
      std::printf("  %-44s %12s %12s %9s\n", label, sx, sy, "-");
  };
  row("buildings", "buildings", 1.0, "%.0f");
  row("generate (s)", "generate_ms", 1e-3, "%.1f");
  row("generate, CPU (s)", "generate_cpu_ms", 1e-3, "%.1f");
  row("generate peak RSS (MiB)", "generate_hwm_mib", 1.0, "%.0f");
  row("load = loadScene, as `info` (ms)", "load_ms", 1.0, "%.0f");
  row("load, CPU (ms)", "load_cpu_ms", 1.0, "%.0f");
  row("RSS after load (MiB)", "load_hwm_mib", 1.0, "%.0f");
  row("Renderer construction (ms)", "setup_ms", 1.0, "%.0f");
  row("Renderer construction, CPU (ms)", "setup_cpu_ms", 1.0, "%.0f");
  row("start to first frame, view 1 (ms)", "start_to_first_frame_ms", 1.0, "%.0f");
  row("start to converged frame, view 1 (ms)", "start_to_converged_ms", 1.0, "%.0f");
  row("first frame after a move (ms)", "first_frame_ms", 1.0, "%.0f");
  row("move to converged frame (ms)", "converge_ms", 1.0, "%.0f");
  row("frames to converge", "converge_frames", 1.0, "%.0f");
  row("steady frame, wall (ms)", "frame_ms", 1.0, "%.1f");
  row("steady frame, CPU (ms)", "frame_cpu_ms", 1.0, "%.1f");
  row("scene triangles", "scene_triangles", 1.0, "%.0f");
  row("triangles drawn per frame", "triangles_drawn", 1.0, "%.0f");
  row("tiles drawn per frame", "tiles_drawn", 1.0, "%.0f");
  row("  of which building tiles (streamed)", "building_tiles_drawn", 1.0, "%.0f");
  row("peak RSS (MiB)", "peak_hwm_mib", 1.0, "%.0f");
  rule();
  std::printf("  load average %s (end), %.0f s in all\n", loadAverage().c_str(), msSince(t0) / 1e3);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    if (args.size() == 3 && args[0] == "--generate") return childGenerate(args[1], std::stoi(args[2]));
    if (args.size() == 2 && args[0] == "--measure") return childMeasure(args[1]);
    if ((args.size() == 2 || args.size() == 3) && args[0] == "--first")
      return childFirst(args[1], args.size() == 3 ? std::stod(args[2]) : -1.0);
    WorkDir work;
    int smallBlocks = kDefaultSmallBlocks, largeBlocks = kDefaultLargeBlocks;
    for (size_t i = 0; i < args.size(); ++i) {
      if (args[i] == "--dir" && i + 1 < args.size()) {
        work.path = args[++i];
        work.keep = true;
      } else if (args[i] == "--blocks" && i + 1 < args.size()) {
        const std::string v = args[++i];
        const size_t comma = v.find(',');
        if (comma == std::string::npos) throw std::runtime_error("--blocks takes SMALL,LARGE");
        smallBlocks = std::stoi(v.substr(0, comma));
        largeBlocks = std::stoi(v.substr(comma + 1));
      } else {
        std::fprintf(stderr, "usage: city_bench [--dir DIR] [--blocks SMALL,LARGE]\n");
        return 2;
      }
    }
    if (work.path.empty()) {
      char tmpl[] = "/tmp/hv_city_bench_XXXXXX";
      if (!mkdtemp(tmpl)) throw std::runtime_error("cannot create a temporary directory");
      work.path = tmpl;
    }
    fs::create_directories(work.path);
    return runParent(work.path, smallBlocks, largeBlocks);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "city_bench: %s\n", e.what());
    return 1;
  }
}
