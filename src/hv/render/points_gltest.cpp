// GL tests of the point pass: perspective-correct sprites, the mat3 (2016) and N'
// (2022) forms against each other, the diachrony filters on the demo city, and points vs
// mesh-only on the demo views.
#include "hv/demo/demo_city.h"
#include "hv/eval/metrics.h"
#include "hv/gpu/gl.h"
#include "hv/ibr/sprite_homography.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/chunks.h"
#include "hv/scene/point_normals.h"
#include "hv/render/renderer.h"
#include "hv/scene/native/raycast.h"
#include "hv/image/native/png_write.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/testing/data_dir.h"
#include "hv/util/dates.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <set>
#include <utility>

namespace hv::render {
namespace {

using testing::kStreetOrigin;

class PointsGlTest : public testing::PhotoGlTest {
 protected:
};

// One point with a normal, a facade-like plane at y = 5 facing the cameras.
void addPoint(Scene& s, glm::dvec3 world, glm::vec3 normal) {
  PointCloud& c = s.points;
  PointFields f;
  f.normals = true;
  const size_t n = c.size();
  c.resize(n + 1, f);
  c.positions[n] = world;
  c.normals[n] = normal;
}

Scene spriteScene() {
  Scene s = testing::streetScene();
  return s;
}

RenderSettings pointSettings(int k) {
  RenderSettings st;
  st.blend.k = k;
  st.depthSize = 512;
  st.points.enabled = true;
  st.points.filter = PointFilter::None;
  st.points.eyeDome = false;
  st.points.maxPointSizePx = 256.0;
  return st;
}

// Inside one large sprite the texture follows the plane's homography: many distinct colours, and
// each checked pixel shows the photograph's texel at the CPU projection of the plane point under
// it (the constant-colour squares of flat sprites would fail both).
TEST_F(PointsGlTest, SpritesArePerspectiveCorrect) {
  const glm::dvec3 o = kStreetOrigin;
  Scene scene = spriteScene();
  const Camera photo = testing::lookAt("a", o + glm::dvec3(0, -10, 4), o + glm::dvec3(0, 5, 4), 160, 120, 120);
  const Image8 pattern = testing::patternImage(160, 120, 3);
  addPhoto(scene, photo, pattern);
  const glm::dvec3 P = o + glm::dvec3(0, 5, 4);
  const glm::vec3 N = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f));
  addPoint(scene, P, N);
  organizeChunks(scene.points);
  RenderSettings st = pointSettings(1);
  st.points.radius = 1.5;
  Diagnostics diag;
  Renderer renderer(scene, st, diag);
  const Camera view = testing::lookAt("v", o + glm::dvec3(2, -3, 5), P, 160, 120, 100);
  const RenderOutput out = renderer.render(view);
  ASSERT_TRUE(diag.ok());
  EXPECT_EQ(renderer.stats().pointsDrawn, 1u);

  const glm::dmat3 M = view.pixFromWorld(), Minv = glm::inverse(M);
  std::set<std::uint32_t> colours;
  int checked = 0, inside = 0;
  for (int y = 0; y < 120; ++y)
    for (int x = 0; x < 160; ++x) {
      // The plane point under the pixel, inside the disk, and its pixel in the photograph.
      const glm::dvec3 d = Minv * glm::dvec3(x + 0.5, y + 0.5, 1.0);
      const double t = glm::dot(glm::dvec3(N), P - view.center) / glm::dot(glm::dvec3(N), d);
      const glm::dvec3 X = view.center + t * d;
      if (glm::length(X - P) > 1.45) continue;  // margin: the disk edge is sampled at pixel centres
      ++inside;
      const std::uint8_t* px = &out.rgba.data[(size_t(y) * 160 + x) * 4];
      ASSERT_EQ(px[3], 255) << x << "," << y;
      colours.insert(px[0] | px[1] << 8 | px[2] << 16);
      const Projection pr = photo.project(X);
      if (!pr.inImage || pr.pxIdeal.x < 2 || pr.pxIdeal.y < 2 || pr.pxIdeal.x > 158 || pr.pxIdeal.y > 118) continue;
      // Bilinear sample at texel centres (the GPU's linear filtering), 8-bit: 3 levels of tolerance
      // for float rounding plus the gradient of the pattern over the float error of the position.
      const double u = pr.pxIdeal.x - 0.5, v = pr.pxIdeal.y - 0.5;
      const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
      const double fx = u - x0, fy = v - y0;
      for (int c = 0; c < 3; ++c) {
        const double e = (1 - fx) * (1 - fy) * pattern.at(x0, y0, c) + fx * (1 - fy) * pattern.at(x0 + 1, y0, c) +
                         (1 - fx) * fy * pattern.at(x0, y0 + 1, c) + fx * fy * pattern.at(x0 + 1, y0 + 1, c);
        EXPECT_NEAR(double(px[c]), e, 4.0) << "pixel " << x << "," << y << " channel " << c;
      }
      ++checked;
    }
  std::cout << "[ sprite ] " << inside << " pixels inside one sprite, " << colours.size() << " distinct colours, "
            << checked << " checked against the CPU homography\n";
  EXPECT_GT(inside, 500);
  EXPECT_GT(colours.size(), size_t(inside / 4));
  EXPECT_GT(checked, 400);
}

