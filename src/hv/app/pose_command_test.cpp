// `histoview pose` on real data: MicMac's historical Paris photographs posed from MicMac's own
// ground control points, against MicMac's orientation of them.
#include "hv/app/pose_command.h"

#include "hv/io/native/micmac_cameras.h"
#include "hv/pose/pose.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

namespace hv::app {
namespace {

double angleDegrees(const glm::dmat3& a, const glm::dmat3& b) {
  const glm::dmat3 d = a * glm::transpose(b);
  return std::acos(std::clamp((d[0][0] + d[1][1] + d[2][2] - 1.0) / 2.0, -1.0, 1.0)) * 180.0 / M_PI;
}

double rmsResidual(const Camera& c, const std::vector<pose::ControlPoint>& pts) {
  double ss = 0.0;
  for (const auto& p : pts) {
    const glm::dvec2 d = c.project(p.world).pxDistorted - p.pixel;
    ss += glm::dot(d, d);
  }
  return std::sqrt(ss / double(pts.size()));
}

TEST(PoseRealData, MicmacGroundControlPointsGiveMicmacsOrientation) {
  const std::string dir = testing::dataset("paris-historical-micmac");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("paris-historical-micmac not found under ") + testing::dataDir());
  for (const char* name : {"FRAN_0207_0648_L", "FRAN_0207_3299_L"}) {
    const MicmacOrientation o = readMicmacOrientation(dir + "/Ori-Aspro/Orientation-" + name + ".jpg.xml");
    const auto pts = readControlPoints(dir + "/gcp_" + name + ".xml", dir + "/appuis_" + name + ".xml", o.imageName);
    ASSERT_GE(pts.size(), 5u) << name;
    // A first guess far from MicMac's: 50 m and 3 degrees away, the focal 5 % off.
    Camera start = o.camera;
    start.center += glm::dvec3(30.0, -30.0, 30.0);
    const double t = 3.0 * M_PI / 180.0;
    const glm::dmat3 rz(std::cos(t), std::sin(t), 0.0, -std::sin(t), std::cos(t), 0.0, 0.0, 0.0, 1.0);
    start.camFromWorld = rz * o.camera.camFromWorld;
    start.focal *= 1.05;
    // MicMac's bundle kept its calibration's focal: so does this comparison (with the focal free,
    // 5 to 7 points this far away trade the focal for the distance; docs/pose.md gives figures).
    start.focal = o.camera.focal;
    pose::PoseOptions options;
    options.refine = pose::parseRefine("none");
    options.inlierPixels = 150.0;  // hand-picked landmarks on old prints: residuals of tens of pixels
    const pose::PoseResult r = pose::solvePose(pts, start, true, options);
    const double dc = glm::length(r.camera.center - o.camera.center);
    const double da = angleDegrees(r.camera.camFromWorld, o.camera.camFromWorld);
    const double df = r.camera.focal.x / o.camera.focal.x - 1.0;
    std::printf("%s: %d of %zu inliers, RMS %.1f px (MicMac's orientation: %.1f px); centre %.2f m from MicMac's "
                "(1 sigma %.2f m), rotation %.3f deg, focal %+.2f %%\n",
                name, r.inlierCount, pts.size(), r.rmsPixels, rmsResidual(o.camera, pts), dc, glm::length(r.centerSigma), da,
                100.0 * df);
    EXPECT_EQ(r.inlierCount, int(pts.size())) << name;
    // Least squares on the same points with the same model: at most MicMac's residual (its
    // bundle also fits other constraints), and a camera within the uncertainty the points allow.
    EXPECT_LE(r.rmsPixels, rmsResidual(o.camera, pts) + 0.05) << name;
    EXPECT_LT(dc, 3.0 * glm::length(r.centerSigma) + 1.0) << name;
    // Measured: 1.85 m and 0.02 m, 0.018 and 0.004 degrees, the same RMS as MicMac's to 0.1 px.
    EXPECT_LT(dc, 5.0) << name;
    EXPECT_LT(da, 0.05) << name;
    // Without a first pose (three-point samples from MicMac's intrinsics alone): the same camera.
    const pose::PoseResult blind = pose::solvePose(pts, start, false, options);
    EXPECT_LT(glm::length(blind.camera.center - r.camera.center), 0.5) << name;
    EXPECT_LT(angleDegrees(blind.camera.camFromWorld, r.camera.camFromWorld), 0.01) << name;
  }
}

}  // namespace
}  // namespace hv::app
