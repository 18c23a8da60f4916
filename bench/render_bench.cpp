// Renderer benchmark: a benchmark, not a test. One run prints
//   1. demo-city generation, scene load, renderer set-up and the first frame of a held-out view;
//   2. steady-state frame time at 1280x720 for K = 1, 8, 40 images blended;
//   3. depth-map render time per image at several depth-map sizes;
// with the context it ran on. Timings are compared as ratios against a baseline measured in the
// same process, because these shared machines are noisy from one run to the next.
// Usage: render_bench [--keep DIR]   (--keep: generate into DIR and leave the files there)
//        render_bench --quality SCENE.json VIEWS.json [WxH]   (only part 4: the picture-quality
//        options against the papers' blend on the first view of a given scene)
// Results and how to read them: docs/performance.md.

#include "hv/demo/demo_city.h"
#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/ibr/frame_plan.h"
#include "hv/ibr/selection.h"
#include "hv/ibr/slice_image.h"
#include "hv/image/image.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/gl/shade_config.h"
#include "hv/render/renderer.h"
#include "hv/util/diagnostics.h"

#include "bench_common.h"

#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

using hv::bench::crop720p;
using hv::bench::kFrameHeight;
using hv::bench::kFrameWidth;

// --- Tuning constants -------------------------------------------------------------------------
// The benchmark frame size (docs/performance.md). The demo views are 4:3 (320x240): they are scaled by 4 to 1280x960
// and the intrinsics cropped to the middle 720 rows, so the frame is a true 1280x720 one with the
// same focal length (see crop720p).
constexpr int kFrameK[] = {1, 8, 40};  // images blended; the first is the ratio baseline
// K = 40 needs at least 40 photographs that see the view: a bigger demo city for parts 2 and 3.
constexpr int kManyPhotos = 64;
// Steady-state frames: one warm-up (loads images, renders depth maps, JIT-compiles shader
// variants), then the median of kFrameRepeats frames (odd, so the median is one frame).
constexpr int kWarmupFrames = 1;
constexpr int kFrameRepeats = 7;
// Depth maps: each size gets a fresh renderer; view 0 warms it up (shader variants, view targets),
// then every other held-out view is rendered once with kDepthK images: the images it is the first
// to need cost a decode, an upload and a depth map each. The steady frame of that view and the
// CPU decode of those images are subtracted, leaving the depth maps (and the ~0.5 MB slice copy).
constexpr int kDepthSizes[] = {512, 1024, 2048};  // the first is the ratio baseline
constexpr int kDepthK = 8;
constexpr int kDepthSteadyRepeats = 3;
// Every photograph of the 64-photo city keeps its slot at 2048^2 (64 x 16.5 MB), so no image is
// evicted and loaded twice while the depth maps are counted.
constexpr std::size_t kDepthMemoryBudget = std::size_t(2) << 30;

using namespace hv::bench;


hv::Aabb geometryBounds(const hv::Scene& scene) {
  hv::Aabb b = scene.terrain.bounds();
  b.extend(scene.buildings.bounds());
  return b;
}

// How many photographs pass the renderer's frustum filter for `view` (the K slots it can fill).
int candidateCount(const hv::Scene& scene, const hv::ibr::CameraIndex& index, const hv::Camera& view) {
  hv::ibr::BlendSettings s;
  s.k = int(scene.photos.size());
  return int(hv::ibr::planFrame(scene, index, view, s, geometryBounds(scene)).images.size());
}

// What the renderer does on the CPU before uploading a photograph it has not seen: decode the
// image (and mask) and build the slice.
Timing decodeTime(const hv::Scene& scene, const std::vector<int>& photos, hv::ibr::SliceSize slice) {
  return measure([&] {
    for (int i : photos) {
      const hv::Photo& p = scene.photos[size_t(i)];
      const hv::Image8 colour = hv::readImage(p.imagePath);
      hv::Image8 mask;
      if (!p.maskPath.empty()) mask = hv::readImage(p.maskPath, 1);
      (void)hv::ibr::makeSliceImage(p.camera, colour, mask, slice, p.camera.id);
    }
  });
}

std::vector<hv::Photo> readViews(const std::string& path, hv::Diagnostics& diag) {
  hv::CameraFileOptions o;
  o.requireImages = false;
  o.checkImageFiles = false;
  auto views = hv::readCameraFile(path, o, diag);
  if (views.empty()) throw std::runtime_error(path + ": no view");
  return views;
}