// A grid of points on two tilted planes seen by three photographs: the 2016 form (a mat3 varying
// per image) and the 2022 form (N') give the same picture (both are H_i p; floats differ in the
// last bits, so one 8-bit level).
TEST_F(PointsGlTest, Mat3AndPlaneVectorFormsAgree) {
  const glm::dvec3 o = kStreetOrigin;
  Scene scene = spriteScene();
  addPhoto(scene, testing::lookAt("a", o + glm::dvec3(-3, -10, 4), o + glm::dvec3(0, 8, 4), 160, 120, 120),
           testing::patternImage(160, 120, 1));
  addPhoto(scene, testing::lookAt("b", o + glm::dvec3(3, -9, 3), o + glm::dvec3(0, 8, 5), 160, 120, 110),
           testing::patternImage(160, 120, 2));
  addPhoto(scene, testing::lookAt("c", o + glm::dvec3(0, -12, 6), o + glm::dvec3(0, 8, 3), 160, 120, 140),
           testing::patternImage(160, 120, 3));
  for (int i = -8; i <= 8; ++i)
    for (int j = 0; j <= 10; ++j) {
      addPoint(scene, o + glm::dvec3(0.5 * i, 6.0 + 0.05 * i, 1.0 + 0.5 * j), glm::normalize(glm::vec3(0.1f, -1, 0)));
      addPoint(scene, o + glm::dvec3(0.5 * i, 2.0 + 0.5 * j, 0.3), glm::vec3(0, 0, 1));
    }
  organizeChunks(scene.points);
  RenderSettings st = pointSettings(3);
  st.points.radius = 0.4;
  const Camera view = testing::lookAt("v", o + glm::dvec3(1, -4, 3), o + glm::dvec3(0, 6, 3), 160, 120, 100);
  Diagnostics diag;
  Image8 a, b;
  {
    Renderer r(scene, st, diag);
    a = r.render(view).rgba;
  }
  st.points.form = SpriteForm::Mat3;
  {
    Renderer r(scene, st, diag);
    b = r.render(view).rgba;
    EXPECT_EQ(r.stats().mat3Images, 3);
  }
  ASSERT_TRUE(diag.ok());
  int maxDiff = 0, differing = 0, covered = 0;
  for (size_t i = 0; i < a.data.size(); i += 4) {
    covered += a.data[i + 3] > 0;
    int d = 0;
    for (int c = 0; c < 4; ++c) d = std::max(d, std::abs(int(a.data[i + c]) - int(b.data[i + c])));
    maxDiff = std::max(maxDiff, d);
    differing += d > 1;
  }
  std::cout << "[ mat3 vs N' ] covered " << covered << " px, max difference " << maxDiff << ", " << differing
            << " px differ by more than 1\n";
  EXPECT_GT(covered, 5000);
  EXPECT_LE(differing, covered / 1000);  // a few edge pixels where the depth winner differs
}

