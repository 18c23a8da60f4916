// The frame logic on the CPU, through the null backend: what the builder asks the backend to do
// frame after frame (uploads, depth maps, view passes) and the statistics the viewer shows. The
// expected values come from the scene's construction (distances computed here, ceil(T / Dmax)
// written out), not from the code under test.
#include "hv/render/frame_builder.h"

#include "hv/image/native/png_write.h"
#include "hv/render/null_backend.h"
#include "hv/scene/building_tiles.h"
#include "hv/scene/chunks.h"
#include "hv/scene/terrain_quadtree.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <numeric>
#include <set>

namespace hv::render {
namespace {

namespace fs = std::filesystem;

constexpr int kPhotos = 10;

class FrameBuilderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("hv_frame_builder_test_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    // A 200 m square of ground at z = 0.
    scene_.terrain.positions = {{-100, -100, 0}, {100, -100, 0}, {100, 100, 0}, {-100, 100, 0}};
    scene_.terrain.triangles = {{0, 1, 2}, {0, 2, 3}};
    // Photographs on a spiral around the centre, all looking at it, each farther from the view
    // than the one before (radius 30 + 7 i m, 20 m up).
    for (int i = 0; i < kPhotos; ++i) {
      const double a = 0.6 * i, r = 30.0 + 7.0 * i;
      Photo p;
      p.camera =
          lookAtCamera("p" + std::to_string(i), {r * std::cos(a), r * std::sin(a), 20.0}, {0, 0, 0}, 32, 24, 30.0);
      Image8 im(32, 24, 3, std::uint8_t(20 * i));
      p.imagePath = (dir_ / (p.camera.id + ".png")).string();
      writePng(p.imagePath, im);
      scene_.photos.push_back(p);
    }
    settings_.blend.k = kPhotos;
    settings_.decodeThreads = 0;  // decodes on this thread: one per progressive frame, deterministic
    settings_.depthSize = 64;
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A 100 x 100 grid of ground points (class 2), 1 m apart, organised into chunks.
  void addGroundPoints() {
    PointCloud& c = scene_.points;
    c.sourcePath = "ground.las";
    c.resize(10000, PointFields{false, true, false, false});
    for (int i = 0; i < 10000; ++i) {
      c.positions[size_t(i)] = {i % 100 - 50.0, i / 100 - 50.0, 0.0};
      c.classification[size_t(i)] = 2;
    }
    organizeChunks(c);
  }

  // Above the centre, looking down at it: every photograph sees part of the view.
  static Camera view() { return lookAtCamera("view", {0, -1, 60}, {0, 0, 0}, 64, 48, 50.0); }

  // The photographs by distance from the view's centre, nearest first.
  std::vector<int> byDistance() const {
    std::vector<int> order(kPhotos);
    std::iota(order.begin(), order.end(), 0);
    const glm::dvec3 c = view().center;
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      return glm::length(scene_.photos[a].camera.center - c) < glm::length(scene_.photos[b].camera.center - c);
    });
    return order;
  }

  std::vector<int> photosDrawn(size_t from) const {
    std::vector<int> photos;
    for (size_t i = from; i < backend_.depthMaps.size(); ++i) photos.push_back(backend_.depthMaps[i].photo);
    return photos;
  }

  fs::path dir_;
  Scene scene_;
  RenderSettings settings_;
  Diagnostics diag_;
  NullBackend backend_;
};

TEST_F(FrameBuilderTest, BatchFrameLoadsAndDrawsEverySelectedImage) {
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  const Frame f = builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(f.plan.images.size(), size_t(kPhotos));
  EXPECT_EQ(backend_.uploads.size(), size_t(kPhotos));
  EXPECT_EQ(backend_.depthMaps.size(), size_t(kPhotos));
  EXPECT_EQ(f.params.size(), size_t(kPhotos));
  EXPECT_EQ(f.packedParams.size(), size_t(kPhotos) * ibr::kTexelsPerImage * 4);
  EXPECT_EQ(builder.stats().imagesWaiting, 0);
  EXPECT_EQ(builder.stats().depthMapsThisFrame, kPhotos);
  EXPECT_TRUE(builder.converged());
  // Every map is drawn into the slot its photograph was uploaded to, at the requested size.
  for (const DepthMapJob& job : backend_.depthMaps) {
    EXPECT_EQ(job.slot, builder.slotOf(job.photo));
    EXPECT_EQ(job.size, 64);
  }
  // A second frame of the same view loads and draws nothing.
  builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(backend_.uploads.size(), size_t(kPhotos));
  EXPECT_EQ(backend_.depthMaps.size(), size_t(kPhotos));
}

