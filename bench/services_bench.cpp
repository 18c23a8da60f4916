// Files against loopback services (docs/services.md; figures in docs/performance.md, "Services"):
// the demo city from its files and from a real local stack, in one process, on the same views.
//
//   services_bench [--keep DIR] [--photos N]
//
// Generates the demo city (40 buildings, N photographs, default 36), starts tools/services.sh on
// it (lighttpd on 127.0.0.1, MapServer behind it) and writes two scenes that hold the same data:
//   files      dtm.tif, the footprints' file, cameras.json (photographs read from disk)
//   services   the DTM by WCS 2.0.1, the footprints by OGC API - Features, the photographs by
//              HTTP (cameras.json with every `image` an http:// URL of the stack's /files/)
// For each, in this order: the scene's load, the renderer's construction, the first progressive
// frame of the first held-out view and the frames to its convergence (as the viewer shows them),
// then a walk through the first four views (a Catmull-Rom path at 10 frames a second of path
// time, one progressive frame per step, then to convergence at the end). Every frame is
// 1280x720, K = 8. The bytes each phase fetched are read from the stack's access log (what the
// server sent: bodies, not headers). histoview's response cache is a fresh folder of the work
// directory, so that every photograph crosses the network once.
//
// Prints a table with the ratio services / files per row; the services are on loopback, so the
// ratio is the cost of the protocols and the servers (MapServer reading and encoding), not of a
// network.
#include "hv/camera/camera_path.h"
#include "hv/demo/demo_city.h"
#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/renderer.h"
#include "hv/util/diagnostics.h"

#include "bench_common.h"

#include <nlohmann/json.hpp>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

namespace fs = std::filesystem;
using namespace hv::bench;
using nlohmann::json;

namespace {

constexpr int kViews = 4;               // the first four held-out views: the walk's keys
constexpr double kWalkFps = 10.0;       // frames per second of path time (keys 1 s apart)
constexpr int kMaxProgressive = 400;    // frames to convergence, at most
constexpr double kMaxConvergeMs = 240e3;

// The output of a shell command (its stdout), or a runtime_error naming it when it fails.
std::string shell(const std::string& command) {
  std::string out;
  FILE* p = popen(command.c_str(), "r");
  if (!p) throw std::runtime_error("cannot run: " + command);
  std::array<char, 4096> buf{};
  size_t n = 0;
  while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) out.append(buf.data(), n);
  const int rc = pclose(p);
  if (rc != 0) throw std::runtime_error("failed (" + std::to_string(rc) + "): " + command + "\n" + out);
  return out;
}

std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// tools/services.sh on a folder, stopped when this goes out of scope (failure included).
class Stack {
 public:
  explicit Stack(const fs::path& city) : city_(city) {
    script_ = fs::path(HV_SOURCE_DIR) / "tools" / "services.sh";
    const std::string out = shell("bash " + quoted(script_.string()) + " up " + quoted(city_.string()) + " 2>&1");
    // "serving DIR on URL (state: STATE)"
    const auto on = out.find(" on http://"), state = out.find("(state: ");
    if (on == std::string::npos || state == std::string::npos)
      throw std::runtime_error("tools/services.sh up: no URL in its output:\n" + out);
    url_ = out.substr(on + 4, out.find(' ', on + 4) - (on + 4));
    const auto end = out.find(')', state);
    accessLog_ = fs::path(out.substr(state + 8, end - (state + 8))) / "access.log";
    up_ = true;
  }
  ~Stack() {
    if (up_) std::system(("bash " + quoted(script_.string()) + " down " + quoted(city_.string()) + " >/dev/null 2>&1").c_str());
  }
  Stack(const Stack&) = delete;
  Stack& operator=(const Stack&) = delete;

  const std::string& url() const { return url_; }

  // Requests and body bytes the server logged since the previous call (lighttpd's default log
  // format: host vhost user [time] "request" status bytes "referer" "agent"). lighttpd writes its
  // log in batches, at least once a second: the call waits 1.5 s first (outside any timing).
  std::pair<long, long> drain() {
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    std::ifstream log(accessLog_);
    log.seekg(offset_);
    std::string line;
    long requests = 0, bytes = 0;
    while (std::getline(log, line)) {
      if (log.eof()) break;  // a line still being written: read it next time
      offset_ += std::streamoff(line.size() + 1);
      const auto q1 = line.find('"'), q2 = q1 == std::string::npos ? q1 : line.find('"', q1 + 1);
      if (q2 == std::string::npos) continue;
      std::istringstream rest(line.substr(q2 + 1));
      std::string status, size;
      rest >> status >> size;
      ++requests;
      if (size != "-") bytes += std::atol(size.c_str());
    }
    return {requests, bytes};
  }

