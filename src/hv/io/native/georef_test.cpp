#include "hv/io/native/georef.h"

#include "hv/io/native/micmac_cameras.h"
#include "hv/testing/data_dir.h"
#include "hv/testing/geodesy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

namespace hv {
namespace {

using testing::ecefFromGeodetic;
using testing::kDeg;
using testing::kE;
using testing::kE2;
using testing::lcc2sp;

TEST(Georef, DescribesCrsNamesCodesAndUnits) {
  const CrsDescription l93 = describeCrs("EPSG:2154");
  EXPECT_EQ(l93.epsg, 2154);
  EXPECT_EQ(l93.type, "projected");
  EXPECT_EQ(l93.horizontalToMetre, 1.0);
  EXPECT_FALSE(l93.hasVerticalAxis());
  const CrsDescription ft = describeCrs("EPSG:2994");
  EXPECT_NEAR(ft.horizontalToMetre, 0.3048, 1e-12);
  const CrsDescription ecef = describeCrs("EPSG:4978");
  EXPECT_TRUE(ecef.geocentric);
  const CrsDescription wgs = describeCrs("EPSG:4326");
  EXPECT_TRUE(wgs.geographic);
  const CrsDescription compound = describeCrs("EPSG:2154+5720");
  EXPECT_EQ(compound.type, "compound");
  EXPECT_EQ(compound.verticalToMetre, 1.0);
  for (const auto& d : {l93, ft, ecef, wgs, compound}) std::printf("  %s\n", d.summary().c_str());
  EXPECT_THROW(describeCrs("EPSG:999999"), InputError);
  EXPECT_THROW(describeCrs("not a crs"), InputError);
}

TEST(Georef, EcefToLambert93AgainstClosedForms) {
  Diagnostics diag;
  const GeoTransform t("EPSG:4978", "EPSG:2154", diag);
  // EPSG:2154 is 2D: ECEF heights arrive as ellipsoidal heights, and the loader says so.
  ASSERT_FALSE(diag.warnings.empty());
  EXPECT_NE(diag.warnings.back().find("ellipsoidal"), std::string::npos) << diag.warnings.back();
  for (const auto& [lat, lon, h] : {std::tuple{48.8566, 2.3522, 35.0}, std::tuple{44.5, 6.8, 2500.0},
                                     std::tuple{43.3, -1.5, 0.0}, std::tuple{50.9, 2.0, 100.0}}) {
    const glm::dvec2 expected = lcc2sp(lat, lon, 49.0, 44.0, 46.5, 3.0, 700000.0, 6600000.0);
    const glm::dvec3 got = t.point(ecefFromGeodetic(lat, lon, h));
    // 1 mm: the closed forms are exact; WGS84 vs GRS80 in EPSG:4978's definition is 0.1 mm.
    EXPECT_NEAR(got.x, expected.x, 1e-3) << lat << " " << lon;
    EXPECT_NEAR(got.y, expected.y, 1e-3) << lat << " " << lon;
    EXPECT_NEAR(got.z, h, 1e-3) << lat << " " << lon;
  }
}

TEST(Georef, GeographicLonLatToEcefAgainstClosedForm) {
  Diagnostics diag;
  // EPSG:4326 is latitude first; the visualisation order makes it longitude, latitude.
  const GeoTransform t("EPSG:4979", "EPSG:4978", diag);
  const glm::dvec3 got = t.point({2.3522, 48.8566, 35.0});
  const glm::dvec3 expected = ecefFromGeodetic(48.8566, 2.3522, 35.0);
  EXPECT_LT(glm::length(got - expected), 1e-3);
  const GeoTransform t2("EPSG:4326", "EPSG:4978", diag);
  EXPECT_LT(glm::length(t2.point({2.3522, 48.8566, 0.0}) - ecefFromGeodetic(48.8566, 2.3522, 0.0)), 1e-3);
  // A geographic scene CRS is refused: degrees are no frame to render in.
  EXPECT_THROW(GeoTransform("EPSG:4978", "EPSG:4326", diag), InputError);
}

TEST(Georef, InternationalFeetBecomeMetres) {
  Diagnostics diag;
  // NAD83(HARN) geographic -> EPSG:2994 (Oregon GIC Lambert, international feet), in metres.
  const GeoTransform t("EPSG:4152", "EPSG:2994", diag);
  EXPECT_NEAR(t.scene().horizontalToMetre, 0.3048, 1e-12);
  const glm::dvec3 got = t.point({-123.07, 44.05, 130.0});
  // EPSG:2994: parallels 43 and 45.5, origin 41.75 N 120.5 W, false easting 400000 m.
  const glm::dvec2 expected = lcc2sp(44.05, -123.07, 43.0, 45.5, 41.75, -120.5, 400000.0, 0.0);
  EXPECT_NEAR(got.x, expected.x, 1e-3);
  EXPECT_NEAR(got.y, expected.y, 1e-3);
  EXPECT_NEAR(got.z, 130.0, 1e-9);  // ellipsoidal height in metres, passed through
  // A source in the same feet CRS (2D: z in its horizontal unit, as the Autzen sample): all scaled.
  const GeoTransform same("EPSG:2994", "EPSG:2994", diag);
  const glm::dvec3 p = same.point({636001.76, 848935.20, 406.26});
  EXPECT_NEAR(p.x, 636001.76 * 0.3048, 1e-6);
  EXPECT_NEAR(p.y, 848935.20 * 0.3048, 1e-6);
  EXPECT_NEAR(p.z, 406.26 * 0.3048, 1e-9);
}

TEST(Georef, CameraRotationFollowsTheLocalJacobian) {
  Diagnostics diag;
  const GeoTransform t("EPSG:4978", "EPSG:2154", diag);
  // A camera 500 m above Paris, looking north and 30 degrees down, in ECEF built from the local
  // east-north-up axes by closed forms; in Lambert-93 its axes must be east/north/up rotated by
  // the meridian convergence gamma = n (lon - lon0) (Snyder eq. 15-1 with theta).
  const double lat = 48.8566, lon = 2.3522;
  const glm::dvec3 c = ecefFromGeodetic(lat, lon, 500.0);
  const double la = lat * kDeg, lo = lon * kDeg;
  const glm::dvec3 east(-std::sin(lo), std::cos(lo), 0.0);
  const glm::dvec3 north(-std::sin(la) * std::cos(lo), -std::sin(la) * std::sin(lo), std::cos(la));
  const glm::dvec3 up(std::cos(la) * std::cos(lo), std::cos(la) * std::sin(lo), std::sin(la));
  const double tilt = 30.0 * kDeg;
  const glm::dvec3 fwd = std::cos(tilt) * north - std::sin(tilt) * up;
  const glm::dvec3 down = glm::cross(fwd, east);  // x right (east), y down, z forward
  Camera cam;
  cam.id = "c";
  cam.width = 100;
  cam.height = 100;
  cam.center = c;
  cam.camFromWorld = glm::transpose(glm::dmat3(east, down, fwd));  // rows: camera axes in world
  double defect = 0.0;
  const Camera out = t.camera(cam, &defect);
  std::printf("  non-orthogonality of the ECEF -> Lambert-93 Jacobian at Paris: %.2e\n", defect);
  EXPECT_LT(defect, 1e-3);  // Lambert-93's scale factor at 48.86 N is 1 - 3e-4
  auto m = [](double p) { return std::cos(p) / std::sqrt(1.0 - kE2 * std::sin(p) * std::sin(p)); };
  auto tt = [](double p) {
    return std::tan(M_PI / 4.0 - p / 2.0) / std::pow((1.0 - kE * std::sin(p)) / (1.0 + kE * std::sin(p)), kE / 2.0);
  };
  const double n = (std::log(m(49 * kDeg)) - std::log(m(44 * kDeg))) / (std::log(tt(49 * kDeg)) - std::log(tt(44 * kDeg)));
  const double gamma = n * (lon - 3.0) * kDeg;  // grid north is east of true north where lon < lon0
  const glm::dvec3 eastL93(std::cos(gamma), std::sin(gamma), 0.0), northL93(-std::sin(gamma), std::cos(gamma), 0.0);
  const glm::dvec3 fwdL93 = std::cos(tilt) * northL93 - std::sin(tilt) * glm::dvec3(0, 0, 1);
  const glm::dmat3 rowsOut = glm::transpose(out.camFromWorld);  // columns: camera axes in the scene frame
  EXPECT_LT(glm::length(rowsOut[0] - eastL93), 2e-5);  // scale anisotropy 3e-4 * sin(30 deg) cos ~ 1e-4 at most
  EXPECT_LT(glm::length(rowsOut[2] - fwdL93), 2e-4);
}

// ../shared/data/paris-historical-micmac: the cameras and their Verif/Appuis in Lambert-93.
TEST(Georef, MicmacCamerasInLambert93StillProjectTheirCheckPoints) {
  const std::string dir = testing::dataset("paris-historical-micmac");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("paris-historical-micmac not found under ") + testing::dataDir());
  Diagnostics diag;
  const GeoTransform toL93("EPSG:4978", "EPSG:2154", diag);
  const GeoTransform toEcef("EPSG:4978", "EPSG:4978", diag);
  for (const auto& entry : std::filesystem::directory_iterator(dir + "/Ori-Aspro")) {
    if (entry.path().filename().string().rfind("Orientation-", 0) != 0) continue;
    const MicmacOrientation o = readMicmacOrientation(entry.path().string());
    for (const GeoTransform* t : {&toEcef, &toL93}) {
      double defect = 0.0;
      const Camera cam = t->camera(o.camera, &defect);
      double maxErr = 0.0, maxDepth = 0.0;
      for (const MicmacCheckPoint& c : o.checks) {
        const Projection p = cam.project(t->point(c.world));
        maxErr = std::max(maxErr, glm::length(p.pxDistorted - c.pixel));
        maxDepth = std::max(maxDepth, p.depth);
      }
      // The identity frame keeps MicMac's tolerance. Lambert-93 is conformal but not rigid: its
      // horizontal scale k differs from the vertical scale 1 (the Jacobian's non-orthogonality
      // ~ 2|k - 1|), and straight ECEF rays bend by the Earth's curvature (sagitta d^2 / 8R over a
      // ray of length d, an angle d / 8R). Bound: f (defect + d / 8R) + Tol, d the deepest point.
      const double bound = o.camera.focal.x * (defect + maxDepth / (8.0 * 6.371e6)) + o.checkTolerance;
      std::printf("  %s in %s: non-orthogonality %.2e, Verif/Appuis max %.4f px (bound %.3f px)\n",
                  o.imageName.c_str(), t->scene().name.c_str(), defect, maxErr, bound);
      EXPECT_LE(maxErr, t == &toEcef ? o.checkTolerance : bound) << o.imageName;
    }
  }
}

}  // namespace
}  // namespace hv
