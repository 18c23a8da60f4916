// Layered projective texture maps (2003, §5) in the GL renderer, against the CPU reference
// (hv::ibr::referenceBlend with BlendOptions::layered, hv::layers::layeredTexel): the demo
// photograph where a building hides another, its hidden building painted in the layer-2 sub-image,
// rendered from a viewpoint turned around the hidden façade (docs/layers.md, "Rendering in the GL
// renderer").
#include "hv/ibr/reference_blend.h"
#include "hv/image/native/png_write.h"
#include "hv/layers/native/layer_export.h"
#include "hv/layers/native/layer_import.h"
#include "hv/layers/native/openraster.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/scene/native/raycast.h"
#include "hv/testing/hidden_facade.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>

namespace hv::render {
namespace {

namespace fs = std::filesystem;
using layers::LayerExport;

bool magentaPixel(const std::uint8_t* c) { return c[3] > 0 && c[0] > 240 && c[1] < 15 && c[2] > 240; }

TEST(LayeredRendering, PaintedHiddenFacadeMatchesTheCpuReference) {
  testing::glContext();
  const std::string dir = testing::makeTempDir("layers-gl");
  demo::DemoOptions o;
  o.buildings = 8;
  o.photos = 6;
  o.views = 1;
  o.samplesPerAxis = 1;
  const demo::DemoSummary summary = demo::generate(o, dir);
  Diagnostics loadDiag;
  const Scene scene = loadScene(summary.scenePath, loadDiag);

  // The photograph where a building (layer 1) hides another (layer 2) on the most rays, and the
  // image layer holding the hidden one (as DemoLayers.PaintedHiddenFacade... finds it).
  std::optional<testing::HiddenFacade> found = testing::findHiddenFacade(scene);
  ASSERT_TRUE(found) << "no photograph of the demo city sees a building behind another";
  testing::HiddenFacade& f = *found;
  const std::size_t photo = f.photo;
  const std::uint32_t occluder = f.occluder, hidden = f.hidden;
  const LayerExport& ex = f.ex;
  const Camera& camera = scene.photos[photo].camera;

  // The artist paints the hidden building's layer-2 pixels magenta (no photograph of the demo has
  // it), in the document the file is written from; the file is then read back as the renderer's
  // caller would.
  ASSERT_GT(testing::paintHiddenFacade(f, glm::u8vec4(255, 0, 255, 255)), 20);
  const fs::path ora = fs::path(dir) / "painted.ora";
  layers::writeOpenRaster(ora.string(), ex.document);
  Diagnostics diag;
  const layers::ImportedLayers in = layers::importLayers(ora.string(), camera);
  const auto layered =
      std::make_shared<layers::LayeredPhotograph>(layers::layeredPhotograph(scene, photo, in, f.settings, diag));
  ASSERT_TRUE(diag.errors.empty()) << diag.errors.front();
  ASSERT_GE(layered->depthMaps.size(), 2u);

  // The viewpoint: the photograph's centre turned about the vertical around the hidden façade's
  // points the occluder hides, raised, looking at their centroid; the one that sees most of both.
  const RayCaster caster(ex.objects.geometry);
  const testing::FacadeViewpoint viewpoint = testing::facadeViewpoint(f, caster);
  ASSERT_FALSE(viewpoint.hiddenPoints.empty());
  ASSERT_GT(viewpoint.seen, 0u);
  const Camera view = lookAtCamera("view", viewpoint.centre, viewpoint.centroid, 200, 150, 150.0);

  // GL: the layered photograph alone (the others excluded), hard edges (no feathering), as the
  // CPU reference below blends it.
  RenderSettings rs;
  for (std::size_t i = 0; i < scene.photos.size(); ++i)
    if (i != photo) rs.blend.exclude.push_back(scene.photos[i].camera.id);
  rs.blend.featherPx = 0.0;
  Diagnostics renderDiag;
  Renderer renderer(scene, rs, renderDiag);
  renderer.setLayeredPhotograph(int(photo), layered);
  const RenderOutput out = renderer.render(view);
  EXPECT_TRUE(renderDiag.ok());
  const std::vector<ibr::ImageParams>& params = renderer.lastImageParams();
  ASSERT_EQ(params.size(), layered->subImages.size()) << "the photograph expands into its sub-images";
  for (const ibr::ImageParams& p : params) {
    EXPECT_EQ(p.photo, int(photo));
    EXPECT_EQ(p.group, int(photo) + 1);
    EXPECT_GE(p.layer, 1);
  }
  EXPECT_EQ(renderer.stats().depthMapsUploaded, int(layered->subImages.size()));
  EXPECT_EQ(renderer.stats().depthMapsRendered, 0) << "a sub-image's peeled depth map is uploaded, not drawn";

  // CPU: referenceBlend with the photograph as one layered image, at each view pixel's ray cast.
  ibr::ImageParams whole =
      ibr::makeImageParams(camera, scene.origin, {0, glm::dvec2(1.0) / glm::dvec2(camera.width, camera.height)}, 1.0,
                           idealRectCoveringImage(camera, 1.0), {});
  whole.photo = int(photo);
  ibr::BlendOptions opt;
  opt.layered.push_back(
      [&](const glm::dvec3& pointRender) { return layers::layeredTexel(*layered, pointRender + scene.origin); });
  const ibr::TextureLookup noTexture = [](int, glm::dvec2) { return glm::dvec4(0.0); };

  std::size_t compared = 0, coverageDiffers = 0, colourDiffers = 0;
  std::size_t glMagentaHidden = 0, cpuMagentaHidden = 0, glMagentaOccluder = 0, occluderSeen = 0;
  double maxDiff = 0.0, sumSq = 0.0;
  std::size_t sqCount = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) {
      const glm::dvec2 px(x + 0.5, y + 0.5);
      const std::optional<RayHit> hit = caster.intersect(view.center, view.rayDirection(px));
      if (!hit) continue;
      const std::uint32_t object = ex.objects.objectOfTriangle[hit->triangle];
      const std::uint8_t* g = out.rgba.px(x, y);
      if (object == occluder) {
        ++occluderSeen;
        glMagentaOccluder += magentaPixel(g);
      }
      const ibr::BlendResult ref = ibr::referenceBlend(hit->position - scene.origin, {whole}, ibr::BlendMethod::Blend,
                                                       noTexture, nullptr, ibr::Selection::Global, 1, opt);
      const bool cpuMagenta = ref.covered() && ref.color.r > 0.95 && ref.color.g < 0.05 && ref.color.b > 0.95;
      if (object == hidden) {
        glMagentaHidden += magentaPixel(g);
        cpuMagentaHidden += cpuMagenta;
      }
      // Compared away from the view's depth edges (all four neighbours on the same plane): there a
      // view pixel's ray cast and the GL depth pass may land on different surfaces.
      bool flat = true;
      for (glm::dvec2 off : {glm::dvec2(1.5, 0), glm::dvec2(-1.5, 0), glm::dvec2(0, 1.5), glm::dvec2(0, -1.5)}) {
        const auto h2 = caster.intersect(view.center, view.rayDirection(px + off));
        if (!h2 || glm::dot(h2->normal, hit->normal) < 0.999 ||
            std::abs(glm::dot(h2->position - hit->position, hit->normal)) > 1e-3)
          flat = false;
      }
      if (!flat) continue;
      ++compared;
      if ((g[3] > 0) != ref.covered()) {
        ++coverageDiffers;
        continue;
      }
      if (!ref.covered()) continue;
      double diff = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double d = g[c] / 255.0 - ref.color[c];
        diff = std::max(diff, std::abs(d));
        sumSq += d * d;
      }
      ++sqCount;
      maxDiff = std::max(maxDiff, diff);
      colourDiffers += diff > 8.0 / 255.0;
    }
  const double psnr = sqCount > 0 && sumSq > 0.0 ? 10.0 * std::log10(1.0 / (sumSq / (3.0 * double(sqCount)))) : 99.0;
  std::cout << "[ layered GL ] " << camera.id << ": " << layered->subImages.size() << " sub-images; painted façade "
            << glMagentaHidden << " GL pixels (CPU " << cpuMagentaHidden << "), occluder " << occluderSeen
            << " pixels, " << glMagentaOccluder << " magenta; " << compared << " pixels compared: coverage differs at "
            << coverageDiffers << ", colour > 8/255 at " << colourDiffers << " of " << sqCount << ", PSNR " << psnr
            << " dB, max " << maxDiff * 255.0 << "/255\n";
  EXPECT_GE(glMagentaHidden, 20u) << "the painting does not show on the hidden building";
  EXPECT_GE(double(glMagentaHidden), 0.9 * double(cpuMagentaHidden));
  EXPECT_LE(double(glMagentaHidden), 1.1 * double(cpuMagentaHidden) + 5.0);
  EXPECT_GE(occluderSeen, 100u);
  EXPECT_EQ(glMagentaOccluder, 0u) << "the painting shows on the occluder";
  ASSERT_GT(compared, 1000u);
  EXPECT_LE(coverageDiffers, compared / 50) << "coverage differs on more than 2 % of the compared pixels";
  EXPECT_LE(colourDiffers, sqCount / 50) << "colour differs by more than 8/255 on more than 2 % of the pixels";
  EXPECT_GE(psnr, 30.0);