// The date test of the per-image chain (shaders/image_test.glsl), in the point pass as in the mesh
// pass: points sampling the façade of a building built in 1950 are not textured by a photograph of
// 1905 (whose depth map sees through the building to the far one, so no shadow hides them), and are
// by one of 1960.
TEST_F(PointsGlTest, PhotographsDoNotTexturePointsOfBuildingsThatDidNotExistAtTheirDate) {
  const glm::dvec3 o = kStreetOrigin;
  auto centre = [&](const std::string& photoDate) {
    Scene scene = spriteScene();
    // Tag the buildings: 0 = near (built in 1950), 1 = far (always there).
    scene.buildings.triangleTags.assign(scene.buildings.triangles.size(), 1);
    for (size_t t = 0; t < 12; ++t) scene.buildings.triangleTags[t] = 0;  // the near box's 12 triangles come first
    DateInterval builtIn1950;
    builtIn1950.first = parseDate("1950")->first;
    scene.buildingValidity = {builtIn1950, DateInterval{}};
    // Points 10 cm in front of the near building's façade (y = 10), facing the cameras.
    for (double x = -3.0; x <= 3.0; x += 0.2)
      for (double z = 2.0; z <= 10.0; z += 0.2) addPoint(scene, o + glm::dvec3(x, 9.9, z), glm::vec3(0, -1, 0));
    organizeChunks(scene.points);
    addPhoto(scene, testing::lookAt("red", o + glm::dvec3(0, -10, 6), o + glm::dvec3(0, 30, 10), 160, 120, 110),
             testing::solidImage(160, 120, 255, 0, 0));
    scene.photos.back().date = photoDate;
    RenderSettings st = pointSettings(1);
    st.points.radius = 0.2;
    Diagnostics diag;
    Renderer renderer(scene, st, diag);
    const Camera front = testing::lookAt("f", o + glm::dvec3(0, 2, 6), o + glm::dvec3(0, 10, 6), 80, 60, 40);
    const RenderOutput out = renderer.render(front);
    EXPECT_TRUE(diag.ok());
    EXPECT_GT(renderer.stats().pointsDrawn, 0u);
    // The centre pixel's red and alpha (alpha 255: textured; 0: a point in its own colour).
    return std::pair<int, int>(out.rgba.at(40, 30, 0), out.rgba.at(40, 30, 3));
  };
  EXPECT_EQ(centre("1905-06-01").second, 0);
  EXPECT_EQ(centre("1960-06-01"), std::make_pair(255, 255));
}

TEST_F(PointsGlTest, LargestMat3ImageCountThatLinks) {
  const gpu::GlLimits limits = gpu::queryLimits();
  const int k = probeMat3SpriteImages(32);
  std::cout << "[ mat3 ] MAX_VARYING_COMPONENTS " << limits.maxVaryingComponents << ": the mat3 sprite program links "
            << "with up to K = " << k << " images\n";
  EXPECT_GE(k, 1);
  EXPECT_LE(k * 9, limits.maxVaryingComponents);
}

using testing::DemoCity;
using testing::demoCity;

Camera smallView(const Camera& v, double s) {
  Camera c = v;
  c.width = int(std::lround(v.width * s));
  c.height = int(std::lround(v.height * s));
  c.focal *= s;
  c.principal *= s;
  if (c.distortion) c.distortion.reset();
  return c;
}

struct FilterCounts {
  int transientPixels = 0, transientTextured = 0, texturedPoints = 0;
};

// Pixels where transient points show: those that change when they are hidden (classification
// filter); then, under `filter`, how many of those pixels are textured (coverage alpha > 0).
FilterCounts filterCounts(const Scene& scene, const std::vector<Photo>& views, PointFilter filter) {
  FilterCounts fc;
  for (size_t v = 0; v < std::min<size_t>(views.size(), 4); ++v) {
    const Camera view = smallView(views[v].camera, 0.25);
    RenderSettings st;
    st.depthSize = 512;
    st.points.enabled = true;
    st.points.eyeDome = false;
    st.points.color = PointColorMode::Classification;
    st.points.filter = PointFilter::Classification;
    Diagnostics diag;
    auto renderWith = [&](const RenderSettings& s) {
      Renderer r(scene, s, diag);
      return r.render(view).rgba;
    };
    const Image8 shown = renderWith(st);
    RenderSettings hiddenSt = st;
    hiddenSt.points.hideTransient = true;
    const Image8 hidden = renderWith(hiddenSt);
    RenderSettings filteredSt = st;
    filteredSt.points.filter = filter;
    const Image8 filtered = filter == PointFilter::Classification ? shown : renderWith(filteredSt);
    for (size_t i = 0; i < shown.data.size(); i += 4) {
      bool differs = false;
      for (int c = 0; c < 4; ++c) differs |= shown.data[i + c] != hidden.data[i + c];
      fc.texturedPoints += filtered.data[i + 3] > 0;
      if (!differs) continue;
      ++fc.transientPixels;
      fc.transientTextured += filtered.data[i + 3] > 0;
    }
  }
  return fc;
}

