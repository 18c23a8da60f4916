#include "hv/layers/native/layer_export.h"

#include "hv/demo/demo_city.h"
#include "hv/image/native/png_write.h"
#include "hv/io/native/scene_loader.h"
#include "hv/layers/native/layer_import.h"
#include "hv/layers/native/openraster.h"
#include "hv/scene/native/raycast.h"
#include "hv/testing/hidden_facade.h"

#include <gtest/gtest.h>
#include <zip.h>
#include <nlohmann/json.hpp>
#include <pugixml.hpp>

#include <algorithm>
#include <fstream>
#include <iostream>
#include <map>

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

  // With every layer shown, the photograph: each pixel's first surface is in the layer that holds
  // it, and no shallower layer has anything on that ray (its objects would be behind a deeper one).
  {
    const Photo& photo = scene_->photos[best];
    Image8 rgb = readImage(photo.imagePath, 3);
    rgb = resizeImage(rgb, settings.width, settings.height);
    Image8 mask;
    if (!photo.maskPath.empty()) mask = resizeImage(readImage(photo.maskPath, 1), settings.width, settings.height);
    const Image8 merged = compositeLayers(ex.document);
    std::size_t differ = 0, compared = 0;
    for (int y = 0; y < settings.height; ++y)
      for (int x = 0; x < settings.width; ++x) {
        if (!mask.empty() && mask.at(x, y, 0) < 128) continue;
        ++compared;
        const std::uint8_t* m = merged.px(x, y);
        const std::uint8_t* r = rgb.px(x, y);
        differ += m[3] != 255 || m[0] != r[0] || m[1] != r[1] || m[2] != r[2];
      }
    EXPECT_GT(compared, std::size_t(settings.width) * std::size_t(settings.height) / 2);
    EXPECT_EQ(differ, 0u) << "of " << compared << " pixels";
  }

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

// Paints every pixel of the first "L2 " layer of an .ora with `colour`, as an artist would: the
// archive edited in place with a zip library, the layer's PNG decoded, painted, encoded.
std::string paintFirstLayer2(const fs::path& ora, glm::u8vec4 colour) {
  int err = 0;
  zip_t* z = zip_open(ora.c_str(), 0, &err);
  EXPECT_NE(z, nullptr);
  if (!z) return "";
  auto read = [&](const std::string& name) {
    zip_stat_t st;
    zip_stat(z, name.c_str(), 0, &st);
    std::vector<std::uint8_t> b(st.size);
    zip_file_t* f = zip_fopen(z, name.c_str(), 0);
    zip_fread(f, b.data(), st.size);
    zip_fclose(f);
    return b;
  };
  const std::vector<std::uint8_t> xml = read("stack.xml");
  pugi::xml_document d;
  d.load_buffer(xml.data(), xml.size());
  std::string name, src;
  for (pugi::xml_node l : d.child("image").child("stack").children("layer"))
    if (std::string(l.attribute("name").value()).rfind("L2 ", 0) == 0) {
      name = l.attribute("name").value();
      src = l.attribute("src").value();
      break;
    }
  EXPECT_FALSE(src.empty()) << "no L2 layer";
  if (src.empty()) {
    zip_discard(z);
    return "";
  }
  const std::vector<std::uint8_t> png = read(src);
  Image8 img = decodeImage(png.data(), png.size(), src, 4);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      for (int c = 0; c < 4; ++c) img.at(x, y, c) = colour[c];
  static std::vector<std::uint8_t> painted;  // zip_close reads it
  painted = encodePng(img, src);
  zip_source_t* s = zip_source_buffer(z, painted.data(), painted.size(), 0);
  EXPECT_EQ(zip_file_replace(z, zip_uint64_t(zip_name_locate(z, src.c_str(), 0)), s, 0), 0);
  EXPECT_EQ(zip_close(z), 0);
  return name;
}