TEST_F(FrameBuilderTest, ProgressiveFramesConvergeInCeilTOverDmaxNearestFirst) {
  settings_.depthMapsPerFrame = 3;
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  builder.preload(view());  // every image resident, no depth map drawn yet
  EXPECT_EQ(backend_.uploads.size(), size_t(kPhotos));
  EXPECT_TRUE(backend_.depthMaps.empty());
  const std::vector<int> order = byDistance();
  // T = 10 maps at Dmax = 3: 3 + 3 + 3 + 1, converged after ceil(10 / 3) = 4 frames.
  const int drawnPerFrame[] = {3, 3, 3, 1};
  const int waitingAfter[] = {7, 4, 1, 0};
  size_t drawn = 0;
  for (int frame = 0; frame < 4; ++frame) {
    if (frame > 0) EXPECT_FALSE(builder.converged());
    const Frame f = builder.build(view(), FrameMode::Progressive, false);
    ASSERT_EQ(f.depthMapsDrawn.size(), size_t(drawnPerFrame[frame])) << "frame " << frame;
    const std::vector<int> expected(order.begin() + std::ptrdiff_t(drawn),
                                    order.begin() + std::ptrdiff_t(drawn + drawnPerFrame[frame]));
    EXPECT_EQ(photosDrawn(drawn), expected) << "frame " << frame;
    drawn += size_t(drawnPerFrame[frame]);
    EXPECT_EQ(builder.stats().depthMapsWaiting, waitingAfter[frame]);
    EXPECT_EQ(builder.stats().imagesWaiting, waitingAfter[frame]);
    EXPECT_EQ(builder.stats().decodesWaiting, 0);
    // The images whose map is current are blended; the others wait.
    EXPECT_EQ(f.params.size(), drawn);
  }
  EXPECT_TRUE(builder.converged());
  EXPECT_EQ(ibr::framesToConverge(kPhotos, 3), 4);
}

TEST_F(FrameBuilderTest, ProgressiveFramesWaitForDecodes) {
  // No preload, no decoding thread: each progressive frame decodes one photograph, nearest first.
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  const std::vector<int> order = byDistance();
  for (int frame = 1; frame <= 3; ++frame) {
    builder.build(view(), FrameMode::Progressive, false);
    EXPECT_EQ(backend_.uploads.size(), size_t(frame));
    EXPECT_EQ(builder.stats().decodesWaiting, kPhotos - frame);
    EXPECT_EQ(builder.stats().depthMapsWaiting, 0);
    EXPECT_EQ(builder.stats().imagesWaiting, kPhotos - frame);
    EXPECT_EQ(builder.photoState(order[size_t(frame - 1)]), PhotoState::Ready);
    EXPECT_FALSE(builder.converged());
  }
  EXPECT_EQ(builder.photoState(order.back()), PhotoState::Decoding);
}

TEST_F(FrameBuilderTest, DepthBudgetDrawsAtLeastOneMapAndFinishesEach) {
  settings_.depthMapsPerFrame = 4;
  settings_.depthBudgetMs = 1e-9;  // spent as soon as one map is drawn
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  builder.preload(view());
  const Frame f = builder.build(view(), FrameMode::Progressive, false);
  EXPECT_EQ(f.depthMapQueue.size(), 4u);
  EXPECT_EQ(f.depthMapsDrawn.size(), 1u);
  EXPECT_EQ(backend_.finishes, 1);
  EXPECT_EQ(builder.stats().depthMapsWaiting, kPhotos - 1);
}

TEST_F(FrameBuilderTest, GenerousDepthBudgetStopsAtDmax) {
  settings_.depthMapsPerFrame = 4;
  settings_.depthBudgetMs = 1e9;
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  builder.preload(view());
  const Frame f = builder.build(view(), FrameMode::Progressive, false);
  EXPECT_EQ(f.depthMapsDrawn.size(), 4u);
  EXPECT_EQ(backend_.finishes, 4);
}

TEST_F(FrameBuilderTest, LayerSwitchRedrawsEveryDepthMapWithoutReloading) {
  RenderSettings& s = settings_;
  FrameBuilder builder(scene_, s, diag_, backend_);
  builder.build(view(), FrameMode::Batch, false);
  const size_t maps = backend_.depthMaps.size();
  s.layers.buildings = false;
  builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(backend_.uploads.size(), size_t(kPhotos));
  ASSERT_EQ(backend_.depthMaps.size(), maps + kPhotos);
  for (size_t i = maps; i < backend_.depthMaps.size(); ++i) {
    const auto& layers = backend_.depthMaps[i].layers;
    EXPECT_TRUE(layers[kLayerTerrain] && !layers[kLayerBuildings] && layers[kLayerMesh]);
  }
  // Progressive: the switch makes every map wait again, Dmax redrawn per frame.
  s.depthMapsPerFrame = 4;
  s.layers.terrain = false;
  builder.build(view(), FrameMode::Progressive, false);
  EXPECT_EQ(builder.stats().depthMapsThisFrame, 4);
  EXPECT_EQ(builder.stats().depthMapsWaiting, kPhotos - 4);
}

