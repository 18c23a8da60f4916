// Leave-one-out evaluation on real photographs (../shared/data/sceaux: 10 photographs of the
// Château de Sceaux with their cameras and an OpenMVS mesh): each photograph rendered from the
// other nine and scored against itself.
#include "hv/eval/evaluate.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/testing/gl_test_support.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>

#include <iostream>

namespace hv::eval {
namespace {

TEST(LeaveOneOutGlTest, BlendBeatsNearestOnSceaux) {
  const std::string dir = hv::testing::dataset("sceaux");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("no sceaux/ in ") + hv::testing::dataDir() + " (set HISTOVIEW_DATA)");
  hv::testing::glContext();
  Diagnostics diag;
  const Scene scene = loadScene(dir + "/scene.json", diag);
  ASSERT_TRUE(diag.ok());
  ASSERT_EQ(scene.photos.size(), 10u);
  ASSERT_EQ(scene.mesh.triangles.size(), 174899u);  // the OpenMVS mesh (data README)
  render::RenderSettings s;
  s.maxSliceSize = 1024;  // 2832 x 2128 photographs scaled into 1024 x 769 slices: fast, and enough here
  render::Renderer renderer(scene, s, diag);
  EvalOptions opt;
  opt.leaveOneOut = true;
  opt.size = {354, 266};  // an eighth of the photographs' size
  opt.methods = {Method::Blend, Method::Nearest, Method::NoOcclusion};
  const EvalReport report = evaluate(renderer, scene.photos, opt, diag);
  std::cout << formatTable(report);
  EXPECT_TRUE(diag.ok());
  ASSERT_EQ(report.rows.size(), 30u);
  const auto mean = meanPsnr(report);
  EXPECT_GT(mean.at("blend"), mean.at("nearest"));
}

}  // namespace
}  // namespace hv::eval
