// Shared by the *_gltest files: one headless context for the whole test binary, temporary
// directories, and a small synthetic street (ground, a near and a far building) whose photographs
// are arbitrary patterns: the GL-vs-CPU tests need any image, not a consistent one.
#pragma once

#include "hv/demo/demo_city.h"
#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/image/image.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/native/lod1.h"
#include "hv/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

namespace hv::testing {

// The context lives as long as the test binary; created on first use.
inline gpu::Context& glContext() {
  static std::unique_ptr<gpu::Context> ctx = gpu::createHeadlessContext();
  ctx->makeCurrent();
  return *ctx;
}

// The fixture of a GL test: the shared context current and GL errors cleared before it, none left
// behind after it.
class GlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    glContext();
    gpu::clearGlErrors();
  }
  void TearDown() override { EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << "a GL error was left behind"; }
};

// Directories made by makeTempDir, removed when the test process exits (a demo city or 4096
// photographs per process would otherwise pile up in /tmp run after run).
struct TempDirs {
  std::vector<std::filesystem::path> dirs;
  ~TempDirs() {
    std::error_code ec;
    for (const auto& d : dirs) std::filesystem::remove_all(d, ec);
  }
};

inline std::string makeTempDir(const std::string& name) {
  static TempDirs registry;  // constructed first, so destroyed after the statics that use its dirs
  const auto dir = std::filesystem::temp_directory_path() /
                   ("histoview-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  registry.dirs.push_back(dir);
  return dir.string();
}

// A camera at `center` (world) looking towards `target`, z up, pinhole.
inline Camera lookAt(const std::string& id, glm::dvec3 center, glm::dvec3 target, int w, int h, double focal) {
  return lookAtCamera(id, center, target, w, h, focal);
}

// A smooth pattern distinct per seed (texels vary across the image, so misplaced lookups show).
inline Image8 patternImage(int w, int h, int seed) {
  Image8 img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      for (int c = 0; c < 3; ++c) {
        const double v = 0.5 + 0.25 * std::sin(0.11 * x * (c + 1) + seed) + 0.25 * std::cos(0.07 * y * (3 - c) + 2 * seed);
        img.at(x, y, c) = std::uint8_t(std::lround(255.0 * std::clamp(v, 0.0, 1.0)));
      }
  return img;
}

inline Image8 solidImage(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Image8 img(w, h, 3);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      img.at(x, y, 0) = r;
      img.at(x, y, 1) = g;
      img.at(x, y, 2) = b;
    }
  return img;
}

inline const glm::dvec3 kStreetOrigin{651000.0, 6862000.0, 40.0};

// Ground 120 x 120 m at z = 40; a near building (x -5..5, y 10..14, 12 m) in front of a far one
// (x -15..15, y 30..34, 20 m), seen from cameras around y = -10.
inline Scene streetScene() {
  Scene s;
  s.origin = kStreetOrigin;
  const glm::dvec3 o = kStreetOrigin;
  s.terrain.positions = {o + glm::dvec3(-60, -60, 0), o + glm::dvec3(60, -60, 0), o + glm::dvec3(60, 60, 0),
                         o + glm::dvec3(-60, 60, 0)};
  s.terrain.triangles = {{0, 1, 2}, {0, 2, 3}};
  auto box = [&](const std::string& id, double x0, double x1, double y0, double y1, double h) {
    Footprint f;
    f.id = id;
    f.rings = {{{o.x + x0, o.y + y0}, {o.x + x1, o.y + y0}, {o.x + x1, o.y + y1}, {o.x + x0, o.y + y1}}};
    return extrudeLod1(f, o.z, o.z + h);
  };
  s.buildings = box("near", -5, 5, 10, 14, 12);
  s.buildings.append(box("far", -15, 15, 30, 34, 20));
  return s;
}

// The default demo city (with its lidar scan), generated once per test binary and shared by every
// GL test that needs it: its loaded scene and held-out views (no images; the truth is in
// summary.truthDir).
struct DemoCity {
  demo::DemoSummary summary;
  Scene scene;
  std::vector<Photo> views;
};

inline const DemoCity& demoCity() {
  static const DemoCity city = [] {
    DemoCity c;
    // Without the traffic: the views are scored against a truth without vehicles.
    demo::DemoOptions options;
    options.traffic.enabled = false;
    c.summary = demo::generate(options, makeTempDir("demo-city"));
    Diagnostics diag;
    c.scene = loadScene(c.summary.scenePath, diag);
    EXPECT_TRUE(diag.ok());
    CameraFileOptions opt;
    opt.requireImages = false;
    c.views = readCameraFile(c.summary.viewsPath, opt, diag);
    return c;
  }();
  return city;
}

}  // namespace hv::testing