TEST_F(PointsGlTest, DemoCityClassificationLeavesTreesAndCarsUntextured) {
  const DemoCity& city = demoCity();
  ASSERT_TRUE(city.scene.points.fields().classification);
  const FilterCounts fc = filterCounts(city.scene, city.views, PointFilter::Classification);
  std::cout << "[ classes ] transient pixels " << fc.transientPixels << ", textured " << fc.transientTextured << "\n";
  EXPECT_GT(fc.transientPixels, 50);
  // The changed pixels also include mesh pixels next to a tree whose screen-space normal (and so
  // shadow bias) changes when the tree is hidden: 1 % tolerance for those (3 of 1675 measured).
  EXPECT_LE(fc.transientTextured, fc.transientPixels / 100);
}

// Without classification, epsilon (2e-3 of the scene extent) does the same for points well in
// front of the model; points of a tree or car within epsilon of the ground or a wall (trunk
// bases, wheels) may be textured: tolerance 5 % of the transient pixels (8 of 1675 measured).
TEST_F(PointsGlTest, DemoCityEpsilonFilterLeavesMostTransientPointsUntextured) {
  const DemoCity& city = demoCity();
  const FilterCounts fc = filterCounts(city.scene, city.views, PointFilter::Epsilon);
  std::cout << "[ epsilon ] transient pixels " << fc.transientPixels << ", textured " << fc.transientTextured << "\n";
  EXPECT_GT(fc.transientPixels, 50);
  EXPECT_LE(fc.transientTextured, fc.transientPixels / 20);
}

// The demo scene without its transient points (trees 5, cars 1): what a tree could change.
Scene withoutTransient(const Scene& scene) {
  Scene s = scene;
  const PointCloud& c = scene.points;
  std::vector<std::uint32_t> kept;
  for (std::uint32_t i = 0; i < c.size(); ++i)
    if (c.classification[i] != 5 && c.classification[i] != 1) kept.push_back(i);
  // Normals estimated when first needed (hv/scene/point_normals.h): made now, over the whole cloud.
  const std::vector<glm::vec3>& normals = pointNormals(c);
  PointFields fields = c.fields();
  fields.normals = !normals.empty();
  PointCloud out;
  out.resize(kept.size(), fields);
  for (size_t j = 0; j < kept.size(); ++j) {
    const std::uint32_t i = kept[j];
    out.positions[j] = c.positions[i];
    if (!c.intensity.empty()) out.intensity[j] = c.intensity[i];
    out.classification[j] = c.classification[i];
    if (!c.rgb.empty()) out.rgb[j] = c.rgb[i];
    if (!normals.empty()) out.normals[j] = normals[i];
  }
  out.crs = c.crs;
  organizeChunks(out);
  s.points = std::move(out);
  return s;
}