 private:
  fs::path city_, script_, accessLog_;
  std::string url_;
  std::streamoff offset_ = 0;
  bool up_ = false;
};

struct Row {
  double loadMs = 0, setupMs = 0, firstMs = 0, convergedMs = 0, walkFrameMs = 0, walkConvergeMs = 0;
  int convergeFrames = 0, walkFrames = 0;
  long loadBytes = 0, firstBytes = 0, convergeBytes = 0, walkBytes = 0, walkMaxFrameBytes = 0, requests = 0;
};

Row measureScene(const std::string& scenePath, const std::vector<hv::Camera>& views, Stack* stack) {
  auto drain = [&] { return stack ? stack->drain() : std::pair<long, long>{0, 0}; };
  Row r;
  hv::Diagnostics diag;
  hv::Scene scene;
  drain();
  r.loadMs = timeMs([&] { scene = hv::loadScene(scenePath, diag); });
  auto [q, b] = drain();
  r.loadBytes = b, r.requests += q;
  hv::render::RenderSettings settings;
  std::unique_ptr<hv::render::Renderer> renderer;
  r.setupMs = timeMs([&] { renderer = std::make_unique<hv::render::Renderer>(scene, settings, diag); });
  for (const auto& m : diag.errors) std::printf("    error: %s\n", m.c_str());
  for (const auto& m : diag.warnings) std::printf("    warning: %s\n", m.c_str());

  auto converge = [&](const hv::Camera& view, int& frames) {
    frames = 0;
    const auto t0 = Clock::now();
    while (!renderer->converged() && frames < kMaxProgressive && msSince(t0) < kMaxConvergeMs) {
      renderer->render(view, false, hv::render::FrameMode::Progressive);
      ++frames;
    }
    if (!renderer->converged()) std::printf("    warning: %s did not converge\n", view.id.c_str());
    return msSince(t0);
  };

  const auto moved = Clock::now();
  r.firstMs = timeMs([&] { renderer->render(views[0], false, hv::render::FrameMode::Progressive); });
  std::tie(q, b) = drain();
  r.firstBytes = b, r.requests += q;
  converge(views[0], r.convergeFrames);
  r.convergedMs = msSince(moved);
  std::tie(q, b) = drain();
  r.convergeBytes = b, r.requests += q;

  std::vector<hv::PathKey> keys;
  for (int v = 0; v < kViews; ++v) keys.push_back({views[size_t(v)], double(v)});
  const hv::PathFrames walk(hv::CameraPath(keys), kWalkFps);
  std::vector<double> frameMs;
  for (int i = 0; i < walk.size(); ++i) {
    const hv::Camera c = walk[i];
    frameMs.push_back(timeMs([&] { renderer->render(c, false, hv::render::FrameMode::Progressive); }));
    std::tie(q, b) = drain();
    r.walkBytes += b, r.requests += q;
    r.walkMaxFrameBytes = std::max(r.walkMaxFrameBytes, b);
  }
  r.walkFrames = walk.size();
  r.walkFrameMs = median(frameMs);
  int n = 0;
  r.walkConvergeMs = converge(walk[walk.size() - 1], n);
  std::tie(q, b) = drain();
  r.walkBytes += b, r.requests += q;
  return r;
}

// The demo's scene.json with its paths made absolute: terrain, buildings, cameras only (the
// lidar scan, the orthophoto and the traffic have no service of the stack, so they are left out
// of both scenes).
json baseScene(const fs::path& city) {
  std::ifstream f(city / "scene.json");
  const json demo = json::parse(f);
  json s;
  s["crs"] = demo.at("crs");
  s["terrain"] = demo.at("terrain");
  s["buildings"] = demo.at("buildings");
  s["cameras"] = demo.at("cameras");
  return s;
}

void writeJson(const fs::path& path, const json& doc) {
  std::ofstream out(path);
  out << doc.dump(1) << "\n";
  if (!out) throw std::runtime_error(path.string() + ": cannot write");
}

}  // namespace