  // The occluder's far walls, between it and the painted façade, on rays one texel or more inside
  // the painted region: in front of D_2, so the painting never lands there (the test is
  // two-sided; a one-sided test paints them). Seen from halfway between such a wall and the
  // façade behind it, looking at the wall.
  const std::vector<std::pair<glm::dvec3, glm::dvec3>> farWalls = testing::occluderFarWalls(f, caster);
  ASSERT_GE(farWalls.size(), 20u);
  const auto& [wall, facade] = farWalls[farWalls.size() / 2];
  const Camera between =
      lookAtCamera("between", 0.5 * (wall + facade) + glm::dvec3(0.0, 0.0, 1.0), wall, 200, 150, 150.0);
  const RenderOutput back = renderer.render(between);
  std::size_t wallSeen = 0, wallMagenta = 0;
  for (int y = 0; y < between.height; ++y)
    for (int x = 0; x < between.width; ++x) {
      const std::optional<RayHit> hit =
          caster.intersect(between.center, between.rayDirection(glm::dvec2(x + 0.5, y + 0.5)));
      if (!hit || ex.objects.objectOfTriangle[hit->triangle] != occluder) continue;
      ++wallSeen;
      wallMagenta += magentaPixel(back.rgba.px(x, y));
    }
  std::cout << "[ layered GL ] from between the buildings: occluder's far wall at " << wallSeen << " pixels, "
            << wallMagenta << " magenta\n";
  EXPECT_GE(wallSeen, 100u);
  EXPECT_EQ(wallMagenta, 0u) << "the painting shows on the occluder's far wall";

