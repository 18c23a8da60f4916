// Shared by the *_gltest files: one headless context for the whole test binary, temporary
// directories, and a small synthetic street (ground, a near and a far building) whose photographs
// are arbitrary patterns: the GL-vs-CPU tests need any image, not a consistent one.
#pragma once

#include "hv/demo/demo_city.h"
#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/image/image.h"
#include "hv/image/native/png_write.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/native/lod1.h"
#include "hv/scene/scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
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

// The street's photographs "a" to "e", each at its own place, size and focal length, all looking
// up the street at the two buildings: "b"'s image is larger than the others, so that it sits
// padded in its slice; "d" and "e" stand further left and further back.
inline Camera streetPhotoCamera(char id) {
  const glm::dvec3 o = kStreetOrigin;
  switch (id) {
    case 'a': return lookAt("a", o + glm::dvec3(-6, -12, 2), o + glm::dvec3(0, 30, 8), 160, 120, 130);
    case 'b': return lookAt("b", o + glm::dvec3(4, -9, 1.7), o + glm::dvec3(-2, 32, 6), 200, 150, 150);
    case 'c': return lookAt("c", o + glm::dvec3(12, -6, 3), o + glm::dvec3(0, 32, 10), 120, 120, 100);
    case 'd': return lookAt("d", o + glm::dvec3(-14, -4, 2.5), o + glm::dvec3(0, 32, 9), 160, 120, 110);
    case 'e': return lookAt("e", o + glm::dvec3(0, -20, 4), o + glm::dvec3(0, 32, 9), 160, 120, 120);
    default: ADD_FAILURE() << "no street photograph '" << id << "'"; return {};
  }
}

// The view the street tests render: among the photographs, looking up the street.
inline Camera streetView() {
  const glm::dvec3 o = kStreetOrigin;
  return lookAt("v", o + glm::dvec3(1, -11, 2.2), o + glm::dvec3(0, 31, 9), 160, 120, 120);
}

// A GL test whose photographs are PNG files (and masks) in a temporary folder, as a scene on disk
// names them.
class PhotoGlTest : public GlTest {
 protected:
  void addPhoto(Scene& s, const Camera& cam, const Image8& image, const Image8* mask = nullptr) {
    if (dir_.empty()) dir_ = makeTempDir("gl-photos");
    Photo p;
    p.camera = cam;
    p.imagePath = dir_ + "/" + cam.id + ".png";
    writePng(p.imagePath, image);
    if (mask) {
      p.maskPath = dir_ + "/" + cam.id + ".mask.png";
      writePng(p.maskPath, *mask);
    }
    s.photos.push_back(p);
  }

  // Adds the street photographs `ids` (streetPhotoCamera), each with its own pattern (seed 1 for
  // "a", 2 for "b", ...). With `distortionRadius` > 0, "b" has a radial distortion (centre off the
  // image centre, c3 = -4e-6) whose domain reaches that many pixels from its centre.
  void addStreetPhotos(Scene& s, std::string_view ids, double distortionRadius = 0.0) {
    for (const char id : ids) {
      Camera cam = streetPhotoCamera(id);
      if (id == 'b' && distortionRadius > 0.0) {
        LensDistortion d;
        d.center = {101.0, 74.0};
        d.c3 = -4e-6;
        d.r2max = distortionRadius * distortionRadius;
        cam.distortion = d;
      }
      addPhoto(s, cam, patternImage(cam.width, cam.height, id - 'a' + 1));
    }
  }

  std::string dir_;
};

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
