// Point-sprite benchmark: points per second at 1280x720 on the demo city's lidar scan
// for K = 1, 8, 40 images, the 2022 form (N') and, where it links, the 2016 form (mat3), each
// frame also timed mesh-only in the same process (the ratio baseline: these shared machines are
// noisy from one run to the next). Prints the largest K the mat3 program links with and
// MAX_VARYING_COMPONENTS. Usage: points_bench. Figures: docs/performance.md.
#include "hv/demo/demo_city.h"
#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/renderer.h"
#include "hv/util/diagnostics.h"

#include "bench_common.h"

#include <GLES3/gl3.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using hv::bench::crop720p;
using hv::bench::kFrameHeight;
using hv::bench::kFrameWidth;

constexpr int kFrameK[] = {1, 8, 40};
constexpr int kManyPhotos = 64;  // K = 40 needs 40 photographs that see the view
constexpr int kRepeats = 5;      // median of these after one warm-up frame

double frameMs(hv::render::Renderer& r, const hv::Camera& view) {
  r.render(view);  // warm-up: images, depth maps, shader variants
  std::vector<double> t;
  for (int i = 0; i < kRepeats; ++i) t.push_back(hv::bench::timeMs([&] { r.render(view); glFinish(); }));
  return hv::bench::median(t);
}

}  // namespace

int main() {
  auto ctx = hv::gpu::createHeadlessContext();
  ctx->makeCurrent();
  const hv::gpu::GlLimits limits = hv::gpu::queryLimits();
  const std::string dir = (std::filesystem::temp_directory_path() / "histoview-points-bench").string();
  hv::demo::DemoOptions opt;
  opt.photos = kManyPhotos;
  const hv::demo::DemoSummary sum = hv::demo::generate(opt, dir);
  hv::Diagnostics diag;
  const hv::Scene scene = hv::loadScene(sum.scenePath, diag);
  hv::CameraFileOptions copt;
  copt.requireImages = false;
  const auto views = hv::readCameraFile(sum.viewsPath, copt, diag);
  const hv::Camera view = crop720p(views.at(0).camera);
  std::printf("%s; %s\n", hv::gpu::glDescription().c_str(), hv::bench::loadAverage().c_str());
  std::printf("points in the scene: %zu; MAX_VARYING_COMPONENTS %d; mat3 sprite program links up to K = %d\n",
              scene.points.size(), limits.maxVaryingComponents, hv::render::probeMat3SpriteImages(32));
  std::printf("%-6s %-8s %12s %12s %12s %14s %8s\n", "K", "form", "mesh ms", "points ms", "sprites", "points/s",
              "ratio");
  for (int k : kFrameK) {
    for (auto form : {hv::render::SpriteForm::PlaneVector, hv::render::SpriteForm::Mat3}) {
      hv::render::RenderSettings st;
      st.blend.k = k;
      const bool mat3 = form == hv::render::SpriteForm::Mat3;
      double meshMs = 0;
      {
        hv::render::Renderer r(scene, st, diag);
        meshMs = frameMs(r, view);
      }
      st.points.enabled = true;
      st.points.form = form;
      hv::render::Renderer r(scene, st, diag);
      const double ms = frameMs(r, view);
      const double drawn = double(r.stats().pointsDrawn);
      // The points' own cost: the frame minus the mesh-only frame of the same K.
      const double pointMs = std::max(ms - meshMs, 1e-3);
      std::printf("%-6d %-8s %12.1f %12.1f %12.0f %14.3g %8.2f%s\n", k, mat3 ? "mat3" : "N'", meshMs, ms, drawn,
                  drawn / (pointMs * 1e-3), ms / meshMs,
                  mat3 && r.stats().mat3Images < k ? (" (mat3 capped at K = " + std::to_string(r.stats().mat3Images) + ")").c_str() : "");
    }
  }
  std::filesystem::remove_all(dir);
  return 0;
}