TEST_F(FrameBuilderTest, LensSwitchRedrawsEveryDepthMap) {
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  builder.build(view(), FrameMode::Batch, false);
  settings_.layers.lensDistortion = false;
  builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(backend_.depthMaps.size(), size_t(2 * kPhotos));
  EXPECT_EQ(backend_.uploads.size(), size_t(kPhotos));
}

TEST_F(FrameBuilderTest, MaskSwitchReloadsEveryPhotograph) {
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  builder.build(view(), FrameMode::Batch, false);
  settings_.blend.masks = false;
  builder.build(view(), FrameMode::Batch, false);
  // The slices hold the colour premultiplied by the mask: decoded and uploaded again, and their
  // depth maps drawn again (a slot's map belongs to the photograph uploaded into it).
  EXPECT_EQ(backend_.uploads.size(), size_t(2 * kPhotos));
  EXPECT_EQ(backend_.depthMaps.size(), size_t(2 * kPhotos));
  EXPECT_EQ(builder.stats().imagesLoaded, 2 * kPhotos);
}

TEST_F(FrameBuilderTest, DebugViewAndBlendSettingsRedrawNothing) {
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  builder.build(view(), FrameMode::Batch, false);
  settings_.debug.view = DebugView::Counts;
  settings_.debug.frusta = true;
  settings_.blend.method = ibr::BlendMethod::Nearest;
  settings_.background = {1, 0, 0};
  const Frame f = builder.build(view(), FrameMode::Batch, true);
  EXPECT_EQ(backend_.uploads.size(), size_t(kPhotos));
  EXPECT_EQ(backend_.depthMaps.size(), size_t(kPhotos));
  // What the view passes are asked instead.
  EXPECT_EQ(f.debug.view, DebugView::Counts);
  ASSERT_NE(f.debug.frustumLines, nullptr);
  EXPECT_EQ(f.debug.frustumLines->perPhoto.size(), size_t(kPhotos));
  EXPECT_EQ(f.blend.method, ibr::BlendMethod::Nearest);
  EXPECT_TRUE(f.withCounts);
  EXPECT_EQ(f.background, glm::dvec3(1, 0, 0));
}

TEST_F(FrameBuilderTest, DepthMapDebugViewLoadsAndDrawsItsPhotographOutsideTheFrame) {
  settings_.blend.k = 3;
  settings_.blend.selection = ibr::Selection::Global;  // the frame's images: the three nearest
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  const int farthest = byDistance().back();
  settings_.debug.view = DebugView::DepthMap;
  settings_.debug.photo = farthest;
  const Frame f = builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(f.plan.images.size(), 3u);
  // The three nearest and the debug photograph.
  EXPECT_EQ(backend_.uploads.size(), 4u);
  EXPECT_EQ(backend_.depthMaps.size(), 4u);
  EXPECT_EQ(backend_.depthMaps.back().photo, farthest);
  EXPECT_EQ(f.debug.slot, builder.slotOf(farthest));
  EXPECT_EQ(f.debug.image, -1);  // not among the frame's images
  EXPECT_FALSE(f.debug.frusta);  // never over the depth-map view
}

TEST_F(FrameBuilderTest, KBeyondTheSlotsIsCappedAndSaid) {
  settings_.maxSlices = 4;
  settings_.blend.selection = ibr::Selection::Global;
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  EXPECT_EQ(backend_.layout().slots, 4);
  const Frame f = builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(f.blend.k, 4);
  EXPECT_EQ(f.plan.images.size(), 4u);
  ASSERT_FALSE(diag_.warnings.empty());
  EXPECT_NE(diag_.warnings.front().find("exceeds the image slots available (4"), std::string::npos);
}

TEST_F(FrameBuilderTest, KCappedIsSaidOnceNamingWhatBoundsTheSlots) {
  settings_.maxSlices = 4;
  settings_.blend.selection = ibr::Selection::Global;
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  for (int i = 0; i < 3; ++i) builder.build(view(), FrameMode::Batch, false);
  ASSERT_EQ(diag_.warnings.size(), 1u);
  EXPECT_NE(diag_.warnings.front().find("bounded by --max-slices 4)"), std::string::npos) << diag_.warnings.front();
  EXPECT_EQ(diag_.warnings.front().find("MAX_ARRAY_TEXTURE_LAYERS"), std::string::npos) << diag_.warnings.front();
}

TEST_F(FrameBuilderTest, KAboveThePhotographsIsNoWarning) {
  // Every photograph has a slot: a K above their count loses nothing.
  settings_.blend.selection = ibr::Selection::Global;
  settings_.blend.k = kPhotos + 5;
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  EXPECT_EQ(backend_.layout().slots, kPhotos);
  const Frame f = builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(f.blend.k, kPhotos);
  EXPECT_TRUE(diag_.warnings.empty()) << diag_.warnings.front();
}

