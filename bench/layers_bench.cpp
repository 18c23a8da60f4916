// Layered projective texture maps benchmark (docs/layers.md; docs/performance.md, "Layers in the
// renderer"): a benchmark, not a test. On the default demo city, one run prints
//   1. the visibility layers of a few photographs peeled on the CPU (the reference, from the ray
//      casts' hit lists) and on the GPU (render/layer_peeling.h: item buffer, occlusion queries,
//      the CPU finishing from the first cycle): times, ratio, and how many surfaces get the same
//      layer both ways;
//   2. the steady-state frame time at 1280x720 of the held-out views, every photograph rendered as
//      itself (the baseline) and every photograph rendered from its exported layers (sub-images,
//      peeled depth maps), in the same process; ratios against the baseline.
// Usage: layers_bench [--keep DIR] [--layers-size N] [--views N]   (--layers-size: the layers at 1/N
//        of each photograph's size, default 2; --views: the first N held-out views only, default all)

#include "hv/demo/demo_city.h"
#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/layers/native/layer_export.h"
#include "hv/layers/native/layer_import.h"
#include "hv/layers/native/openraster.h"
#include "hv/render/layer_peeling.h"
#include "hv/render/renderer.h"
#include "hv/util/diagnostics.h"

#include "bench_common.h"

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using namespace hv::bench;