void rule() { std::printf("%s\n", std::string(78, '-').c_str()); }

// --- 1. Generation, load, first frame ---------------------------------------------------------
void benchFirstFrame(const fs::path& dir) {
  std::printf("\n1. Demo city (default options), load and first frame\n");
  rule();
  hv::demo::DemoOptions options;
  hv::demo::DemoSummary summary;
  const double genMs = timeMs([&] { summary = hv::demo::generate(options, (dir / "default").string()); });
  std::printf("  %-52s %9.0f ms\n", "generate demo city (not part of load)", genMs);
  std::printf("    %d buildings, %d photos, %d views\n", summary.buildings, summary.photos, summary.views);

  hv::Diagnostics diag;
  hv::Scene scene;
  const double loadMs = timeMs([&] { scene = hv::loadScene(summary.scenePath, diag); });
  const auto views = readViews(summary.viewsPath, diag);
  std::unique_ptr<hv::gpu::Context> context;
  const double contextMs = timeMs([&] { context = hv::gpu::createHeadlessContext(); });
  std::unique_ptr<hv::render::Renderer> renderer;
  const double setupMs = timeMs(
      [&] { renderer = std::make_unique<hv::render::Renderer>(scene, hv::render::RenderSettings{}, diag); });
  const hv::Camera& view = views.front().camera;
  const double firstMs = timeMs([&] { renderer->render(view); });
  std::vector<double> steady;
  for (int i = 0; i < kFrameRepeats; ++i) steady.push_back(timeMs([&] { renderer->render(view); }));
  const double steadyMs = median(steady);
  const auto& st = renderer->stats();

  std::printf("  %-52s %9.0f ms\n", "loadScene (DTM, LOD1 buildings, cameras)", loadMs);
  std::printf("    %zu terrain + %zu building triangles, %zu photos\n", scene.terrain.triangles.size(),
              scene.buildings.triangles.size(), scene.photos.size());
  std::printf("  %-52s %9.0f ms\n", "headless EGL context", contextMs);
  std::printf("  %-52s %9.0f ms\n", "Renderer construction (shaders, geometry, slots)", setupMs);
  char label[128];
  std::snprintf(label, sizeof label, "first frame, view %s %dx%d, K = %d", view.id.c_str(), view.width,
                view.height, renderer->settings().blend.k);
  std::printf("  %-52s %9.0f ms\n", label, firstMs);
  std::printf("    %d images decoded and uploaded, %d depth maps (%d^2)\n", st.imagesLoaded,
              st.depthMapsRendered, renderer->settings().depthSize);
  std::printf("  %-52s %9.0f ms\n", "load + construction + first frame",
              loadMs + contextMs + setupMs + firstMs);
  std::printf("  %-52s %9.1f ms\n", "same view, steady state (median)", steadyMs);
  rule();
}