TEST_F(FrameBuilderTest, RegionCandidatesAreCappedByTheSlotsAndKKeepsItsMeaning) {
  settings_.maxSlices = 4;
  settings_.blend.selection = ibr::Selection::Region;
  settings_.blend.candidates = 24;
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  const Frame f = builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(f.blend.candidates, 4);
  EXPECT_EQ(f.blend.k, kPhotos);  // the most images blended at one pixel: not a residency bound
  EXPECT_EQ(f.plan.images.size(), 4u);
  EXPECT_EQ(backend_.uploads.size(), 4u);
  for (size_t i = 1; i < f.plan.images.size(); ++i) EXPECT_LE(f.plan.images[i - 1].distance, f.plan.images[i].distance);
  EXPECT_TRUE(diag_.warnings.empty());
}

TEST_F(FrameBuilderTest, NaiveBindingSlotsFollowTheFreeTextureUnits) {
  settings_.binding = Binding::Naive;
  BackendLimits limits;
  limits.naiveImageUnits = 6;  // three images, two units each
  NullBackend backend(limits);
  FrameBuilder builder(scene_, settings_, diag_, backend);
  EXPECT_EQ(backend.layout().slots, 3);
  const Frame f = builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(f.params.size(), 3u);
  EXPECT_FALSE(f.culling);  // the naive baseline walks every image
}

TEST_F(FrameBuilderTest, PointsRespectTheBudgetAndShareTheDepthMapsOnlyWithClassification) {
  addGroundPoints();
  settings_.points.enabled = true;
  settings_.points.budget = 2500;
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  EXPECT_EQ(backend_.points, 10000u);
  const Frame f = builder.build(view(), FrameMode::Batch, false);
  ASSERT_TRUE(f.points.enabled);
  EXPECT_GT(f.points.pass.points, 0u);
  EXPECT_LE(f.points.pass.points, 2500u);
  std::uint64_t sum = 0;
  for (const PointDraw& d : f.points.pass.draws) sum += d.count;
  EXPECT_EQ(sum, f.points.pass.points);
  EXPECT_EQ(builder.stats().pointsDrawn, f.points.pass.points);
  // Classified cloud, Auto filter: the classification filter, ground (2) kept, and the kept
  // points drawn into every depth map, transient ones dropped there.
  EXPECT_TRUE(f.points.pass.classify);
  EXPECT_EQ(f.points.pass.keptClasses[0] & (1u << 2), 1u << 2);
  ASSERT_EQ(backend_.depthMaps.size(), size_t(kPhotos));
  for (const DepthMapJob& job : backend_.depthMaps) {
    EXPECT_TRUE(job.withPoints);
    EXPECT_TRUE(job.points.dropTransient);
    EXPECT_LE(job.points.points, 2500u);
  }
  // Changing the kept classes changes what the depth maps hold: every one is redrawn.
  settings_.points.keptClasses = {2};
  builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(backend_.depthMaps.size(), size_t(2 * kPhotos));
  // The epsilon filter keeps the points out of the depth maps: redrawn once more, without them.
  settings_.points.filter = PointFilter::Epsilon;
  const Frame e = builder.build(view(), FrameMode::Batch, false);
  ASSERT_EQ(backend_.depthMaps.size(), size_t(3 * kPhotos));
  EXPECT_FALSE(backend_.depthMaps.back().withPoints);
  EXPECT_TRUE(e.points.epsilonTest);
  // A sprite setting of the view alone (eye-dome lighting) redraws nothing.
  settings_.points.eyeDome = false;
  builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(backend_.depthMaps.size(), size_t(3 * kPhotos));
}

TEST_F(FrameBuilderTest, PointsSwitchedOnLaterAreUploadedOnceAndRedrawTheDepthMaps) {
  addGroundPoints();
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(backend_.points, 0u);
  settings_.points.enabled = true;
  builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(backend_.points, 10000u);
  // The points extend the bounds (depth ranges) and share the depth maps: all redrawn.
  EXPECT_EQ(backend_.depthMaps.size(), size_t(2 * kPhotos));
  settings_.points.enabled = false;
  const Frame off = builder.build(view(), FrameMode::Batch, false);
  EXPECT_FALSE(off.points.enabled);
  EXPECT_EQ(backend_.depthMaps.size(), size_t(3 * kPhotos));  // the maps lose the points
}


