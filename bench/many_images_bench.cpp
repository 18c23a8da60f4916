// Many-images benchmark: a benchmark, not a test. One run prints
//   1. naive binding (a sampler2D per image and per depth map) against the array binding at T = 8;
//   2. the array binding at T = 8, 40, 128, 256, 1024 selected images, with and without per-tile
//      culling, and the ratio (array, culled, T = 256) / (naive, T = 8);
//   3. progressive depth maps: frames to converge with Dmax per frame, and time per depth map;
//   4. kNN selection (CameraIndex) for 10^3 .. 10^6 cameras, and the frame plan on the street;
//   5. memory with 4096 photographs through a 64-slot budget, the view moving along the street
//      (in a child process, so that its peak RSS is its own);
// on synthetic streets generated here: a facade covered by small photographs, each 1 m in front
// of its own 1 m patch and seeing only that patch, so T selected images cover T disjoint patches.
// Frames are 1280x720. Timings are compared as ratios against baselines measured in the same
// process (these shared machines are noisy), with process CPU time beside wall time.
// Usage: many_images_bench [--keep DIR]   (--keep: generate into DIR and leave the files there)
// Results and how to read them: docs/performance.md, "Many images".

#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/ibr/frame_plan.h"
#include "hv/ibr/selection.h"
#include "hv/image/image.h"
#include "hv/render/renderer.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"
#include "hv/image/native/png_write.h"

#include "bench_common.h"

#include <sched.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using hv::bench::kFrameHeight;
using hv::bench::kFrameWidth;

// --- Tuning constants -------------------------------------------------------------------------
// The street of parts 1-3: a facade of kRows x kCols patches of 1 m, one photograph per patch.
// The view stands kViewDistance in front of the middle of the facade and sees its full height
// (24 m) over 42.7 m of its length: ~44 x 24 = 1056 photographs pass the frustum filter, enough
// for T = 1024, each patch ~30 px wide in the frame.
constexpr int kRows = 24;
constexpr int kCols = 64;
constexpr double kViewDistance = 30.0;
// Photographs: tiny (so that 1024 slices stay small), 1 m from their patch, seeing 0.8 m of it.
constexpr int kPhotoPx = 16;
constexpr double kPhotoDistance = 1.0;
constexpr int kDepthSize = 64;     // depth maps of parts 1 and 2 (the scene has 4 triangles)
constexpr int kMaxSlices = 1100;   // >= 1024 for T = 1024 (MAX_ARRAY_TEXTURE_LAYERS is 2048 on llvmpipe)
constexpr int kSelected[] = {8, 40, 128, 256, 1024};  // T = K; the first is the ratio baseline
constexpr int kNaiveT = 8;
// Steady-state frames: one warm-up frame (loads, depth maps, shader variants), then an odd number
// of timed frames (median): as many as fit in kPointBudgetMs judging by the first timed frame,
// between 1 and kMaxRepeats.
constexpr int kMaxRepeats = 7;
constexpr double kPointBudgetMs = 6000.0;
// A frame slower than this is measured once: its warm-up frame is the measurement when that
// frame loaded no image and rendered no depth map (then it was a steady frame already).
constexpr double kSlowFrameMs = 20000.0;
// Part 3: progressive depth maps.
constexpr int kConvergeT = 256;
constexpr int kConvergeDmax = 8;
constexpr int kConvergeDepthSizes[] = {64, 512};
constexpr int kConvergeFrameCap = 200;
// Part 4: kNN.
constexpr int kKnnSizes[] = {1000, 10000, 100000, 1000000};
constexpr int kKnnQueries = 20000;
constexpr int kKnnCount = 9;  // K + 1 for K = 8
// Part 5: 4096 photographs (kMemRows x kMemCols), a 64-slot budget, K = 64, the view moved along.
constexpr int kMemRows = 16;
constexpr int kMemCols = 256;
constexpr int kMemSlots = 64;
constexpr double kMemStep = 6.0;  // metres between successive views

using namespace hv::bench;


double peakRssMiB() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return ru.ru_maxrss / 1024.0;  // kilobytes on Linux
}

// This process image's own high-water mark (VmHWM). ru_maxrss can be larger: Linux carries the
// peak of the image a process replaced through execve (here, the forked copy of the parent).
double hwmMiB() {
  std::ifstream f("/proc/self/status");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::atof(line.c_str() + 6) / 1024.0;  // kB
  return -1.0;
}