// --- 2. Frame time against K ------------------------------------------------------------------
void benchFrames(const hv::Scene& scene, const std::vector<hv::Photo>& views, hv::Diagnostics& diag) {
  std::printf("\n2. Steady-state frame time at %dx%d (median of %d frames after %d warm-up)\n", kFrameWidth,
              kFrameHeight, kFrameRepeats, kWarmupFrames);
  rule();
  // The view that the most photographs see, so that K = 40 blends 40 images.
  const hv::ibr::CameraIndex index([&] {
    std::vector<glm::dvec3> c;
    for (const auto& p : scene.photos) c.push_back(p.camera.center);
    return c;
  }());
  int best = 0, bestCount = -1;
  for (size_t i = 0; i < views.size(); ++i) {
    const int n = candidateCount(scene, index, crop720p(views[i].camera));
    if (n > bestCount) best = int(i), bestCount = n;
  }
  const hv::Camera view = crop720p(views[size_t(best)].camera);
  hv::render::RenderSettings settings;
  const int maxK = *std::max_element(std::begin(kFrameK), std::end(kFrameK));
  // Below maxK candidates the frustum filter would cap K; lifting it keeps K honest (the shader
  // loops over every image whether or not it covers the pixel).
  settings.blend.frustumFilter = bestCount >= maxK;
  std::printf("  view %s (%d of %zu photographs see it%s)\n", view.id.c_str(), bestCount, scene.photos.size(),
              settings.blend.frustumFilter ? "" : "; frustum filter off to reach K");
  hv::render::Renderer renderer(scene, settings, diag);

  std::printf("  %4s %7s %11s %11s %9s %9s %11s %9s\n", "K", "images", "median ms", "min..max", "vs K=1",
              "cpu ms", "cpu vs K=1", "ms/image");
  struct Point {
    int images;
    Timing t;
  };
  std::vector<Point> points;
  for (int k : kFrameK) {
    renderer.settings().blend.k = k;
    for (int i = 0; i < kWarmupFrames; ++i) renderer.render(view);
    const hv::render::RenderStats before = renderer.stats();
    std::vector<Timing> t;
    for (int i = 0; i < kFrameRepeats; ++i) t.push_back(measure([&] { renderer.render(view); }));
    const hv::render::RenderStats after = renderer.stats();
    if (after.imagesLoaded != before.imagesLoaded || after.depthMapsRendered != before.depthMapsRendered)
      std::printf("  warning: K = %d loaded images during the timed frames (not steady)\n", k);
    const int images = int(renderer.lastPlan().images.size());
    const Timing m = median(t);
    points.push_back({images, m});
    const Timing& base = points.front().t;
    auto byWall = [](const Timing& x, const Timing& y) { return x.wall < y.wall; };
    char range[32];
    std::snprintf(range, sizeof range, "%.0f..%.0f", std::min_element(t.begin(), t.end(), byWall)->wall,
                  std::max_element(t.begin(), t.end(), byWall)->wall);
    std::printf("  %4d %7d %11.1f %11s %8.2fx %9.1f %10.2fx %9.1f\n", k, images, m.wall, range,
                m.wall / base.wall, m.cpu, m.cpu / base.cpu, m.wall / std::max(images, 1));
  }
  // Marginal cost of one more image: the slope between the two largest K, free of the fixed cost
  // (view depth pass, readback) that the ms/image column still carries.
  const Point& a = points[points.size() - 2];
  const Point& b = points.back();
  if (b.images > a.images)
    std::printf("  marginal cost per image (K %d -> %d): %.1f ms wall, %.1f ms cpu per %dx%d frame\n",
                a.images, b.images, (b.t.wall - a.t.wall) / (b.images - a.images),
                (b.t.cpu - a.t.cpu) / (b.images - a.images), kFrameWidth, kFrameHeight);
  rule();
}

// --- 3. Depth maps ----------------------------------------------------------------------------
void benchDepthMaps(const hv::Scene& scene, const std::vector<hv::Photo>& views, hv::Diagnostics& diag) {
  std::printf("\n3. Depth-map render time (K = %d, held-out views at their own size, %zu triangles)\n",
              kDepthK, scene.terrain.triangles.size() + scene.buildings.triangles.size());
  rule();
  std::printf("  %6s %6s %10s %10s %10s %10s %8s %10s %8s\n", "size", "maps", "first ms", "steady ms",
              "decode ms", "ms/map", "vs 512", "cpu ms/map", "vs 512");
  Timing baseline;
  for (int size : kDepthSizes) {
    hv::render::RenderSettings settings;
    settings.depthSize = size;
    settings.blend.k = kDepthK;
    settings.memoryBudgetBytes = kDepthMemoryBudget;
    hv::render::Renderer renderer(scene, settings, diag);
    std::set<int> resident;
    auto remember = [&] {
      for (const auto& im : renderer.lastPlan().images) resident.insert(im.photo);
    };
    renderer.render(views.front().camera);
    remember();
    const int mapsBefore = renderer.stats().depthMapsRendered;
    Timing first, steady, decode;
    int predicted = 0;
    for (size_t v = 1; v < views.size(); ++v) {
      const hv::Camera& view = views[v].camera;
      first += measure([&] { renderer.render(view); });
      std::vector<int> fresh;
      for (const auto& im : renderer.lastPlan().images)
        if (!resident.count(im.photo)) fresh.push_back(im.photo);
      remember();
      predicted += int(fresh.size());
      std::vector<Timing> t;
      for (int i = 0; i < kDepthSteadyRepeats; ++i) t.push_back(measure([&] { renderer.render(view); }));
      steady += median(t);
      decode += decodeTime(scene, fresh, renderer.sliceSize());
    }
    const int maps = renderer.stats().depthMapsRendered - mapsBefore;
    if (maps != predicted)
      std::printf("  warning: %d depth maps rendered, %d expected (an image was evicted and reloaded)\n",
                  maps, predicted);
    if (maps == 0) throw std::runtime_error("no depth map rendered after the warm-up view");
    const Timing perMap{(first.wall - steady.wall - decode.wall) / maps,
                        (first.cpu - steady.cpu - decode.cpu) / maps};
    if (baseline.wall == 0.0) baseline = perMap;
    std::printf("  %6d %6d %10.0f %10.0f %10.0f %10.1f %7.2fx %10.1f %7.2fx\n", size, maps, first.wall,
                steady.wall, decode.wall, perMap.wall, perMap.wall / baseline.wall, perMap.cpu,
                perMap.cpu / baseline.cpu);
  }
  std::printf("  ms/map = (first - steady - decode) / maps, summed over views 2..%zu (wall; cpu likewise)\n",
              views.size());
  rule();
}