// Streamed buildings (render/building_stream.h): a 10 x 10 grid of 40 m tiles, one 10 m tower in
// each, some of them dated. The photographs (within 93 m of the centre, focal 30 px: a reach of
// 4 m x 30 = 120 m) never see the far corner; a view looking there shows its towers all the same.
std::shared_ptr<BuildingTileSet> towerTiles() {
  auto set = std::make_shared<BuildingTileSet>();
  for (std::uint32_t t = 0; t < 100; ++t) {
    const double x = -200.0 + 40.0 * (t % 10), y = -200.0 + 40.0 * (t / 10);
    Aabb b;
    b.lo = {x - 40.0, y - 40.0, -50.0};
    b.hi = {x + 80.0, y + 80.0, 60.0};
    set->boxes.push_back(b);
  }
  set->read = [](std::uint32_t t) {
    const double x = -200.0 + 40.0 * (t % 10) + 15.0, y = -200.0 + 40.0 * (t / 10) + 15.0;
    BuildingTileData d;
    Mesh& m = d.mesh;
    for (int c = 0; c < 8; ++c) m.positions.push_back({x + (c & 1 ? 10.0 : 0.0), y + (c & 2 ? 10.0 : 0.0), c & 4 ? 10.0 : 0.0});
    const int f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                          {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    for (const auto& tri : f) m.triangles.push_back(glm::uvec3(tri[0], tri[1], tri[2]));
    m.triangleTags.assign(12, 0);
    DateInterval v;
    if (t % 4 == 1) v.first = 1000 + t;
    d.validity.push_back(v);
    return d;
  };
  return set;
}

TEST_F(FrameBuilderTest, StreamedBuildingsFollowTheViewAndTheirDatesComeWithThem) {
  scene_.buildingTiles = towerTiles();
  settings_.geometryThreads = 0;
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  // The far corner (tiles 88, 89, 98, 99), seen from inside the city.
  const Camera corner = lookAtCamera("corner", {60, 60, 30}, {175, 175, 5}, 64, 48, 60.0);
  const Frame f = builder.build(corner, FrameMode::Batch, false);
  ASSERT_TRUE(builder.converged());
  EXPECT_TRUE(builder.stats().streamingBuildings);
  std::set<std::uint32_t> viewTiles, mapTiles;
  for (std::uint64_t id : f.streamedTiles) {
    ASSERT_TRUE(id & kBuildingTileId);
    EXPECT_TRUE(backend_.streamedTiles.count(id));
    viewTiles.insert(std::uint32_t(id & ~kBuildingTileId));
  }
  for (const DepthMapJob& job : backend_.depthMaps)
    for (std::uint64_t id : job.streamedTiles) mapTiles.insert(std::uint32_t(id & ~kBuildingTileId));
  EXPECT_TRUE(viewTiles.count(99) && viewTiles.count(88)) << "the view shows the far corner's towers";
  EXPECT_FALSE(mapTiles.count(99)) << "no photograph reaches the far corner";
  EXPECT_TRUE(mapTiles.count(44) || mapTiles.count(55)) << "the photographs see the centre's towers";
  // One tower a tile, 12 triangles: what the backend holds is what the stream says.
  EXPECT_EQ(size_t(builder.stats().buildingTilesResident), backend_.streamedTiles.size());
  for (const auto& [id, triangles] : backend_.streamedTiles) EXPECT_EQ(triangles, 12);
  // The validity texels hold the dates of exactly the resident towers.
  std::multiset<float> expected, uploaded;
  for (const auto& [id, triangles] : backend_.streamedTiles) {
    const std::uint32_t t = std::uint32_t(id & ~kBuildingTileId);
    DateInterval v;
    if (t % 4 == 1) v.first = 1000 + t;
    expected.insert(ibr::gpuDays(v).x);
  }
  ASSERT_EQ(backend_.validityWidth, 1024);
  ASSERT_EQ(backend_.validity.size(), size_t(backend_.validityWidth) * backend_.validityRows * 4);
  for (std::uint32_t b = 0; b < builder.buildingStream()->buildingIndexEnd(); ++b)
    uploaded.insert(backend_.validity[size_t(b) * 4]);
  EXPECT_EQ(uploaded, expected);
  EXPECT_TRUE(diag_.ok());
}

TEST_F(FrameBuilderTest, StreamedBuildingsRedrawDepthMapsOnlyWhenTilesChangeAndStayWithinTheBudget) {
  scene_.buildingTiles = towerTiles();
  settings_.geometryThreads = 0;    // one tile a progressive frame, on this thread
  settings_.depthMapsPerFrame = 0;  // every dirty map at once, so a frame's redraws are its own
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  int frames = 0, redrawFrames = 0;
  for (; frames < 500 && (frames == 0 || !builder.converged()); ++frames) {
    const auto tilesBefore = backend_.streamedTiles;
    const size_t uploadsBefore = backend_.uploads.size(), mapsBefore = backend_.depthMaps.size();
    builder.build(view(), FrameMode::Progressive, false);
    const bool changed = backend_.streamedTiles != tilesBefore || backend_.uploads.size() != uploadsBefore;
    if (backend_.depthMaps.size() > mapsBefore) {
      ++redrawFrames;
      EXPECT_TRUE(changed) << "frame " << frames << " redrew a depth map with nothing new";
    }
  }
  ASSERT_TRUE(builder.converged());
  EXPECT_GT(frames, 3);
  EXPECT_GT(redrawFrames, 1);
  const size_t maps = backend_.depthMaps.size();
  for (int i = 0; i < 3; ++i) builder.build(view(), FrameMode::Progressive, false);
  EXPECT_EQ(backend_.depthMaps.size(), maps) << "nothing arrived: no depth map is redrawn";

  // A budget of a few towers: what is resident after each frame fits it, and the tiles are evicted
  // on the backend too.
  NullBackend tight;
  RenderSettings small = settings_;
  const std::size_t perTower = 8 * GeometryBuffers::kStride * sizeof(float) + 36 * sizeof(std::uint32_t);
  small.geometryMemoryBytes = 5 * perTower;
  FrameBuilder limited(scene_, small, diag_, tight);
  for (const Camera& c : {view(), lookAtCamera("corner", {60, 60, 30}, {175, 175, 5}, 64, 48, 60.0), view()}) {
    limited.build(c, FrameMode::Batch, false);
    EXPECT_LE(limited.stats().buildingBytes, small.geometryMemoryBytes);
    EXPECT_EQ(tight.streamedTiles.size(), size_t(limited.stats().buildingTilesResident));
  }
  EXPECT_GT(limited.stats().buildingEvictions, 0u);
  EXPECT_TRUE(diag_.ok());
}
}  // namespace
}  // namespace hv::render