  // The same photograph without its layers: no magenta anywhere (the renderer goes back to it).
  renderer.setLayeredPhotograph(int(photo), nullptr);
  const RenderOutput plain = renderer.render(view);
  std::size_t plainMagenta = 0;
  for (int y = 0; y < view.height; ++y)
    for (int x = 0; x < view.width; ++x) plainMagenta += magentaPixel(plain.rgba.px(x, y));
  EXPECT_EQ(plainMagenta, 0u);
  // HV_LAYERS_FIGURE=file.png: the view without the layers (left) and with them (right), the
  // picture of docs/layers.md.
  if (const char* figure = std::getenv("HV_LAYERS_FIGURE")) {
    Image8 pair(2 * view.width, view.height, 3);
    for (int y = 0; y < view.height; ++y)
      for (int x = 0; x < view.width; ++x)
        for (int c = 0; c < 3; ++c) {
          pair.at(x, y, c) = plain.rgba.px(x, y)[c];
          pair.at(view.width + x, y, c) = out.rgba.px(x, y)[c];
        }
    writePng(figure, pair);
  }
  EXPECT_EQ(renderer.lastImageParams().size(), 1u);
  EXPECT_EQ(renderer.lastImageParams()[0].layer, 0);
}

}  // namespace
}  // namespace hv::render
