// Buildings loaded whole against streamed per view, on a demo city (`histoview demo --blocks N
// --out DIR`): its buildings.gpkg, its photographs' cameras as the views. Run once per mode, each
// in its own process, so that the peak RSS is the mode's own:
//   building_stream_bench DIR whole            every tile read and extruded (base height 0)
//   building_stream_bench DIR stream [THREADS [reach]]
//       the tile set indexed, then for each camera in turn the tiles its frustum may see (with
//       `reach`: within kBuildingReachMetresPerPixel x its focal length) streamed until converged
//       (BuildingStream, 256 MiB, THREADS workers: 2)
// Figures: docs/performance.md, "Building streaming".
#include "hv/camera/frustum.h"
#include "hv/io/native/footprints.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/building_stream.h"

#include "bench_common.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <limits>
#include <string>
#include <thread>

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: building_stream_bench CITY_DIR whole|stream [THREADS [reach]]\n");
    return 2;
  }
  const std::string dir = argv[1], mode = argv[2];
  const int threads = argc > 3 ? std::stoi(argv[3]) : 2;
  // "reach": each camera's tiles within kBuildingReachMetresPerPixel x its focal length only.
  const bool reach = argc > 4 && std::string(argv[4]) == "reach";
  const std::string path = dir + "/buildings.gpkg";
  std::printf("%s, %s; %s\n", path.c_str(), mode.c_str(), hv::bench::loadAverage().c_str());
  hv::FootprintTileOptions options;
  options.perTile = hv::kBuildingsPerTile;
  const auto t0 = hv::bench::Clock::now();
  if (mode == "whole") {
    hv::Diagnostics diag;
    std::size_t triangles = 0, buildings = 0;
    const hv::FootprintTileSource src = hv::readFootprintTiles(
        path, hv::FootprintFields{}, hv::SourceGeoref{}, options,
        [&](hv::FootprintTile& t) {
          const hv::BuildingTileData d =
              hv::extrudeFootprintTile(t.footprints, nullptr, hv::FootprintFields{}, path, diag);
          triangles += d.mesh.triangles.size();
          buildings += d.validity.size();
        },
        diag);
    std::printf("whole: %zu tiles, %zu buildings, %zu triangles, %.0f ms, peak RSS %ld MiB\n", src.tilesRead, buildings,
                triangles, hv::bench::msSince(t0), hv::bench::residentKb("VmHWM:") / 1024);
    return 0;
  }
  hv::Diagnostics diag;
  hv::SceneLoadOptions camerasOnly;
  camerasOnly.camerasOnly = true;
  const hv::Scene scene = hv::loadScene(dir + "/scene.json", diag, camerasOnly);
  const double camerasMs = hv::bench::msSince(t0);
  const auto t1 = hv::bench::Clock::now();
  hv::FootprintTileSource info;
  const auto set = hv::footprintTileSet(path, hv::FootprintFields{}, hv::SourceGeoref{}, options, nullptr, -100.0,
                                        1000.0, info, diag);
  std::printf("cameras %.0f ms; tile set: %zu tiles, %zu features, indexed in %.0f ms, RSS %ld MiB\n", camerasMs,
              set->boxes.size(), info.features, hv::bench::msSince(t1), hv::bench::residentKb("VmRSS:") / 1024);
  hv::Aabb all;
  for (const hv::Aabb& b : set->boxes) all.extend(b);
  const glm::dvec3 origin = glm::round(all.center());
  hv::render::BuildingStream stream(set, origin, threads, std::size_t(256) << 20);
  int n = 0;
  for (const hv::Photo& p : scene.photos) {
    if (n >= 8) break;
    const hv::Camera cam = hv::bench::crop720p(p.camera);
    hv::PinholeFrustum fr = hv::idealRectCoveringImage(cam, 0.0);
    hv::setDepthRange(fr, cam, all);
    const glm::dmat4 clip = hv::clipFromRender(cam, fr, origin);
    const auto f0 = hv::bench::Clock::now();
    double firstMs = -1.0;
    int frames = 0;
    hv::render::BuildingCut cut;
    for (;; ++frames) {
      stream.beginFrame();
      stream.poll(std::chrono::milliseconds(30));
      cut = stream.select(cam, clip, 0.0,
                          reach ? hv::kBuildingReachMetresPerPixel * std::max(cam.focal.x, cam.focal.y)
                                : std::numeric_limits<double>::infinity());
      stream.endFrame();
      if (firstMs < 0.0) firstMs = hv::bench::msSince(f0);
      if (cut.missing == 0 && stream.pendingTiles() == 0) break;
      if (threads > 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    std::size_t triangles = 0;
    for (std::uint32_t t : cut.tiles) triangles += stream.trianglesOf(t);
    std::printf(
        "view %s: first frame %.1f ms, converged %.0f ms (%d frames), %zu tiles drawn, %zu triangles; "
        "resident %zu tiles, %.1f MiB\n",
        p.camera.id.c_str(), firstMs, hv::bench::msSince(f0), frames + 1, cut.tiles.size(), triangles,
        stream.residentTiles(), double(stream.residentBytes()) / (1 << 20));
    ++n;
  }
  std::printf("stream: %.0f ms in all, peak RSS %ld MiB\n", hv::bench::msSince(t0),
              hv::bench::residentKb("VmHWM:") / 1024);
  return diag.ok() ? 0 : 1;
}