TEST_F(DemoLayers, RoundTripThroughAnEditAndSceneJson) {
  // A photograph with at least two visibility layers.
  std::size_t photo = scene_->photos.size();
  LayerExport ex;
  LayerExportSettings settings;
  for (std::size_t i = 0; i < scene_->photos.size() && photo == scene_->photos.size(); ++i) {
    settings.width = scene_->photos[i].camera.width / 4;
    settings.height = scene_->photos[i].camera.height / 4;
    settings.prefill = false;
    Diagnostics diag;
    ex = exportLayers(*scene_, i, settings, diag);
    if (ex.visibility.layers.size() >= 2) photo = i;
  }
  ASSERT_LT(photo, scene_->photos.size());
  const Camera& camera = scene_->photos[photo].camera;
  const fs::path sceneDir = fs::path(scene_->path).parent_path();
  const fs::path ora = sceneDir / "edited.ora";
  writeOpenRaster(ora.string(), ex.document);
  const glm::u8vec4 magenta(255, 0, 255, 255);
  const std::string painted = paintFirstLayer2(ora, magenta);
  ASSERT_FALSE(painted.empty());

  // scene.json names it; a second entry names no photograph.
  nlohmann::json doc;
  std::ifstream(scene_->path) >> doc;
  doc["layers"] = {{camera.id, "edited.ora"}, {"no-such-camera", "edited.ora"}};
  std::ofstream(sceneDir / "scene-layers.json") << doc.dump(2);
  Diagnostics diag;
  const Scene scene = loadScene((sceneDir / "scene-layers.json").string(), diag);
  const std::map<std::string, std::string> files = readLayerFiles(scene, diag);
  ASSERT_EQ(files.size(), 1u);
  ASSERT_EQ(files.count(camera.id), 1u);
  EXPECT_EQ(fs::path(files.at(camera.id)), fs::path(ora).lexically_normal());
  bool named = false;
  for (const std::string& e : diag.errors) named |= e.find("layers: 'no-such-camera'") != std::string::npos;
  EXPECT_TRUE(named) << "the entry naming no photograph is not reported";

  const ImportedLayers in = importLayers(files.at(camera.id), camera);
  ASSERT_EQ(in.subImages.size(), ex.imageLayers.size());
  EXPECT_EQ(in.skipped, int(ex.document.layers.size() - ex.imageLayers.size()));  // guide, background
  const double s = double(camera.width) / settings.width;
  bool found = false;
  for (std::size_t i = 0; i < in.subImages.size(); ++i) {
    const ImportedSubImage& sub = in.subImages[i];
    const ImageLayerInfo& info = ex.imageLayers[i];
    EXPECT_EQ(sub.visibilityLayer, info.visibilityLayer);
    EXPECT_EQ(sub.name, info.name);
    EXPECT_DOUBLE_EQ(sub.window.pxMin.x, info.box.x0 * s);
    EXPECT_DOUBLE_EQ(sub.window.pxMax.y, info.box.y1 * s);
    if (sub.name == painted) {
      found = true;
      for (int y = 0; y < sub.rgba.height; ++y)
        for (int x = 0; x < sub.rgba.width; ++x)
          ASSERT_EQ(glm::u8vec4(sub.rgba.at(x, y, 0), sub.rgba.at(x, y, 1), sub.rgba.at(x, y, 2), sub.rgba.at(x, y, 3)),
                    magenta);
    } else {
      // Not edited: as exported.
      EXPECT_EQ(sub.rgba.data, ex.document.layers[i + 1].rgba.data) << sub.name;
    }
  }
  EXPECT_TRUE(found);
  // Another size of the photograph's aspect ratio reads; another aspect ratio is refused.
  Camera other = camera;
  other.height = camera.height * 2;
  EXPECT_THROW(importLayers(ora.string(), other), InputError);
}