// No building (or ground) pixel is shadowed by a tree: every pixel the photographs texture comes
// out the same whether the trees and cars are in the cloud or not (they are shown untextured,
// never written into depth maps). Classification: exactly; epsilon (classes ignored, depth maps of
// the model only): the same, within 0.5 % of the textured pixels for the sprites whose depth
// order against the mesh changes where a tree stands in front of them.
TEST_F(PointsGlTest, DemoCityNoTexturedPixelIsShadowedByATree) {
  const DemoCity& city = demoCity();
  const Scene bare = withoutTransient(city.scene);
  ASSERT_LT(bare.points.size(), city.scene.points.size());
  for (PointFilter filter : {PointFilter::Classification, PointFilter::Epsilon}) {
    long textured = 0, differing = 0;
    for (size_t v = 0; v < std::min<size_t>(city.views.size(), 4); ++v) {
      const Camera view = smallView(city.views[v].camera, 0.25);
      RenderSettings st;
      st.depthSize = 512;
      st.points.enabled = true;
      st.points.eyeDome = false;
      st.points.filter = filter;
      // One radius for all sprites: the per-chunk default follows each chunk's density, which
      // removing points changes.
      st.points.radius = 0.3;
      Diagnostics diag;
      Image8 with, without;
      {
        Renderer r(city.scene, st, diag);
        with = r.render(view).rgba;
      }
      {
        Renderer r(bare, st, diag);
        without = r.render(view).rgba;
      }
      // A tree or car pixel: untextured with them, textured without.
      auto transient = [&](int x, int y) {
        const size_t i = 4 * (size_t(y) * view.width + x);
        return with.data[i + 3] == 0 && without.data[i + 3] > 0;
      };
      for (int y = 1; y + 1 < view.height; ++y) {
        for (int x = 1; x + 1 < view.width; ++x) {
          const size_t i = 4 * (size_t(y) * view.width + x);
          if (with.data[i + 3] == 0) continue;  // untextured (a tree or car point, or nothing)
          // Next to a tree the shading pass's normal (screen derivatives over 2x2 pixels) spans
          // the tree's depth, and so does its slope-scaled bias: not a shadow, left out.
          bool besideTransient = false;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) besideTransient |= transient(x + dx, y + dy);
          if (besideTransient) continue;
          ++textured;
          bool differs = without.data[i + 3] == 0;
          for (int c = 0; c < 3; ++c) differs |= with.data[i + c] != without.data[i + c];
          differing += differs;
        }
      }
    }
    const char* name = filter == PointFilter::Classification ? "classes" : "epsilon";
    std::cout << "[ " << name << " ] textured pixels " << textured << ", changed by the trees and cars " << differing
              << "\n";
    EXPECT_GT(textured, 1000);
    if (filter == PointFilter::Classification)
      EXPECT_EQ(differing, 0);
    else
      EXPECT_LE(differing, textured / 200);
  }
}

// Where the LOD1 model lacks the city's detail: pixels whose ground-truth surface (World::truth:
// balconies, recessed windows and doors, kerbs) is more than `tolerance` from the model the
// renderer has (terrain + LOD1 buildings) along the pixel's ray, or that only one of them hits.
// Ray cast on the CPU (Embree), independently of the renderer.
std::vector<std::uint8_t> detailMask(const RayCaster& truth, const RayCaster& model, const Camera& view,
                                     double tolerance) {
  std::vector<std::uint8_t> mask(size_t(view.width) * view.height, 0);
  for (int y = 0; y < view.height; ++y) {
    for (int x = 0; x < view.width; ++x) {
      const glm::dvec3 dir = view.rayDirection({x + 0.5, y + 0.5});
      const auto t = truth.intersect(view.center, dir);
      const auto m = model.intersect(view.center, dir);
      if (!t) continue;  // sky: nothing to texture
      mask[size_t(y) * view.width + x] = !m || std::abs(t->t - m->t) > tolerance;
    }
  }
  return mask;
}

// Points vs mesh-only on the demo views against their ground truth:
// where the model lacks detail the points, which sample the real surfaces, must do better; over
// the whole picture the figures are printed (the sprites' sampling competes with the mesh's exact
// planes where the model is right).
TEST_F(PointsGlTest, DemoCityPointsImproveWhereTheMeshLacksDetail) {
  const DemoCity& city = demoCity();
  const demo::World world = demo::buildWorld(demo::DemoOptions{});
  const RayCaster truth(world.truth.mesh);
  Mesh modelMesh = city.scene.terrain;
  modelMesh.append(city.scene.buildings);
  const RayCaster model(modelMesh);
  double sumMesh = 0, sumPoints = 0, allMesh = 0, allPoints = 0;
  int n = 0;
  for (size_t v = 0; v < std::min<size_t>(city.views.size(), 4); ++v) {
    const Camera view = smallView(city.views[v].camera, 0.5);
    const std::string truthPath = city.summary.truthDir + "/" + view.id + ".png";
    if (!std::filesystem::exists(truthPath)) continue;
    const Image8 truthImage = resizeImage(readImage(truthPath, 3), view.width, view.height);
    RenderSettings st;
    st.depthSize = 512;
    Diagnostics diag;
    Image8 mesh, points;
    {
      Renderer r(city.scene, st, diag);
      mesh = r.render(view).rgba;
    }
    st.points.enabled = true;
    st.points.hideTransient = true;
    {
      Renderer r(city.scene, st, diag);
      points = r.render(view).rgba;
    }
    const std::vector<std::uint8_t> detail = detailMask(truth, model, view, 0.1);
    std::vector<std::uint8_t> both(detail.size()), onDetail(detail.size());
    size_t detailPixels = 0;
    for (size_t i = 0; i < both.size(); ++i) {
      both[i] = mesh.data[4 * i + 3] > 0 && points.data[4 * i + 3] > 0;
      onDetail[i] = both[i] && detail[i];
      detailPixels += onDetail[i];
    }
    const double a = eval::compareImages(mesh, truthImage, onDetail).psnr;
    const double b = eval::compareImages(points, truthImage, onDetail).psnr;
    const double aa = eval::compareImages(mesh, truthImage, both).psnr;
    const double bb = eval::compareImages(points, truthImage, both).psnr;
    std::cout << "[ eval ] " << view.id << ": where the mesh lacks detail (" << detailPixels
              << " px): mesh-only " << a << " dB, with points " << b << " dB; whole view: " << aa << " / " << bb
              << " dB\n";
    if (detailPixels < 50) continue;
    sumMesh += a;
    sumPoints += b;
    allMesh += aa;
    allPoints += bb;
    ++n;
  }
  ASSERT_GT(n, 0);
  std::cout << "[ eval ] mean over " << n << " views, where the mesh lacks detail: mesh-only " << sumMesh / n
            << " dB, with points " << sumPoints / n << " dB; whole views: " << allMesh / n << " / "
            << allPoints / n << " dB\n";
  EXPECT_GT(sumPoints / n, sumMesh / n);
}