namespace {

constexpr int kWarmupLimit = 30;  // frames until no image waits (decodes, depth maps)
constexpr int kFrameRepeats = 5;  // then the median of these
const char* const kPeelPhotos[] = {"p0004", "p0010", "p0020"};

void rule() { std::printf("%s\n", std::string(78, '-').c_str()); }

std::size_t photoIndex(const hv::Scene& scene, const std::string& id) {
  for (std::size_t i = 0; i < scene.photos.size(); ++i)
    if (scene.photos[i].camera.id == id) return i;
  throw std::runtime_error("no photograph " + id);
}

void benchPeeling(const hv::Scene& scene) {
  std::printf("\n1. Visibility layers: CPU reference against the GPU pass (each photograph at its own size)\n");
  rule();
  std::printf("  %-7s %9s %7s %9s %9s %7s %8s %12s\n", "photo", "size", "layers", "CPU ms", "GPU ms", "GPU/CPU",
              "GPU whole", "same layer");
  for (const char* id : kPeelPhotos) {
    const std::size_t i = photoIndex(scene, id);
    hv::layers::LayerExportSettings s;
    s.prefill = false;
    hv::Diagnostics diag;
    const hv::layers::LayerExport cpu = hv::layers::exportLayers(scene, i, s, diag);
    hv::render::GpuObjectLayers gpuLayers;
    double gpuPassMs = 0.0;
    s.objectLayers = [&](const hv::Camera& camera, const hv::layers::SceneObjects& objects) {
      const auto t0 = Clock::now();
      gpuLayers = hv::render::peelObjectLayersGl(camera, objects.geometry, objects.objectOfTriangle,
                                                 objects.terrainTriangle, objects.objects.size());
      gpuPassMs = msSince(t0);
      return gpuLayers.layerOfObject;
    };
    const hv::layers::LayerExport gpu = hv::layers::exportLayers(scene, i, s, diag);
    std::size_t same = 0;
    for (std::size_t k = 0; k < cpu.visibility.layerOfHit.size(); ++k)
      same += cpu.visibility.layerOfHit[k] == gpu.visibility.layerOfHit[k];
    const double total = double(std::max<std::size_t>(cpu.visibility.layerOfHit.size(), 1));
    std::printf("  %-7s %4dx%-4d %3zu/%-3zu %9.1f %9.1f %7.2f %8d%s %11.2f%%\n", id, cpu.camera.width,
                cpu.camera.height, cpu.visibility.layers.size(), gpu.visibility.layers.size(), cpu.peelSeconds * 1e3,
                gpu.peelSeconds * 1e3, gpu.peelSeconds / std::max(cpu.peelSeconds, 1e-9), gpuLayers.layers,
                gpuLayers.stoppedAtCycle ? "+c" : "  ", 100.0 * double(same) / total);
    std::printf("          (GPU pass alone %.1f ms, %zu occlusion queries, %zu objects seen)\n", gpuPassMs,
                gpuLayers.queries, gpuLayers.objectsSeen);
  }
  std::printf("  layers: CPU/GPU-then-CPU; GPU whole: layers the GPU peeled whole (+c: it stopped at a cycle)\n");
}

void benchRenderer(const hv::Scene& scene, const std::vector<hv::Photo>& views, const fs::path& dir, int divide) {
  std::printf("\n2. Frame time at %dx%d, photographs as themselves (baseline) against their layers\n", kFrameWidth,
              kFrameHeight);
  rule();
  // Every photograph's layers, exported at 1/divide of its size with the pre-fill, written and read
  // back as scene.json's "layers" would be.
  std::vector<std::shared_ptr<const hv::layers::LayeredPhotograph>> layered(scene.photos.size());
  std::size_t subImages = 0;
  const Timing prep = measure([&] {
    for (std::size_t i = 0; i < scene.photos.size(); ++i) {
      const hv::Camera& cam = scene.photos[i].camera;
      hv::layers::LayerExportSettings s;
      s.width = cam.width / divide;
      s.height = cam.height / divide;
      hv::Diagnostics diag;
      const hv::layers::LayerExport ex = hv::layers::exportLayers(scene, i, s, diag);
      const fs::path ora = dir / (cam.id + ".ora");
      hv::layers::writeOpenRaster(ora.string(), ex.document);
      const hv::layers::ImportedLayers in = hv::layers::importLayers(ora.string(), cam);
      auto l = std::make_shared<hv::layers::LayeredPhotograph>(hv::layers::layeredPhotograph(scene, i, in, s, diag));
      subImages += l->subImages.size();
      layered[i] = std::move(l);
    }
  });
  std::printf(
      "  %zu photographs layered at 1/%d of their size: %zu sub-images (%.1f a photograph); export, write,\n"
      "  read back and peel again: %.1f s\n",
      scene.photos.size(), divide, subImages, double(subImages) / double(scene.photos.size()), prep.wall / 1e3);

  hv::Diagnostics diag;
  hv::render::Renderer plain(scene, hv::render::RenderSettings{}, diag);
  hv::render::Renderer withLayers(scene, hv::render::RenderSettings{}, diag);
  for (std::size_t i = 0; i < scene.photos.size(); ++i) withLayers.setLayeredPhotograph(int(i), layered[i]);

  struct Frame {
    double ms = 0.0;
    int images = 0, waiting = 0;
  };
  auto steady = [&](hv::render::Renderer& r, const hv::Camera& view) {
    int warm = 0;
    do r.render(view);
    while (r.stats().imagesWaiting > 0 && ++warm < kWarmupLimit);
    std::vector<double> t;
    for (int k = 0; k < kFrameRepeats; ++k) t.push_back(timeMs([&] { r.render(view); }));
    return Frame{median(t), int(r.lastImageParams().size()), r.stats().imagesWaiting};
  };
  std::printf("  %-10s %12s %20s %8s\n", "view", "plain ms (K)", "layers ms (images)", "ratio");
  std::vector<double> ratios;
  for (const hv::Photo& v : views) {
    const hv::Camera view = crop720p(v.camera);
    const Frame a = steady(plain, view);
    const Frame b = steady(withLayers, view);
    ratios.push_back(b.ms / a.ms);
    std::printf("  %-10s %8.1f (%d) %13.1f (%d%s) %8.2f\n", v.camera.id.c_str(), a.ms, a.images, b.ms, b.images,
                b.waiting ? ", some waiting" : "", b.ms / a.ms);
  }
  std::printf("  median ratio %.2f (images: the sub-images and photographs blended; median of %d frames)\n",
              median(ratios), kFrameRepeats);
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // each line as it is printed (long runs)
  try {
    WorkDir dir;
    int divide = 2, maxViews = 1000;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--keep" && i + 1 < argc) {
        dir.path = argv[++i];
        dir.keep = true;
      } else if (a == "--layers-size" && i + 1 < argc) {
        divide = std::max(1, std::atoi(argv[++i]));
      } else if (a == "--views" && i + 1 < argc) {
        maxViews = std::max(1, std::atoi(argv[++i]));
      } else {
        std::fprintf(stderr, "usage: layers_bench [--keep DIR] [--layers-size N] [--views N]\n");
        return 2;
      }
    }
    if (dir.path.empty()) dir.path = fs::temp_directory_path() / ("hv-layers-bench-" + std::to_string(getpid()));
    fs::create_directories(dir.path);
    auto context = hv::gpu::createHeadlessContext();
    context->makeCurrent();
    std::printf("layers_bench: %s; %d CPUs; load average %s\n", context->description().c_str(), cpuCount(),
                loadAverage().c_str());
    const hv::demo::DemoSummary summary = hv::demo::generate(hv::demo::DemoOptions{}, (dir.path / "city").string());
    hv::Diagnostics diag;
    const hv::Scene scene = hv::loadScene(summary.scenePath, diag);
    hv::CameraFileOptions o;
    o.requireImages = false;
    o.checkImageFiles = false;
    std::vector<hv::Photo> views = hv::readCameraFile(summary.viewsPath, o, diag);
    if (views.size() > std::size_t(maxViews)) views.resize(std::size_t(maxViews));
    benchPeeling(scene);
    benchRenderer(scene, views, dir.path, divide);
    std::printf("\npeak resident memory %ld MiB\n", residentKb("VmHWM:") / 1024);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "layers_bench: %s\n", e.what());
    return 1;
  }
}
