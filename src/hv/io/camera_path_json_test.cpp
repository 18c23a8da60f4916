#include "hv/io/camera_path_json.h"

#include <gtest/gtest.h>

namespace hv {
namespace {

TEST(CameraPathJson, WrittenPathReadsBackWithItsTimes) {
  std::vector<PathKey> keys;
  for (int i = 0; i < 3; ++i) {
    PathKey k;
    k.camera = lookAtCamera("k" + std::to_string(i), {651000.0 + i, 6862000.0 + 2.0 * i, 42.5},
                            {651010.0, 6862030.0, 44.0}, 320, 240, 260.0 + i);
    k.time = 0.25 + 0.4 * i;
    keys.push_back(k);
  }
  Diagnostics diag;
  const CameraPath back = parseCameraPath(cameraPathJson(keys), "recorded.json", diag);
  EXPECT_TRUE(diag.ok());
  ASSERT_EQ(back.keys().size(), keys.size());
  for (size_t i = 0; i < keys.size(); ++i) {
    const Camera& a = keys[i].camera;
    const Camera& b = back.keys()[i].camera;
    EXPECT_EQ(b.id, a.id);
    EXPECT_DOUBLE_EQ(back.keys()[i].time, keys[i].time);
    EXPECT_EQ(b.center, a.center);  // full double precision
    EXPECT_NEAR(glm::length(b.camFromWorld[2] - a.camFromWorld[2]), 0.0, 1e-12);
    EXPECT_EQ(b.focal, a.focal);
    EXPECT_EQ(b.width, a.width);
  }
}

}  // namespace
}  // namespace hv