int main(int argc, char** argv) {
  try {
    WorkDir work;
    int photos = 36;
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      if (a == "--keep" && i + 1 < argc) {
        work.path = argv[++i];
        work.keep = true;
      } else if (a == "--photos" && i + 1 < argc) {
        photos = std::atoi(argv[++i]);
      } else {
        std::fprintf(stderr, "usage: %s [--keep DIR] [--photos N]\n", argv[0]);
        return 2;
      }
    }
    if (work.path.empty()) work.path = fs::temp_directory_path() / ("hv-services-bench-" + std::to_string(getpid()));
    fs::remove_all(work.path);
    fs::create_directories(work.path);
    // A fresh response cache: every photograph is fetched once.
    setenv("HV_CACHE_DIR", (work.path / "cache").c_str(), 1);

    hv::demo::DemoOptions options;
    options.photos = photos;
    options.traffic.enabled = false;
    std::printf("generating the demo city (%d photographs) in %s...\n", photos, work.path.c_str());
    const hv::demo::DemoSummary summary = hv::demo::generate(options, work.path.string());
    const fs::path city = fs::path(summary.scenePath).parent_path();

    Stack stack(city);
    const json base = baseScene(city);
    writeJson(city / "bench-files.json", base);

    // The photographs by URL: cameras.json with every image an http:// URL of /files/.
    json cams = json::parse(std::ifstream(city / base["cameras"]["path"].get<std::string>()));
    for (auto& c : cams["cameras"]) {
      c["image"] = stack.url() + "/files/" + c["image"].get<std::string>();
      if (c.contains("mask")) c["mask"] = stack.url() + "/files/" + c["mask"].get<std::string>();
    }
    writeJson(city / "bench-cameras-url.json", cams);
    json services = base;
    services["terrain"]["path"] = "WCS:" + stack.url() + "/mapserv?map=city&SERVICE=WCS&VERSION=2.0.1&COVERAGEID=dtm";
    services["buildings"]["path"] = "OAPIF:" + stack.url() + "/mapserv/city/ogcapi/collections/buildings";
    services["cameras"]["path"] = "bench-cameras-url.json";
    writeJson(city / "bench-services.json", services);

    hv::Diagnostics diag;
    hv::CameraFileOptions vo;
    vo.requireImages = false;
    vo.checkImageFiles = false;
    const auto held = hv::readCameraFile(summary.viewsPath, vo, diag);
    if (int(held.size()) < kViews) throw std::runtime_error(summary.viewsPath + ": fewer than 4 held-out views");
    std::vector<hv::Camera> views;
    for (int v = 0; v < kViews; ++v) views.push_back(crop720p(held[size_t(v)].camera));

    const auto context = hv::gpu::createHeadlessContext();
    std::printf("files...\n");
    const Row files = measureScene((city / "bench-files.json").string(), views, nullptr);
    std::printf("services (%s)...\n", stack.url().c_str());
    const Row served = measureScene((city / "bench-services.json").string(), views, &stack);

    std::printf("\nFiles against loopback services: the demo city (%d photographs), 1280x720, K = 8\n", summary.photos);
    std::printf("  GL %s | load average %s\n", hv::gpu::queryLimits().renderer.c_str(), loadAverage().c_str());
    std::printf("------------------------------------------------------------------------------\n");
    std::printf("  %-44s %12s %12s %8s\n", "", "files", "services", "ratio");
    auto row = [](const char* name, double a, double b) {
      if (a >= 1.0)
        std::printf("  %-44s %12.0f %12.0f %7.2fx\n", name, a, b, b / a);
      else  // nothing to wait for from the files (already converged): no ratio
        std::printf("  %-44s %12.0f %12.0f %8s\n", name, a, b, "-");
    };
    row("load (ms)", files.loadMs, served.loadMs);
    row("renderer (ms)", files.setupMs, served.setupMs);
    row("first frame, view 1 (ms)", files.firstMs, served.firstMs);
    row("load + renderer + first frame (ms)", files.loadMs + files.setupMs + files.firstMs,
        served.loadMs + served.setupMs + served.firstMs);
    row("first frame to converged, view 1 (ms)", files.convergedMs, served.convergedMs);
    row("walk: median frame (ms)", files.walkFrameMs, served.walkFrameMs);
    row("walk: end to converged (ms)", files.walkConvergeMs, served.walkConvergeMs);
    std::printf("  %-44s %12d %12d\n", "frames to converge, view 1", files.convergeFrames, served.convergeFrames);
    std::printf("------------------------------------------------------------------------------\n");
    std::printf("  fetched from the services: %ld requests\n", served.requests);
    std::printf("    load          %10.1f KiB\n", served.loadBytes / 1024.0);
    std::printf("    first frame   %10.1f KiB\n", served.firstBytes / 1024.0);
    std::printf("    to converged  %10.1f KiB\n", served.convergeBytes / 1024.0);
    std::printf("    walk          %10.1f KiB over %d frames: %.1f KiB a frame on average, %.1f KiB at most\n",
                served.walkBytes / 1024.0, served.walkFrames, served.walkBytes / 1024.0 / std::max(1, served.walkFrames),
                served.walkMaxFrameBytes / 1024.0);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "services_bench: %s\n", e.what());
    return 1;
  }
}