namespace hv::render {
namespace {

// Geometry culling: on a finely tessellated 200 m ground (80,000 triangles, many tiles), each
// depth map and the view draw a subset of the tiles, and never leave out a triangle that their
// frustum sees (checked by projecting every triangle's vertices and centroid, independently of the
// tiles' boxes).
TEST_F(FrameBuilderTest, CullingKeepsEveryTriangleAFrustumSees) {
  Mesh& t = scene_.terrain;
  t = Mesh{};
  const int n = 200;
  for (int y = 0; y <= n; ++y)
    for (int x = 0; x <= n; ++x) t.positions.push_back({-100.0 + x, -100.0 + y, 0.05 * std::sin(0.1 * x * y)});
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const auto v = [&](int i, int j) { return std::uint32_t(j * (n + 1) + i); };
      t.triangles.push_back({v(x, y), v(x + 1, y), v(x + 1, y + 1)});
      t.triangles.push_back({v(x, y), v(x + 1, y + 1), v(x, y + 1)});
    }
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  const GeometryBuffers& g = backend_.geometry;
  ASSERT_GT(builder.stats().geometryTiles, 10);
  EXPECT_EQ(builder.stats().geometryTiles, int(g.tiles.size()));
  // A close, narrow view: few tiles.
  const Camera close = lookAtCamera("close", {-60, -60, 8}, {-40, -40, 0}, 64, 48, 80.0);
  const Frame f = builder.build(close, FrameMode::Batch, false);
  ASSERT_FALSE(backend_.depthMaps.empty());
  auto covered = [](const std::vector<DrawRange>& draws, int index) {
    for (const DrawRange& r : draws)
      if (index >= r.first && index < r.first + r.count) return true;
    return false;
  };
  auto check = [&](const Camera& cam, const std::vector<DrawRange>& draws, const std::string& what) {
    int seen = 0, drawn = 0, total = 0;
    for (const DrawRange& r : draws) drawn += r.count / 3;
    for (int i = 0; i < int(g.indices.size()); i += 3) {
      ++total;
      // Seen: a vertex or the centroid projects into the image in front of the camera.
      bool in = false;
      glm::dvec3 centroid(0.0);
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 p = t.positions[g.indices[size_t(i + k)]];
        centroid += p / 3.0;
        in = in || cam.project(p).inImage;
      }
      in = in || cam.project(centroid).inImage;
      if (!in) continue;
      ++seen;
      EXPECT_TRUE(covered(draws, i)) << what << ": triangle at index " << i << " is seen but not drawn";
    }
    EXPECT_GT(seen, 0) << what;
    EXPECT_LT(drawn, total) << what << " draws every triangle";
  };
  check(close, f.draws, "the view");
  EXPECT_LT(builder.stats().tilesDrawn, builder.stats().geometryTiles);
  for (const DepthMapJob& job : backend_.depthMaps) check(job.camera, job.draws, "depth map of " + job.camera.id);

  // Culling off: every tile, one range.
  settings_.geometryCulling = false;
  const Frame all = builder.build(close, FrameMode::Batch, false);
  ASSERT_EQ(all.draws.size(), 1u);
  EXPECT_EQ(all.draws[0].count, int(g.indices.size()));
  EXPECT_EQ(builder.stats().tilesDrawn, builder.stats().geometryTiles);
}