int run(const fs::path& dir) {
  // The context first: the GL strings head the report, and a missing GL fails before generating.
  {
    auto context = hv::gpu::createHeadlessContext();
    const hv::gpu::GlLimits l = hv::gpu::queryLimits();
    const char* lp = std::getenv("LP_NUM_THREADS");
    std::printf("histoview render benchmark\n");
    rule();
    std::printf("  GL            %s | %s | %s\n", l.vendor.c_str(), l.renderer.c_str(), l.version.c_str());
    std::printf("  CPUs (nproc)  %d\n", cpuCount());
    std::printf("  LP_NUM_THREADS %s\n", lp ? lp : "(unset: llvmpipe picks one thread per CPU)");
    std::printf("  load average  %s (at start)\n", loadAverage().c_str());
    std::printf("  work dir      %s\n", dir.c_str());
    rule();
  }  // a context per part: each part is self-contained

  const auto t0 = Clock::now();
  benchFirstFrame(dir);

  hv::demo::DemoOptions many;
  many.photos = kManyPhotos;
  hv::demo::DemoSummary summary;
  const double genMs = timeMs([&] { summary = hv::demo::generate(many, (dir / "many").string()); });
  std::printf("\n(demo city with %d photos for parts 2 and 3: generated in %.0f ms, not timed below)\n",
              summary.photos, genMs);
  hv::Diagnostics diag;
  const hv::Scene scene = hv::loadScene(summary.scenePath, diag);
  const auto views = readViews(summary.viewsPath, diag);
  auto context = hv::gpu::createHeadlessContext();
  benchFrames(scene, views, diag);
  benchDepthMaps(scene, views, diag);
  std::printf("\ntotal %.0f s; load average now %s\n", msSince(t0) / 1000.0, loadAverage().c_str());
  if (!diag.ok()) {
    std::printf("%zu input error(s) (listed above): figures may be off\n", diag.errors.size());
    return 1;
  }
  return 0;
}