// Real lidar (../shared/data: AHN3 Delft with its footprints and DTM, PDAL's Autzen with RGB;
// neither has photographs, so the points show their own colour with eye-dome lighting): the
// whole scene loads (read, georeference, normals, chunks) in seconds and renders at 1280x720.
// Load and frame times are printed for docs/performance.md (not asserted).
TEST_F(PointsGlTest, RealLidarLoadsAndRenders) {
  bool any = false;
  for (const char* name : {"delft", "autzen"}) {
    const std::string dir = hv::testing::dataset(name);
    if (dir.empty()) continue;
    any = true;
    const auto t0 = std::chrono::steady_clock::now();
    Diagnostics diag;
    const Scene scene = loadScene(dir + "/scene.json", diag);
    const auto t1 = std::chrono::steady_clock::now();
    ASSERT_TRUE(diag.ok()) << name;
    ASSERT_FALSE(scene.points.empty()) << name;
    // An oblique view over the middle of the data, from the south, 300 m away.
    const Aabb b = scene.points.bounds();
    const glm::dvec3 target = b.center();
    const Camera view = lookAtCamera("v", target + glm::dvec3(0.0, -250.0, 160.0), target, 1280, 720, 1100.0);
    RenderSettings st;
    st.points.enabled = true;
    Renderer r(scene, st, diag);
    const auto t2 = std::chrono::steady_clock::now();
    const Image8 first = r.render(view).rgba;
    const auto t3 = std::chrono::steady_clock::now();
    r.render(view);
    const auto t4 = std::chrono::steady_clock::now();
    auto ms = [](auto a, auto c) { return std::chrono::duration<double, std::milli>(c - a).count(); };
    // Pixels the points drew: untextured points have alpha 0 and their own (non-black) colour.
    std::size_t drawn = 0;
    for (size_t i = 0; i < first.data.size(); i += 4)
      drawn += first.data[i] + first.data[i + 1] + first.data[i + 2] > 0;
    std::printf("[ lidar ] %s: %zu points, scene load %.0f ms, renderer setup %.0f ms, first frame %.0f ms, "
                "next frame %.0f ms, %llu sprites, %.0f %% of the pixels drawn\n",
                name, scene.points.size(), ms(t0, t1), ms(t1, t2), ms(t2, t3), ms(t3, t4),
                static_cast<unsigned long long>(r.stats().pointsDrawn), 100.0 * double(drawn) / (1280.0 * 720.0));
    EXPECT_GT(r.stats().pointsDrawn, scene.points.size() / 2) << name;
    EXPECT_GT(drawn, std::size_t(1280 * 720 / 10)) << name;
  }
  if (!any) HV_SKIP_WITHOUT_DATA(std::string("no delft/ or autzen/ in ") + hv::testing::dataDir() + " (set HISTOVIEW_DATA)");
}

}  // namespace
}  // namespace hv::render