// A streamed terrain (render/terrain_stream.h): a depth map is redrawn only in a frame where the
// terrain tiles or the photographs changed (a tile arrived or was evicted, an image installed),
// never otherwise, and once everything has arrived no map is redrawn.
TEST_F(FrameBuilderTest, StreamedTerrainRedrawsDepthMapsOnlyWhenTilesChange) {
  Heightfield h;
  h.cols = h.rows = 129;
  h.originX = -100.0, h.originY = 100.0;
  h.cellX = 200.0 / 128, h.cellY = -200.0 / 128;
  h.z.resize(size_t(h.cols) * h.rows);
  for (int j = 0; j < h.rows; ++j)
    for (int i = 0; i < h.cols; ++i) h.z[size_t(j) * h.cols + i] = float(4.0 * std::sin(0.2 * i) * std::cos(0.15 * j));
  scene_.terrainTiles =
      std::make_shared<TerrainQuadtree>(std::make_shared<HeightfieldTerrainSource>(h), TerrainTileOptions{8});
  scene_.terrain = scene_.terrainTiles->mesh({TerrainQuadtree::root()});
  settings_.geometryThreads = 0;         // one tile a progressive frame, on this thread
  settings_.depthMapsPerFrame = 0;       // every dirty map at once, so a frame's redraws are its own
  settings_.geometryTolerancePx = 0.05;  // fine enough for the small view to refine a few levels
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  EXPECT_TRUE(backend_.geometry.tiles.empty() ||
              std::none_of(backend_.geometry.tiles.begin(), backend_.geometry.tiles.end(),
                           [](const GeometryTile& t) { return t.layer == kLayerTerrain; }))
      << "the streamed terrain is not in the static buffer";
  int frames = 0, redrawFrames = 0;
  for (; frames < 2000 && (frames == 0 || !builder.converged()); ++frames) {
    const auto tilesBefore = backend_.streamedTiles;
    const size_t uploadsBefore = backend_.uploads.size(), mapsBefore = backend_.depthMaps.size();
    const Frame f = builder.build(view(), FrameMode::Progressive, false);
    const bool changed = backend_.streamedTiles != tilesBefore || backend_.uploads.size() != uploadsBefore;
    if (backend_.depthMaps.size() > mapsBefore) {
      ++redrawFrames;
      EXPECT_TRUE(changed) << "frame " << f.number << " redrew a depth map with nothing new";
    }
    for (size_t m = mapsBefore; m < backend_.depthMaps.size(); ++m)
      for (std::uint64_t id : backend_.depthMaps[m].streamedTiles) EXPECT_TRUE(backend_.streamedTiles.count(id));
    for (std::uint64_t id : f.streamedTiles) EXPECT_TRUE(backend_.streamedTiles.count(id));
  }
  ASSERT_TRUE(builder.converged());
  EXPECT_GT(frames, 3);
  EXPECT_GT(redrawFrames, 1);  // the maps followed the tiles as they arrived
  EXPECT_EQ(builder.stats().terrainViewMissing, 0);
  EXPECT_EQ(builder.stats().terrainTilesPending, 0);
  EXPECT_EQ(size_t(builder.stats().terrainTilesResident), backend_.streamedTiles.size());
  EXPECT_LE(builder.stats().terrainBytes, builder.stats().terrainBudgetBytes);
  const size_t maps = backend_.depthMaps.size();
  for (int i = 0; i < 3; ++i) builder.build(view(), FrameMode::Progressive, false);
  EXPECT_EQ(backend_.depthMaps.size(), maps) << "nothing arrived: no depth map is redrawn";
  EXPECT_TRUE(diag_.ok());
}

}  // namespace
}  // namespace hv::render

