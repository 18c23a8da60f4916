#include "hv/layers/native/layer_export.h"

#include "hv/demo/demo_city.h"
#include "hv/io/native/scene_loader.h"
#include "hv/layers/native/openraster.h"

#include <gtest/gtest.h>

#include <unistd.h>
#include <filesystem>

namespace hv::layers {
namespace {

namespace fs = std::filesystem;

// The small demo city: 8 buildings, 6 photographs (a few seconds to generate).
class DemoLayers : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("hv_layers_test_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    demo::DemoOptions o;
    o.buildings = 8;
    o.photos = 6;
    o.views = 1;
    o.samplesPerAxis = 1;
    const demo::DemoSummary s = demo::generate(o, dir_->string());
    Diagnostics diag;
    scene_ = new Scene(loadScene(s.scenePath, diag));
  }
  static void TearDownTestSuite() {
    delete scene_;
    fs::remove_all(*dir_);
    delete dir_;
  }
  static fs::path* dir_;
  static Scene* scene_;
};
fs::path* DemoLayers::dir_ = nullptr;
Scene* DemoLayers::scene_ = nullptr;

// Rays on which a building is seen and another building lies behind it.
std::size_t buildingBehindBuilding(const LayerExport& ex) {
  std::size_t n = 0;
  const PixelHits& h = ex.hits;
  for (std::size_t p = 0; p < h.pixelCount(); ++p) {
    if (h.first[p] == h.first[p + 1]) continue;
    const std::uint32_t front = h.hits[h.first[p]].object;
    if (ex.objects.objects[front].kind != SceneObject::Kind::Building) continue;
    for (std::uint32_t i = h.first[p] + 1; i < h.first[p + 1]; ++i) {
      const std::uint32_t o = h.hits[i].object;
      if (o != front && ex.objects.objects[o].kind == SceneObject::Kind::Building) {
        ++n;
        break;
      }
    }
  }
  return n;
}

TEST_F(DemoLayers, BuildingHidingAnotherGivesAPrefilledSecondLayer) {
  ASSERT_GE(scene_->photos.size(), 2u);
  LayerExportSettings settings;
  // A quarter of the photographs' size keeps the test to a few seconds.
  settings.width = scene_->photos[0].camera.width / 4;
  settings.height = scene_->photos[0].camera.height / 4;
  // Every photograph that sees a building behind another gets at least two visibility layers;
  // the one whose layer 2 gets the most from the other photographs is looked at closer.
  std::size_t best = scene_->photos.size(), bestPrefilled = 0, seeingOneBehindAnother = 0;
  for (std::size_t i = 0; i < scene_->photos.size(); ++i) {
    LayerExportSettings s = settings;
    s.width = scene_->photos[i].camera.width / 4;
    s.height = scene_->photos[i].camera.height / 4;
    Diagnostics diag;
    const LayerExport ex = exportLayers(*scene_, i, s, diag);
    if (buildingBehindBuilding(ex) < 20) continue;
    ++seeingOneBehindAnother;
    EXPECT_GE(ex.visibility.layers.size(), 2u) << scene_->photos[i].camera.id;
    std::size_t prefilled = 0;
    for (const ImageLayerInfo& l : ex.imageLayers)
      for (std::uint32_t o : l.objects)
        if (l.visibilityLayer == 2 && ex.objects.objects[o].kind == SceneObject::Kind::Building) {
          prefilled += l.prefilledPixels;
          break;
        }
    if (prefilled > bestPrefilled) best = i, bestPrefilled = prefilled;
  }
  ASSERT_GE(seeingOneBehindAnother, 1u) << "no photograph of the demo city sees a building behind another";
  ASSERT_LT(best, scene_->photos.size()) << "no layer 2 building got anything from the other photographs";

  settings.width = scene_->photos[best].camera.width / 4;
  settings.height = scene_->photos[best].camera.height / 4;
  Diagnostics diag;
  const LayerExport ex = exportLayers(*scene_, best, settings, diag);
  EXPECT_TRUE(diag.errors.empty());
  EXPECT_GE(ex.visibility.layers.size(), 2u);
  EXPECT_GE(ex.prefillPhotos, 1);
  std::size_t prefilled2 = 0;
  for (const ImageLayerInfo& l : ex.imageLayers)
    if (l.visibilityLayer == 2) prefilled2 += l.prefilledPixels;
  EXPECT_GT(prefilled2, 0u) << "layer 2 got nothing from the other photographs";

  // Written and read back: names, order, sizes, and the pixels counted above are opaque.
  const fs::path ora = *dir_ / "layers.ora";
  writeOpenRaster(ora.string(), ex.document);
  const OraDocument doc = readOpenRaster(ora.string());
  EXPECT_EQ(doc.width, settings.width);
  EXPECT_EQ(doc.height, settings.height);
  ASSERT_EQ(doc.layers.size(), ex.document.layers.size());
  EXPECT_FALSE(doc.layers.front().visible);  // the guide
  int lastK = 0;
  std::size_t opaque2 = 0, counted2 = 0;
  std::size_t info = 0;
  for (const OraLayer& l : doc.layers) {
    if (l.name.rfind("L", 0) != 0) continue;
    const int k = std::stoi(l.name.substr(1));
    EXPECT_EQ(l.name.substr(0, std::to_string(k).size() + 2), "L" + std::to_string(k) + " ") << l.name;
    EXPECT_GE(k, lastK) << "layers out of order: " << l.name;
    lastK = k;
    ASSERT_LT(info, ex.imageLayers.size());
    const ImageLayerInfo& li = ex.imageLayers[info++];
    EXPECT_EQ(l.name, li.name);
    EXPECT_EQ(l.rgba.width, li.box.width());
    EXPECT_EQ(l.rgba.height, li.box.height());
    EXPECT_EQ(l.x, li.box.x0);
    if (k != 2) continue;
    for (int y = 0; y < l.rgba.height; ++y)
      for (int x = 0; x < l.rgba.width; ++x) opaque2 += l.rgba.at(x, y, 3) == 255;
    counted2 += li.photoPixels + li.prefilledPixels;
  }
  EXPECT_EQ(info, ex.imageLayers.size());
  EXPECT_GE(lastK, 2);
  EXPECT_EQ(opaque2, counted2);

  // Without the pre-fill the hidden parts stay transparent.
  settings.prefill = false;
  const LayerExport bare = exportLayers(*scene_, best, settings, diag);
  std::size_t bare2 = 0;
  for (const ImageLayerInfo& l : bare.imageLayers)
    if (l.visibilityLayer == 2) bare2 += l.prefilledPixels;
  EXPECT_EQ(bare2, 0u);
  EXPECT_EQ(bare.visibility.layers.size(), ex.visibility.layers.size());
}

}  // namespace
}  // namespace hv::layers