// --- 4. Picture-quality options -----------------------------------------------------------------
// Frame time of each option against the papers' blend, in one process, on one view of a given
// scene (the first of `viewsPath`, at `size` when given): median of kFrameRepeats frames each.
int benchQuality(const std::string& scenePath, const std::string& viewsPath, const std::string& size) {
  hv::Diagnostics diag;
  const hv::Scene scene = hv::loadScene(scenePath, diag);
  const auto views = readViews(viewsPath, diag);
  auto context = hv::gpu::createHeadlessContext();
  hv::Camera view = views.front().camera;
  if (!size.empty()) {
    int w = 0, h = 0;
    if (std::sscanf(size.c_str(), "%dx%d", &w, &h) != 2 || w <= 0 || h <= 0)
      throw std::runtime_error("--quality: size " + size + ": expected WxH");
    view = view.resized(w, h);
  }
  std::printf("\n4. Picture-quality options: frame time at %dx%d, view %s (median of %d frames after %d warm-up)\n",
              view.width, view.height, view.id.c_str(), kFrameRepeats, kWarmupFrames);
  std::printf("  GL %s | load average %s\n", hv::gpu::queryLimits().renderer.c_str(), loadAverage().c_str());
  rule();
  struct Option {
    const char* name;
    void (*apply)(hv::ibr::BlendSettings&);
    // The one generic shade program of every configuration (before per-configuration programs,
    // render/gl/shade_config.h): the papers' blend as it was measured against SIBR's ULR.
    bool generic = false;
  };
  const Option options[] = {
      {"papers' blend (distance, no feather, level 0)", [](hv::ibr::BlendSettings&) {}},
      {"papers' blend, generic program", [](hv::ibr::BlendSettings&) {}, true},
      {"weights geometry, generic program",
       [](hv::ibr::BlendSettings& b) { b.weighting = hv::ibr::Weighting::Geometry; }, true},
      {"weights geometry", [](hv::ibr::BlendSettings& b) { b.weighting = hv::ibr::Weighting::Geometry; }},
      // SIBR's unstructured lumigraph renderer blends the best 4 per pixel.
      {"weights geometry, geometry-k 4", [](hv::ibr::BlendSettings& b) {
         b.weighting = hv::ibr::Weighting::Geometry;
         b.geometryK = 4;
       }},
      // The better-quality setting on real photographs (docs/evaluation.md, Sceaux).
      {"weights geometry, mipmaps", [](hv::ibr::BlendSettings& b) {
         b.weighting = hv::ibr::Weighting::Geometry;
         b.mipmaps = true;
         b.anisotropy = 1.0;
       }},
      {"weights geometry, geometry-k 4, mipmaps", [](hv::ibr::BlendSettings& b) {
         b.weighting = hv::ibr::Weighting::Geometry;
         b.geometryK = 4;
         b.mipmaps = true;
         b.anisotropy = 1.0;
       }},
      {"feather 16 px", [](hv::ibr::BlendSettings& b) { b.featherPx = 16.0; }},
      // Anisotropic filtering is left out: llvmpipe's takes minutes per frame (docs/performance.md).
      {"mipmaps (footprint-area level)", [](hv::ibr::BlendSettings& b) {
         b.mipmaps = true;
         b.anisotropy = 1.0;
       }},
      {"all three", [](hv::ibr::BlendSettings& b) {
         b.weighting = hv::ibr::Weighting::Geometry;
         b.featherPx = 16.0;
         b.mipmaps = true;
         b.anisotropy = 1.0;
       }},
      {"all three, geometry-k 4", [](hv::ibr::BlendSettings& b) {
         b.weighting = hv::ibr::Weighting::Geometry;
         b.geometryK = 4;
         b.featherPx = 16.0;
         b.mipmaps = true;
         b.anisotropy = 1.0;
       }},
      {"all three, selection region", [](hv::ibr::BlendSettings& b) {
         b.weighting = hv::ibr::Weighting::Geometry;
         b.featherPx = 16.0;
         b.mipmaps = true;
         b.anisotropy = 1.0;
         b.selection = hv::ibr::Selection::Region;
       }},
  };
  std::printf("  %-46s %7s %11s %9s %9s\n", "option", "images", "median ms", "vs papers", "cpu ms");
  hv::render::RenderSettings settings;
  // The papers' blend as the reference, whatever the defaults are.
  settings.blend.weighting = hv::ibr::Weighting::Distance;
  settings.blend.featherPx = 0.0;
  settings.blend.mipmaps = false;
  settings.blend.selection = hv::ibr::Selection::Global;
  const hv::ibr::BlendSettings papers = settings.blend;
  hv::render::Renderer renderer(scene, settings, diag);
  Timing base;
  for (const Option& o : options) {
    renderer.settings().blend = papers;
    o.apply(renderer.settings().blend);
    hv::render::gl::setShadeSpecialisation(!o.generic);
    for (int i = 0; i < kWarmupFrames; ++i) renderer.render(view);
    std::vector<Timing> t;
    for (int i = 0; i < kFrameRepeats; ++i) t.push_back(measure([&] { renderer.render(view); }));
    const Timing m = median(t);
    if (&o == &options[0]) base = m;
    std::printf("  %-46s %7zu %11.1f %8.2fx %9.1f\n", o.name, renderer.lastPlan().images.size(), m.wall,
                m.wall / base.wall, m.cpu);
  }
  hv::render::gl::setShadeSpecialisation(true);
  rule();
  return diag.ok() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  WorkDir dir;
  if ((argc == 4 || argc == 5) && std::string(argv[1]) == "--quality") {
    try {
      return benchQuality(argv[2], argv[3], argc == 5 ? argv[4] : "");
    } catch (const std::exception& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
      return 2;
    }
  }
  if (argc == 3 && std::string(argv[1]) == "--keep") {
    dir.path = argv[2];
    dir.keep = true;
  } else if (argc == 1) {
    dir.path = fs::temp_directory_path() / ("hv-render-bench-" + std::to_string(getpid()));
  } else {
    std::fprintf(stderr, "usage: %s [--keep DIR] | --quality SCENE.json VIEWS.json [WxH]\n", argv[0]);
    return 2;
  }
  try {
    return run(dir.path);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