namespace hv::render {
namespace {

// A layered photograph (Layered projective texture maps, 2003, §5): the builder expands it into
// its sub-images, each in a slot of its own with its peeled depth map uploaded (not drawn), packed
// consecutively with the photograph's group and weight, its window's uv offset and scale.
TEST_F(FrameBuilderTest, LayeredPhotographExpandsIntoItsSubImages) {
  FrameBuilder builder(scene_, settings_, diag_, backend_);
  const Camera& cam = scene_.photos[3].camera;  // 32 x 24
  auto layered = std::make_shared<layers::LayeredPhotograph>();
  layered->camera = cam;
  // D_1: every ray meets a surface 50 m away; D_2: nothing (+inf) but the left half at 80 m.
  for (int k = 1; k <= 2; ++k) {
    layers::PeeledDepthMap d;
    d.layer = k;
    d.width = 16;
    d.height = 12;
    for (int y = 0; y < d.height; ++y)
      for (int x = 0; x < d.width; ++x)
        d.distance.push_back(k == 1 ? 50.0f : x < 8 ? 80.0f : std::numeric_limits<float>::infinity());
    layered->depthMaps.push_back(d);
  }
  // In the file's order: layer 2 first, so the builder must sort them.
  layers::LayeredSubImage s2;
  s2.visibilityLayer = 2;
  s2.window = {{8.0, 6.0}, {28.0, 18.0}};
  s2.rgba = Image8(10, 6, 4, 255);
  layers::LayeredSubImage s1;
  s1.visibilityLayer = 1;
  s1.window = {{0.0, 0.0}, {32.0, 24.0}};
  s1.rgba = Image8(8, 6, 4, 128);
  layered->subImages = {s2, s1};
  builder.setLayeredPhotograph(3, layered);
  EXPECT_THROW(builder.setLayeredPhotograph(kPhotos, layered), std::invalid_argument);

  const Frame f = builder.build(view(), FrameMode::Batch, false);
  ASSERT_EQ(f.params.size(), size_t(kPhotos + 1));
  EXPECT_EQ(f.packedParams.size(), size_t(kPhotos + 1) * ibr::kTexelsPerImage * 4);
  // Nine photographs decoded and drawn, two sub-images uploaded with their maps.
  EXPECT_EQ(backend_.uploads.size(), size_t(kPhotos + 1));
  EXPECT_EQ(backend_.depthMaps.size(), size_t(kPhotos - 1));
  for (const DepthMapJob& job : backend_.depthMaps) EXPECT_NE(job.photo, 3);
  ASSERT_EQ(backend_.depthUploads.size(), 2u);
  EXPECT_EQ(builder.stats().depthMapsUploaded, 2);
  EXPECT_TRUE(builder.converged());
  EXPECT_EQ(builder.photoState(3), PhotoState::Ready);

  // The sub-images in the plan's place of photograph 3, consecutive, layer 1 first.
  size_t first = 0;
  while (first < f.params.size() && f.params[first].photo != 3) ++first;
  ASSERT_LT(first + 1, f.params.size());
  const double weight = f.plan.images[first].weight;  // photographs before it map one to one
  EXPECT_EQ(f.plan.images[first].photo, 3);
  const layers::LayeredSubImage* expected[2] = {&s1, &s2};
  for (size_t j = 0; j < 2; ++j) {
    const ibr::ImageParams& p = f.params[first + j];
    EXPECT_EQ(p.photo, 3);
    EXPECT_EQ(p.group, 4);
    EXPECT_EQ(p.layer, expected[j]->visibilityLayer);
    EXPECT_EQ(p.weight, weight);
    EXPECT_EQ(p.uvOffset, expected[j]->window.pxMin);
    EXPECT_DOUBLE_EQ(p.layout.uvScale.x, 1.0 / expected[j]->window.size().x);
    EXPECT_DOUBLE_EQ(p.layout.uvScale.y, 1.0 / expected[j]->window.size().y);
    EXPECT_DOUBLE_EQ(p.bias.absolute, 0.05);  // the two-sided test's tolerance
    EXPECT_DOUBLE_EQ(p.bias.relative, 2e-3);
    // The slot's map: D_k over the sub-image's frustum, depth along the axis in [0, 1].
    const NullBackend::DepthUpload* up = nullptr;
    for (const auto& u : backend_.depthUploads)
      if (u.slot == p.layout.slice) up = &u;
    ASSERT_NE(up, nullptr);
    const int n = settings_.depthSize;
    ASSERT_EQ(up->depth.size(), size_t(n) * size_t(n));
    const PinholeFrustum& fr = p.depth;
    // The frustum is the window's (no distortion: the window itself).
    EXPECT_NEAR(fr.pxMin.x, expected[j]->window.pxMin.x, 1e-9);
    EXPECT_NEAR(fr.pxMax.y, expected[j]->window.pxMax.y, 1e-9);
    for (int t : {0, 5, n / 2, n - 1}) {
      const glm::dvec2 px = fr.pxMin + (glm::dvec2(t, n - 1 - t) + 0.5) / double(n) * (fr.pxMax - fr.pxMin);
      const double x = (px.x - cam.principal.x) / cam.focal.x, y = (px.y - cam.principal.y) / cam.focal.y;
      const double distance = j == 0 ? 50.0 : px.x < 15.0 ? 80.0 : px.x > 17.0 ? -1.0 : 0.0;
      const float stored = up->depth[size_t(n - 1 - t) * size_t(n) + size_t(t)];
      if (distance < 0.0) {
        EXPECT_EQ(stored, 1.0f) << "no surface of layers >= 2 there";
      } else if (distance > 0.0) {
        const double z = distance / std::sqrt(1.0 + x * x + y * y);
        EXPECT_NEAR(stored, (z - fr.near) / (fr.far - fr.near), 1e-6) << "texel " << t << " of sub-image " << j;
      }
    }
  }

  // Without its layers the photograph is decoded and drawn again.
  builder.setLayeredPhotograph(3, nullptr);
  const Frame g = builder.build(view(), FrameMode::Batch, false);
  EXPECT_EQ(g.params.size(), size_t(kPhotos));
  for (const ibr::ImageParams& p : g.params) EXPECT_EQ(p.layer, 0);
}

}  // namespace
}  // namespace hv::render