double currentRssMiB() {
  std::ifstream f("/proc/self/statm");
  long pages = 0, resident = 0;
  if (!(f >> pages >> resident)) return -1.0;
  return resident * double(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

double mib(std::size_t bytes) { return bytes / (1024.0 * 1024.0); }


void rule() { std::printf("%s\n", std::string(100, '-').c_str()); }

// --- Synthetic street -------------------------------------------------------------------------
const glm::dvec3 kOrigin{651000.0, 6862000.0, 40.0};
constexpr double kWallY = 10.0;

hv::Camera lookAt(const std::string& id, glm::dvec3 center, glm::dvec3 target, int w, int h, double focal) {
  return hv::lookAtCamera(id, center, target, w, h, focal);
}

hv::Image8 solid(int w, int h, int seed) {
  hv::Image8 img(w, h, 3);
  const std::uint8_t r = std::uint8_t(40 + 37 * (seed % 7)), g = std::uint8_t(30 + 23 * (seed / 7 % 9)),
                     b = std::uint8_t(20 + 19 * (seed / 63 % 11));
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      img.at(x, y, 0) = r;
      img.at(x, y, 1) = g;
      img.at(x, y, 2) = b;
    }
  return img;
}

// The street: ground (z = 0, y in [-40, 10]) and a facade in the plane y = 10 facing -y,
// x in [0, cols], z in [0, rows], above `kOrigin`; one photograph per 1 m patch.
hv::Scene makeStreet(int rows, int cols, const fs::path& dir, bool patchPhotos = true) {
  fs::create_directories(dir);
  const glm::dvec3 o = kOrigin;
  hv::Scene s;
  s.origin = o;
  s.terrain.positions = {o + glm::dvec3(-10, -40, 0), o + glm::dvec3(cols + 10, -40, 0),
                         o + glm::dvec3(cols + 10, kWallY, 0), o + glm::dvec3(-10, kWallY, 0)};
  s.terrain.triangles = {{0, 1, 2}, {0, 2, 3}};
  s.buildings.positions = {o + glm::dvec3(0, kWallY, 0), o + glm::dvec3(cols, kWallY, 0),
                           o + glm::dvec3(cols, kWallY, rows), o + glm::dvec3(0, kWallY, rows)};
  s.buildings.triangles = {{0, 2, 1}, {0, 3, 2}};
  const double focal = kPhotoPx * kPhotoDistance / 0.8;  // 0.8 m of the patch across the image
  for (int i = 0; patchPhotos && i < rows * cols; ++i) {
    const glm::dvec3 patch = o + glm::dvec3(i % cols + 0.5, kWallY, i / cols + 0.5);
    hv::Photo p;
    p.camera = lookAt("p" + std::to_string(i), patch - glm::dvec3(0, kPhotoDistance, 0), patch, kPhotoPx, kPhotoPx,
                      focal);
    p.imagePath = (dir / (p.camera.id + ".png")).string();
    hv::writePng(p.imagePath, solid(kPhotoPx, kPhotoPx, i));
    s.photos.push_back(std::move(p));
  }
  return s;
}

// The same street with 8 photographs instead, each taken near the view and covering all of it:
// the "8 images covering everything" that 256 disjoint ones are compared with.
hv::Scene makeWideStreet(int rows, int cols, const fs::path& dir) {
  hv::Scene s = makeStreet(rows, cols, dir, false);  // geometry only
  const glm::dvec3 o = kOrigin;
  const glm::dvec3 target = o + glm::dvec3(cols / 2.0, kWallY, rows / 2.0);
  const double viewWidth = kFrameWidth * double(rows) / kFrameHeight;  // metres of facade the view sees
  for (int i = 0; i < kNaiveT; ++i) {
    // 1 m apart along the street, 1 m behind the view, looking straight at the facade; 256x144 px
    // covering 1.4 times the width the view sees (and 1.4 times its height).
    const glm::dvec3 c = o + glm::dvec3(cols / 2.0 - 3.5 + i, kWallY - kViewDistance - 1.0, rows / 2.0);
    const double focal = 256.0 * (kViewDistance + 1.0) / (1.4 * viewWidth);
    hv::Photo p;
    p.camera = lookAt("w" + std::to_string(i), c, glm::dvec3(c.x, target.y, target.z), 256, 144, focal);
    p.imagePath = (dir / (p.camera.id + ".png")).string();
    hv::writePng(p.imagePath, solid(256, 144, 100 + i));
    s.photos.push_back(std::move(p));
  }
  return s;
}

// The view of parts 1-3: in front of the middle of the facade, its full height in the 720 rows.
hv::Camera streetView(int rows, double x) {
  const glm::dvec3 target = kOrigin + glm::dvec3(x, kWallY, rows / 2.0);
  const double focal = kFrameHeight * kViewDistance / rows;
  return lookAt("view", target - glm::dvec3(0, kViewDistance, 0), target, kFrameWidth, kFrameHeight, focal);
}

hv::render::RenderSettings streetSettings() {
  hv::render::RenderSettings s;
  s.blend.sigma = 100.0;  // near-uniform weights: every selected image contributes where it sees
  s.blend.featherPx = 0.0;  // the papers' blend, the one the naive binding has
  s.depthSize = kDepthSize;
  s.maxSlices = kMaxSlices;
  return s;
}

// One steady-state measurement: warm-up frame, then timed frames (see kPointBudgetMs).
struct Point {
  int selected = 0;      // images in the frame plan
  int slots = 0;         // the renderer's image slots
  double meanList = 0, maxList = 0;
  double meanLoop = -1.0;  // culled: mean shading-loop length over covered pixels (untimed frame)
  double covered = 0.0;    // fraction of the frame some image textures
  std::vector<Timing> t;
  Timing m;              // median
  Timing warm;           // the warm-up frame
  bool steady = true;    // no image loaded nor depth map rendered during the timed frames
  bool warmWasTimed = false;
};

Point measurePoint(hv::render::Renderer& r, const hv::Camera& view) {
  Point p;
  const hv::render::RenderStats beforeWarm = r.stats();
  p.warm = measure([&] { r.render(view); });
  const hv::render::RenderStats before = r.stats();
  const bool warmSteady = before.imagesLoaded == beforeWarm.imagesLoaded &&
                          before.depthMapsRendered == beforeWarm.depthMapsRendered;
  if (p.warm.wall > kSlowFrameMs && warmSteady) {
    p.t.push_back(p.warm);
    p.warmWasTimed = true;
  } else {
    p.t.push_back(measure([&] { r.render(view); }));
  }
  int reps = int(std::clamp(kPointBudgetMs / std::max(p.t[0].wall, 1.0), 1.0, double(kMaxRepeats)));
  if (reps % 2 == 0) --reps;
  while (int(p.t.size()) < reps) p.t.push_back(measure([&] { r.render(view); }));
  const hv::render::RenderStats after = r.stats();
  p.steady = after.imagesLoaded == before.imagesLoaded && after.depthMapsRendered == before.depthMapsRendered;
  p.selected = int(r.lastPlan().images.size());
  p.slots = r.sliceCount();
  p.meanList = r.settings().tileCulling ? after.meanTileList : 0.0;
  p.maxList = r.settings().tileCulling ? after.maxTileList : 0;
  p.m = median(p.t);
  if (r.settings().tileCulling) {
    // One more frame, untimed, with the debug outputs: how long each pixel's loop really is.
    const hv::render::RenderOutput out = r.render(view, true);
    double sum = 0.0;
    long n = 0;
    for (int y = 0; y < out.rgba.height; ++y)
      for (int x = 0; x < out.rgba.width; ++x)
        if (out.rgba.at(x, y, 3) != 0) sum += out.loopLengths.at(x, y, 0), ++n;
    p.meanLoop = n > 0 ? sum / n : 0.0;
    p.covered = double(n) / (double(out.rgba.width) * out.rgba.height);
  }
  return p;
}

std::string rangeOf(const Point& p) {
  double lo = 1e300, hi = 0;
  for (const auto& t : p.t) lo = std::min(lo, t.wall), hi = std::max(hi, t.wall);
  char b[48];
  std::snprintf(b, sizeof b, "%.0f..%.0f", lo, hi);
  return b;
}

std::string what(const std::exception& e) {
  std::string s = e.what();
  if (s.size() > 80) s = s.substr(0, 77) + "...";
  return s;
}

// --- 1. Naive vs array at T = 8 ----------------------------------------------------------------
// maxSlices: the naive binding's slots, i.e. the samplers its shader declares (at most its cap).
std::optional<Point> naivePoint(const hv::Scene& scene, const hv::Camera& view, bool culled, int maxSlices,
                                hv::Diagnostics& diag, const char* label) {
  try {
    hv::render::RenderSettings s = streetSettings();
    s.binding = hv::render::Binding::Naive;
    s.blend.k = kNaiveT;
    s.tileCulling = culled;
    s.maxSlices = maxSlices;
    hv::render::Renderer r(scene, s, diag);
    Point p = measurePoint(r, view);
    return p;
  } catch (const std::exception& e) {
    std::printf("  %-34s n/a: %s\n", label, what(e).c_str());
    return std::nullopt;
  }
}

// --- Output helpers ----------------------------------------------------------------------------
std::string ratio(double a, double b) {
  if (!(b > 0)) return "n/a";
  char s[32];
  std::snprintf(s, sizeof s, "%.2fx", a / b);
  return s;
}

void header() {
  std::printf("  %-30s %5s %5s %6s %5s %5s %5s %3s %9s %13s %9s\n", "", "sel", "slots", "cover", "list", "list",
              "loop", "n", "wall ms", "wall", "cpu ms");
  std::printf("  %-30s %5s %5s %6s %5s %5s %5s %3s %9s %13s %9s\n", "", "", "", "%", "mean", "max", "mean", "",
              "median", "min..max", "median");
}

void row(const std::string& label, const Point& p) {
  char cover[16] = "-", loop[16] = "-";
  if (p.meanLoop >= 0) {
    std::snprintf(cover, sizeof cover, "%.1f", 100.0 * p.covered);
    std::snprintf(loop, sizeof loop, "%.1f", p.meanLoop);
  }
  std::printf("  %-30s %5d %5d %6s %5.1f %5.0f %5s %3d %9.1f %13s %9.1f\n", label.c_str(), p.selected, p.slots, cover,
              p.meanList, p.maxList, loop, int(p.t.size()), p.m.wall, rangeOf(p).c_str(), p.m.cpu);
  if (!p.steady) std::printf("    warning: images loaded or depth maps rendered during the timed frames\n");
  if (p.warmWasTimed)
    std::printf("    one frame only: over %.0f s, and the warm-up frame (%.1f s) had nothing to load, so it is the "
                "measurement\n", kSlowFrameMs / 1000.0, p.warm.wall / 1000.0);
  else if (p.t.size() == 1)
    std::printf("    one timed frame only (it took %.1f s; the warm-up %.1f s)\n", p.t[0].wall / 1000.0,
                p.warm.wall / 1000.0);
}

// --- 3. Convergence ----------------------------------------------------------------------------
// Frames to converge: a fresh renderer, preload(view) (images resident, no depth map yet), then
// progressive frames until converged(). Time per depth map: another fresh renderer, warmed up on
// a view at the end of the street (other images: shaders JIT-compiled, view targets made), then
// preload(view) and one batch frame, which renders the T depth maps before shading; minus the
// steady batch frame, divided by the maps it rendered. (The progressive frames cannot give it:
// an image whose map is not current is left out of the frame, so they shade fewer images.)
void benchConvergence(const hv::Scene& scene, const hv::Camera& view, hv::Diagnostics& diag) {
  std::printf("\n3. Progressive depth maps: T = %d, Dmax = %d per frame, after preload(view); 1280x720, culled\n",
              kConvergeT, kConvergeDmax);
  rule();
  std::printf("  %6s %6s %8s %6s %10s %10s %10s %6s %10s %10s %9s %9s\n", "depth", "frames", "expected", "maps",
              "frame ms", "frame cpu", "steady ms", "maps", "batch ms", "steady ms", "ms/map", "cpu/map");
  std::printf("  %6s %6s %8s %6s %10s %10s %10s %6s %10s %10s %9s %9s\n", "", "", "ceil T/D", "", "mean conv.",
              "mean conv.", "", "batch", "all maps", "no map", "", "");
  for (int size : kConvergeDepthSizes) {
    try {
      hv::render::RenderSettings s = streetSettings();
      s.depthSize = size;
      s.blend.k = kConvergeT;
      s.maxSlices = kConvergeT + 8;
      s.depthMapsPerFrame = kConvergeDmax;
      s.tileCulling = true;
      int frames = 0, maps = 0, selected = 0, maxPer = 0;
      bool done = false;
      Timing total, steady;
      {
        hv::render::Renderer r(scene, s, diag);
        r.preload(view);
        const int maps0 = r.stats().depthMapsRendered;
        while (frames < kConvergeFrameCap && !done) {
          const Timing t = measure([&] { r.render(view, false, hv::render::FrameMode::Progressive); });
          total.wall += t.wall;
          total.cpu += t.cpu;
          ++frames;
          maxPer = std::max(maxPer, r.stats().depthMapsThisFrame);
          done = r.converged();
        }
        maps = r.stats().depthMapsRendered - maps0;
        selected = int(r.lastPlan().images.size());
        std::vector<Timing> st;
        for (int i = 0; i < 3; ++i)
          st.push_back(measure([&] { r.render(view, false, hv::render::FrameMode::Progressive); }));
        steady = median(st);
      }
      // Time per depth map.
      int batchMaps = 0;
      Timing batch, batchSteady;
      {
        hv::render::Renderer r(scene, s, diag);
        hv::render::RenderSettings& rs = r.settings();
        rs.blend.k = kNaiveT;
        r.render(streetView(kRows, 0.0));  // the street's left end: other photographs
        rs.blend.k = kConvergeT;
        r.preload(view);
        const int m0 = r.stats().depthMapsRendered;
        batch = measure([&] { r.render(view); });
        batchMaps = r.stats().depthMapsRendered - m0;
        std::vector<Timing> st;
        for (int i = 0; i < 3; ++i) st.push_back(measure([&] { r.render(view); }));
        batchSteady = median(st);
      }
      const int expected = (selected + kConvergeDmax - 1) / kConvergeDmax;
      std::printf("  %5d² %6d %8d %6d %10.1f %10.1f %10.1f %6d %10.1f %10.1f %9.3f %9.3f%s\n", size, frames, expected,
                  maps, total.wall / frames, total.cpu / frames, steady.wall, batchMaps, batch.wall, batchSteady.wall,
                  batchMaps ? (batch.wall - batchSteady.wall) / batchMaps : 0.0,
                  batchMaps ? (batch.cpu - batchSteady.cpu) / batchMaps : 0.0, done ? "" : "  (not converged)");
      std::printf("         %d selected; at most %d depth maps in one progressive frame; converging frames %.0f ms "
                  "in all (cpu %.0f)\n",
                  selected, maxPer, total.wall, total.cpu);
    } catch (const std::exception& e) {
      std::printf("  %5d² n/a: %s\n", size, what(e).c_str());
    }
  }
  std::printf("  ms/map = (batch frame rendering every map - steady batch frame) / maps (wall; cpu likewise)\n");
  rule();
}

// --- 4. kNN -------------------------------------------------------------------------------------
void benchKnn(const hv::Scene& street, const hv::Camera& view) {
  std::printf("\n4. kNN selection: CameraIndex over N random centres (10 km x 10 km x 50 m), nearest(q, %d)\n",
              kKnnCount);
  rule();
  std::printf("  %9s %10s %10s %12s %12s %10s\n", "N", "build ms", "build cpu", "us/query", "cpu us/query",
              "vs 10^3");
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> ux(0.0, 10000.0), uz(0.0, 50.0);
  std::vector<glm::dvec3> queries(kKnnQueries);
  for (auto& q : queries) q = {ux(rng), ux(rng), uz(rng)};
  double base = 0.0;
  for (int n : kKnnSizes) {
    std::vector<glm::dvec3> c(static_cast<size_t>(n));
    for (auto& p : c) p = {ux(rng), ux(rng), uz(rng)};
    std::optional<hv::ibr::CameraIndex> index;
    const Timing build = measure([&] { index.emplace(std::move(c)); });
    std::size_t sink = 0;
    const Timing q = measure([&] {
      for (const auto& x : queries) sink += index->nearest(x, kKnnCount).size();
    });
    if (sink != size_t(kKnnQueries) * kKnnCount) std::printf("  warning: %zu results\n", sink);
    const double us = q.wall * 1000.0 / kKnnQueries;
    if (base == 0.0) base = us;
    std::printf("  %9d %10.1f %10.1f %12.2f %12.2f %9.2fx\n", n, build.wall, build.cpu, us,
                q.cpu * 1000.0 / kKnnQueries, us / base);
  }
  // What the renderer does per frame: the K + 1 nearest that pass the filters, the frustum filter
  // (exact frustum overlap test) run on each centre visited.
  hv::Aabb bounds = street.terrain.bounds();
  bounds.extend(street.buildings.bounds());
  std::vector<glm::dvec3> centres;
  for (const auto& p : street.photos) centres.push_back(p.camera.center);
  const hv::ibr::CameraIndex index(centres);
  std::printf("  planFrame on the street (%zu photographs, frustum filter on), per frame:\n", street.photos.size());
  for (int t : kSelected) {
    hv::ibr::BlendSettings s;
    s.k = t;
    s.sigma = 100.0;
    size_t got = 0;
    const int reps = t >= 256 ? 5 : 21;
    std::vector<Timing> ts;
    for (int i = 0; i < reps; ++i)
      ts.push_back(measure([&] { got = hv::ibr::planFrame(street, index, view, s, bounds).images.size(); }));
    const Timing m = median(ts);
    std::printf("    T = %4d: %4zu selected, %8.2f ms (cpu %.2f ms)\n", t, got, m.wall, m.cpu);
  }
  rule();
}

// --- 5. Memory at 4096 photographs (child process) ------------------------------------------------
int memoryPart(const fs::path& dir) {
  std::printf("\n5. Memory: %d photographs (%dx%d px), %d-slot budget, K = %d, view moved along the street\n",
              kMemRows * kMemCols, kPhotoPx, kPhotoPx, kMemSlots, kMemSlots);
  rule();
  std::printf("  (child process %d: peak RSS below is this part's alone)\n", int(getpid()));
  const double rss0 = peakRssMiB(), hwm0 = hwmMiB();
  auto context = hv::gpu::createHeadlessContext();
  const double rssContext = peakRssMiB(), hwmContext = hwmMiB();
  hv::Scene scene;
  const Timing gen = measure([&] { scene = makeStreet(kMemRows, kMemCols, dir / "street4096"); });
  const double rssScene = peakRssMiB(), hwmScene = hwmMiB();
  hv::Diagnostics diag;
  hv::render::RenderSettings s = streetSettings();
  s.maxSlices = kMemSlots;
  s.blend.k = kMemSlots;
  hv::render::Renderer r(scene, s, diag);
  const double rssRenderer = peakRssMiB(), hwmRenderer = hwmMiB();
  std::vector<Timing> frames;
  int views = 0;
  double minX = 1e9, maxX = -1e9;
  const double half = 0.5 * kFrameWidth * double(kMemRows) / kFrameHeight;  // half the width the view sees
  for (double x = half; x <= kMemCols - half + 1e-9; x += kMemStep) {
    const hv::Camera view = streetView(kMemRows, x);
    frames.push_back(measure([&] { r.render(view); }));
    ++views;
    minX = std::min(minX, x), maxX = std::max(maxX, x);
    if (int(r.lastPlan().images.size()) != kMemSlots)
      std::printf("  warning: view at x = %.0f selected %zu\n", x, r.lastPlan().images.size());
  }
  const auto& st = r.stats();
  const std::size_t perSlot = std::size_t(kPhotoPx) * kPhotoPx * 4 + std::size_t(kDepthSize) * kDepthSize * 4;
  std::printf("  street generated (PNG files) in %.0f ms, not part of the figures below\n", gen.wall);
  std::printf("  %d views, x = %.0f .. %.0f m every %.0f m (the facade is %d m long); frame median %.0f ms "
              "(cpu %.0f ms)\n",
              views, minX, maxX, kMemStep, kMemCols, median(frames).wall, median(frames).cpu);
  std::printf("  images loaded (decoded + uploaded) %d; depth maps rendered %d; slots %d\n", st.imagesLoaded,
              st.depthMapsRendered, r.sliceCount());
  std::printf("  RenderStats::sliceBytes      %10zu B  (%.2f MiB; %zu B per slot x %d; all %d resident: %.1f MiB)\n",
              st.sliceBytes, mib(st.sliceBytes), perSlot, r.sliceCount(), kMemRows * kMemCols,
              mib(perSlot * size_t(kMemRows) * kMemCols));
  std::printf("  RenderStats::decodePeakBytes %10zu B  (%.3f MiB; cap %.0f MiB)\n", st.decodePeakBytes,
              mib(st.decodePeakBytes), mib(s.decodeMemoryBytes));
  std::printf("  peak RSS (getrusage ru_maxrss): start %.1f MiB, + EGL context %.1f, + scene %.1f, + renderer %.1f,"
              " end %.1f MiB\n",
              rss0, rssContext, rssScene, rssRenderer, peakRssMiB());
  std::printf("  peak RSS (/proc VmHWM, this image): start %.1f MiB, + EGL context %.1f, + scene %.1f, + renderer "
              "%.1f, end %.1f MiB (current RSS %.1f MiB)\n",
              hwm0, hwmContext, hwmScene, hwmRenderer, hwmMiB(), currentRssMiB());
  rule();
  return diag.ok() ? 0 : 1;
}

// Part 5 runs in a child process (this binary again, --memory-part), started before this process
// creates a GL context or a scene: its peak RSS is then its own (execve carries the peak of the
// image it replaces, here the forked copy of a still small parent). Its output is kept and
// printed at the end, as part 5.
struct ChildResult {
  int status = 1;
  std::string output;
};

ChildResult runMemoryChild(const fs::path& dir) {
  std::fflush(stdout);
  std::fflush(stderr);
  int fds[2];
  if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
  const std::string d = dir.string();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    close(fds[0]);
    dup2(fds[1], 1);
    dup2(fds[1], 2);
    close(fds[1]);
    execl("/proc/self/exe", "many_images_bench", "--memory-part", d.c_str(), static_cast<char*>(nullptr));
    std::perror("execl");
    _exit(127);
  }
  close(fds[1]);
  ChildResult r;
  char buf[4096];
  for (ssize_t n; (n = read(fds[0], buf, sizeof buf)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      break;
    }
    r.output.append(buf, size_t(n));
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  r.status = WIFEXITED(status) ? WEXITSTATUS(status) : 1;
  return r;
}

// --- Main run ----------------------------------------------------------------------------------
int run(const fs::path& dir) {
  const auto t0 = Clock::now();
  std::printf("(part 5, memory, runs first in a child process; its report comes last)\n");
  const ChildResult memory = runMemoryChild(dir);
  auto context = hv::gpu::createHeadlessContext();
  const hv::gpu::GlLimits l = hv::gpu::queryLimits();
  const char* lp = std::getenv("LP_NUM_THREADS");
  std::printf("histoview many-images benchmark\n");
  rule();
  std::printf("  GL            %s | %s | %s\n", l.vendor.c_str(), l.renderer.c_str(), l.version.c_str());
  std::printf("  limits        MAX_ARRAY_TEXTURE_LAYERS %d, MAX_TEXTURE_IMAGE_UNITS %d, MAX_TEXTURE_SIZE %d\n",
              l.maxArrayTextureLayers, l.maxTextureImageUnits, l.maxTextureSize);
  std::printf("  CPUs (nproc)  %d\n", cpuCount());
  std::printf("  LP_NUM_THREADS %s\n", lp ? lp : "(unset: llvmpipe picks one thread per CPU)");
  std::printf("  load average  %s (at start)\n", loadAverage().c_str());
  std::printf("  work dir      %s\n", dir.c_str());
  rule();

  hv::Scene street, wide;
  const Timing gen = measure([&] {
    street = makeStreet(kRows, kCols, dir / "street");
    wide = makeWideStreet(kRows, kCols, dir / "wide8");
  });
  const hv::Camera view = streetView(kRows, kCols / 2.0);
  std::printf("  street: facade %d m x %d m, %zu photographs %dx%d px (one per 1 m patch, each seeing only its "
              "patch),\n          depth maps %d², view %dx%d at %.0f m seeing 42.7 m x 24 m (~30 px per patch)\n",
              kCols, kRows, street.photos.size(), kPhotoPx, kPhotoPx, kDepthSize, kFrameWidth, kFrameHeight,
              kViewDistance);
  std::printf("  wide8:  the same geometry and view, 8 photographs 256x144 px each covering the whole view\n");
  std::printf("  (generated in %.0f ms, not timed below)\n", gen.wall);
  hv::Diagnostics diag;

  // 1. Naive vs array at T = 8.
  std::printf("\n1. Naive binding vs array binding, T = K = %d, %dx%d (warm-up, then median of n frames)\n", kNaiveT,
              kFrameWidth, kFrameHeight);
  rule();
  header();
  std::optional<Point> naiveStreet = naivePoint(street, view, false, kNaiveT, diag, "naive, street, 8 slots");
  if (naiveStreet) row("naive, street, 8 slots", *naiveStreet);
  // The same with the naive binding's full cap of samplers declared (HV_NAIVE_COUNT): its shader
  // reaches image i through a chain of `if (i == j)` over every declared sampler.
  std::optional<Point> naiveCap = naivePoint(street, view, false, kMaxSlices, diag, "naive, street, cap slots");
  if (naiveCap) row("naive, street, cap slots", *naiveCap);
  std::optional<Point> naiveWide = naivePoint(wide, view, false, kNaiveT, diag, "naive, wide8, 8 slots");
  if (naiveWide) row("naive, wide8, 8 slots", *naiveWide);
  std::optional<Point> arrayWide, arrayWideCulled, arrayStreet;
  try {
    hv::render::RenderSettings s = streetSettings();
    s.blend.k = kNaiveT;
    s.tileCulling = false;
    hv::render::Renderer r(wide, s, diag);
    {
      hv::render::RenderSettings a = s;
      a.maxSlices = kNaiveT;
      hv::render::Renderer rs(street, a, diag);
      arrayStreet = measurePoint(rs, view);
      row("array, street, 8 slots, uncul.", *arrayStreet);
    }
    arrayWide = measurePoint(r, view);
    row("array, wide8, unculled", *arrayWide);
    r.settings().tileCulling = true;
    arrayWideCulled = measurePoint(r, view);
    row("array, wide8, culled", *arrayWideCulled);
  } catch (const std::exception& e) {
    std::printf("  %-30s n/a: %s\n", "array, wide8", what(e).c_str());
  }
  std::printf("  load average now %s\n", loadAverage().c_str());
  rule();

  // 2. Array binding against T, culled and not.
  std::printf("\n2. Array binding on the street, T = K selected images (disjoint patches), %dx%d\n", kFrameWidth,
              kFrameHeight);
  rule();
  header();
  struct Entry {
    int t;
    bool culled;
    Point p;
  };
  std::vector<Entry> entries;
  {
    hv::render::RenderSettings s = streetSettings();
    hv::render::Renderer r(street, s, diag);
    for (int t : kSelected) {
      // Culled first: the unculled frame's warm-up then has nothing to load (see kSlowFrameMs).
      for (bool culled : {true, false}) {
        r.settings().blend.k = t;
        r.settings().tileCulling = culled;
        char label[64];
        std::snprintf(label, sizeof label, "array, T = %4d, %s", t, culled ? "culled" : "unculled");
        try {
          Point p = measurePoint(r, view);
          row(label, p);
          if (p.selected != t) std::printf("    warning: %d selected, not %d\n", p.selected, t);
          std::fflush(stdout);
          entries.push_back({t, culled, p});
        } catch (const std::exception& e) {
          std::printf("  %-30s n/a: %s\n", label, what(e).c_str());
        }
      }
    }
  }
  const Point* array8 = nullptr;
  for (const auto& e : entries)
    if (e.t == kSelected[0] && !e.culled) array8 = &e.p;
  std::printf("\n  ratios (median frame time; wall / cpu)\n");
  std::printf("  %-30s %17s %17s %17s %17s\n", "", "vs naive street 8", "vs naive wide8", "vs array street 8",
              "vs array wide8");
  std::printf("  %-30s %17s %17s %17s %17s\n", "", "(8 slots)", "(8 cover all)", "(unculled)", "(unculled)");
  auto both = [](const Point& a, const std::optional<Point>& b) {
    if (!b) return std::string("n/a");
    return ratio(a.m.wall, b->m.wall) + " / " + ratio(a.m.cpu, b->m.cpu);
  };
  for (const auto& e : entries) {
    char label[64];
    std::snprintf(label, sizeof label, "array, T = %4d, %s", e.t, e.culled ? "culled" : "unculled");
    std::printf("  %-30s %17s %17s %17s %17s\n", label, both(e.p, naiveStreet).c_str(), both(e.p, naiveWide).c_str(),
                array8 ? both(e.p, *array8).c_str() : "n/a", both(e.p, arrayWide).c_str());
  }
  if (arrayWide && naiveWide)
    std::printf("  array/naive at T = 8, wide8 (same scene, unculled): %s wall, %s cpu\n",
                ratio(arrayWide->m.wall, naiveWide->m.wall).c_str(), ratio(arrayWide->m.cpu, naiveWide->m.cpu).c_str());
  if (arrayStreet && naiveStreet)
    std::printf("  array/naive at T = 8, street (same view, unculled, 8 slots each): %s wall, %s cpu\n",
                ratio(arrayStreet->m.wall, naiveStreet->m.wall).c_str(),
                ratio(arrayStreet->m.cpu, naiveStreet->m.cpu).c_str());
  if (array8 && naiveStreet)
    std::printf("  array/naive at T = 8, street (array with %d slots, as in the table above): %s wall, %s cpu\n",
                kMaxSlices, ratio(array8->m.wall, naiveStreet->m.wall).c_str(),
                ratio(array8->m.cpu, naiveStreet->m.cpu).c_str());
  for (const auto& e : entries)
    if (e.t == 256 && e.culled) {
      std::printf("  KEY (array, culled, T = 256) / (naive, T = 8, street): %s wall, %s cpu\n",
                  naiveStreet ? ratio(e.p.m.wall, naiveStreet->m.wall).c_str() : "n/a",
                  naiveStreet ? ratio(e.p.m.cpu, naiveStreet->m.cpu).c_str() : "n/a");
      std::printf("      (array, culled, T = 256) / (naive, T = 8, wide8):  %s wall, %s cpu\n",
                  naiveWide ? ratio(e.p.m.wall, naiveWide->m.wall).c_str() : "n/a",
                  naiveWide ? ratio(e.p.m.cpu, naiveWide->m.cpu).c_str() : "n/a");
      if (array8)
        std::printf("      (array, culled, T = 256) / (array, unculled, T = 8, street): %s wall, %s cpu\n",
                    ratio(e.p.m.wall, array8->m.wall).c_str(), ratio(e.p.m.cpu, array8->m.cpu).c_str());
      if (arrayWideCulled)
        std::printf("      (array, culled, T = 256) / (array, culled, T = 8, wide8): %s wall, %s cpu\n",
                    ratio(e.p.m.wall, arrayWideCulled->m.wall).c_str(),
                    ratio(e.p.m.cpu, arrayWideCulled->m.cpu).c_str());
    }
  std::printf("  load average now %s\n", loadAverage().c_str());
  rule();
  std::fflush(stdout);

  benchConvergence(street, view, diag);
  std::fflush(stdout);
  benchKnn(street, view);
  std::fflush(stdout);
  context.reset();

  std::fputs(memory.output.c_str(), stdout);
  if (memory.status != 0) std::printf("  (the memory part exited with status %d)\n", memory.status);
  const int child = memory.status;
  std::printf("\ntotal %.0f s; load average now %s\n", msSince(t0) / 1000.0, loadAverage().c_str());
  if (!diag.ok()) {
    std::printf("%zu error(s) (listed above): figures may be off\n", diag.errors.size());
    return 1;
  }
  return child;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    if (argc == 3 && std::string(argv[1]) == "--memory-part") return memoryPart(argv[2]);
    WorkDir dir;
    if (argc == 3 && std::string(argv[1]) == "--keep") {
      dir.path = argv[2];
      dir.keep = true;
    } else if (argc == 1) {
      dir.path = fs::temp_directory_path() / ("hv-many-images-bench-" + std::to_string(getpid()));
    } else {
      std::fprintf(stderr, "usage: %s [--keep DIR]\n", argv[0]);
      return 2;
    }
    return run(dir.path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