// The paper's use (§5): an artist paints a façade hidden in the photograph into its layer 2; seen
// from another viewpoint, the façade shows the painting, and the building in front of it (layer 1,
// the photograph) never does.
TEST_F(DemoLayers, PaintedHiddenFacadeShowsFromAnotherViewpointNeverOnItsOccluder) {
  // A photograph where a building (layer 1) hides another (layer 2) on the most rays, and the
  // image layer holding the hidden one.
  std::optional<testing::HiddenFacade> found = testing::findHiddenFacade(*scene_);
  ASSERT_TRUE(found) << "no photograph of the demo city sees a building behind another";
  testing::HiddenFacade& f = *found;
  ASSERT_GE(f.rays, 20u);
  const std::size_t photo = f.photo;
  const std::uint32_t occluder = f.occluder, hidden = f.hidden;
  const LayerExport& ex = f.ex;
  const LayerExportSettings& settings = f.settings;
  const Camera& camera = scene_->photos[photo].camera;

  // The artist paints the hidden building where the guide outlines it (its layer-2 pixels), in a
  // colour no photograph of the demo has.
  ASSERT_GT(testing::paintHiddenFacade(f, glm::u8vec4(255, 0, 255, 255)), 20);
  const fs::path sceneDir = fs::path(scene_->path).parent_path();
  const fs::path ora = sceneDir / "painted.ora";
  writeOpenRaster(ora.string(), ex.document);

  // Read back through scene.json, as the renderer's scene would.
  nlohmann::json doc;
  std::ifstream(scene_->path) >> doc;
  doc["layers"] = {{camera.id, "painted.ora"}};
  std::ofstream(sceneDir / "scene-painted.json") << doc.dump(2);
  Diagnostics diag;
  const Scene scene = loadScene((sceneDir / "scene-painted.json").string(), diag);
  const std::map<std::string, std::string> files = readLayerFiles(scene, diag);
  ASSERT_EQ(files.count(camera.id), 1u);
  const ImportedLayers in = importLayers(files.at(camera.id), camera);
  const LayeredPhotograph layered = layeredPhotograph(scene, photo, in, settings, diag);
  EXPECT_TRUE(diag.errors.empty()) << diag.errors.front();
  ASSERT_EQ(layered.depthMaps.size(), ex.visibility.layers.size());
  ASSERT_EQ(layered.subImages.size(), ex.imageLayers.size());

  // Another viewpoint that sees the hidden façade and the occluder's face in front of it.
  const RayCaster caster(ex.objects.geometry);
  const auto isMagenta = [](const glm::dvec4& t) { return t.a > 0.99 && t.r > 0.99 && t.g < 0.01 && t.b > 0.99; };
  const testing::FacadeViewpoint viewpoint = testing::facadeViewpoint(f, caster);
  ASSERT_FALSE(viewpoint.hiddenPoints.empty());
  ASSERT_GT(viewpoint.seen, 0u) << "no viewpoint around sees both the hidden façade and its occluder";
  const std::vector<glm::dvec3>& frontPoints = viewpoint.frontPoints;

  // Where the occluder stands in front of the painted façade, the photograph (layer 1) textures it.
  std::size_t frontPhotograph = 0, frontMagenta = 0;
  for (const glm::dvec3& y : frontPoints) {
    const std::optional<glm::dvec4> t = layeredTexel(layered, y);
    frontPhotograph += t.has_value() && !isMagenta(*t);
    frontMagenta += t.has_value() && isMagenta(*t);
  }
  EXPECT_EQ(frontMagenta, 0u);
  EXPECT_GE(frontPhotograph, frontPoints.size() * 9 / 10) << "of " << frontPoints.size();
  // The occluder's far walls, on the same rays between its front and the painted façade (seen from
  // behind it, from a viewpoint beyond the hidden building): in front of layer 2's surface, so
  // they get nothing of the painting either (the depth test is two-sided). Rays one texel or more
  // inside the painted region: at its border the test reads the texels of the next surface too (the
  // ground the far wall stands on, on the bottom row), where the wall's foot does lie on it.
  std::size_t backPoints = 0, backMagenta = 0;
  for (const auto& [wall, facade] : testing::occluderFarWalls(f, caster)) {
    ++backPoints;
    const std::optional<glm::dvec4> c = layeredTexel(layered, wall);
    backMagenta += c.has_value() && isMagenta(*c);
  }
  EXPECT_GE(backPoints, 20u);
  EXPECT_EQ(backMagenta, 0u) << "of " << backPoints << " points on the occluder's far walls";

  // The view, cast against the scene's objects: what the layered photograph gives on each pixel
  // of the two buildings.
  const Camera view = lookAtCamera("view", viewpoint.centre, viewpoint.centroid, 200, 150, 150.0);
  std::size_t paintedSeen = 0, occluderSeen = 0, occluderTextured = 0, occluderMagenta = 0, hiddenElse = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const std::optional<glm::dvec3> ray = pixelRay(view, x, y);
      if (!ray) continue;
      const std::optional<RayHit> hit = caster.intersect(view.center, *ray);
      if (!hit) continue;
      const std::uint32_t object = ex.objects.objectOfTriangle[hit->triangle];
      if (object != hidden && object != occluder) continue;
      const std::optional<glm::dvec4> t = layeredTexel(layered, hit->position);
      if (object == occluder) {
        ++occluderSeen;
        if (t) ++occluderTextured;
        if (t && isMagenta(*t)) ++occluderMagenta;
      } else if (t && isMagenta(*t)) {
        ++paintedSeen;
      } else if (t) {
        ++hiddenElse;  // the parts of it the photograph sees, in its layer-2 window unpainted
      }
    }
  EXPECT_GE(paintedSeen, 20u) << "the painting does not show on the hidden building";
  EXPECT_GE(occluderTextured, 20u) << "the occluder is not textured by the photograph's layer 1";
  EXPECT_EQ(occluderMagenta, 0u) << "the painting shows on the occluder (" << occluderSeen << " pixels seen)";
  std::cout << "[ layered  ] " << camera.id << ": painted hidden façade seen at " << paintedSeen
            << " view pixels, occluder at " << occluderSeen << " (" << occluderTextured
            << " textured by layer 1, none magenta); other texels on the hidden building " << hiddenElse << "\n";

  // The whole blend (hv::ibr::referenceBlend's layered images) is checked in LayeredBlend.*.
  // A sub-image of a layer the geometry does not have is reported, naming the file and the layer.
  ImportedLayers deeper = in;
  deeper.subImages.push_back(in.subImages.back());
  deeper.subImages.back().visibilityLayer = 99;
  deeper.subImages.back().name = "L99 nothing";
  Diagnostics d2;
  EXPECT_EQ(layeredPhotograph(scene, photo, deeper, settings, d2).subImages.size(), in.subImages.size());
  ASSERT_EQ(d2.errors.size(), 1u);
  EXPECT_NE(d2.errors[0].find("painted.ora: layer 'L99 nothing'"), std::string::npos) << d2.errors[0];
}

TEST(LayerTextureMemory, PowerOfTwoSubImagesAgainstWholeLayers) {
  // 640x480 -> 1024 x 512 per whole layer; two layers. Sub-images 100x50 (128 x 64) and 300x200
  // (512 x 256) in layer 1, 60x60 (64 x 64) in layer 2.
  const LayerTextureMemory m = layerTextureMemory({1, 1, 2}, {{100, 50}, {300, 200}, {60, 60}}, 640, 480);
  EXPECT_EQ(m.visibilityLayers, 2);
  EXPECT_EQ(m.subImages, 3);
  EXPECT_EQ(m.subImageTexels, 128 * 64 + 512 * 256 + 64 * 64);
  EXPECT_EQ(m.wholeImageTexels, 2 * 1024 * 512);
}

}  // namespace
}  // namespace hv::layers
