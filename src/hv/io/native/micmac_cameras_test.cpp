#include "hv/io/native/micmac_cameras.h"

#include "hv/io/cameras_json.h"
#include "hv/io/native/georef.h"
#include "hv/io/native/scene_loader.h"
#include "hv/testing/data_dir.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

std::string calibrationXml(const std::string& model) {
  return "<?xml version=\"1.0\" ?>\n<ExportAPERO><CalibrationInternConique>"
         "<KnownConv>eConvApero_DistM2C</KnownConv><PP>320 240</PP><F>1000</F><SzIm>640 480</SzIm>"
         "<CalibDistortion>" + model + "</CalibDistortion></CalibrationInternConique></ExportAPERO>\n";
}

// Camera -> world rows: camera x is world +y, camera y is world -x, camera z is world z.
std::string orientationXml(const std::string& interne, const std::string& centre = "10 20 30",
                           const std::string& l2 = "1 0 0") {
  return "<?xml version=\"1.0\" ?>\n<ExportAPERO><OrientationConique>"
         "<OrIntImaM2C><I00>0 0</I00><V10>1 0</V10><V01>0 1</V01></OrIntImaM2C>"
         "<TypeProj>eProjStenope</TypeProj>" + interne +
         "<Externe><KnownConv>eConvApero_DistM2C</KnownConv>" +
         (centre.empty() ? "" : "<Centre>" + centre + "</Centre>") +
         "<ParamRotation><CodageMatr><L1>0 -1 0</L1><L2>" + l2 + "</L2><L3>0 0 1</L3></CodageMatr></ParamRotation>"
         "</Externe><Verif><Tol>0.001</Tol><Appuis><Num>0</Num><Im>420 440</Im><Ter>8 21 40</Ter></Appuis></Verif>"
         "<ConvOri><KnownConv>eConvApero_DistM2C</KnownConv></ConvOri></OrientationConique></ExportAPERO>\n";
}

class MicmacTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv-micmac-" + std::to_string(::getpid()));
    fs::create_directories(dir_ / "Ori-T");
    fs::create_directories(dir_ / "img");
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& rel, const std::string& text) { std::ofstream(dir_ / rel) << text; }
  fs::path dir_;
};

TEST_F(MicmacTest, ReadsPoseIntrinsicsAndDistortionAgainstHandValues) {
  write("Ori-T/AutoCal_a.xml",
        calibrationXml("<ModRad><CDist>320 240</CDist><CoeffDist>1e-7</CoeffDist></ModRad>"));
  write("Ori-T/Orientation-a.jpg.xml", orientationXml("<FileInterne>Ori-T/AutoCal_a.xml</FileInterne>"));
  const MicmacOrientation o = readMicmacOrientation((dir_ / "Ori-T/Orientation-a.jpg.xml").string());
  EXPECT_EQ(o.imageName, "a.jpg");
  EXPECT_EQ(o.camera.id, "a");
  EXPECT_EQ(o.camera.width, 640);
  EXPECT_EQ(o.camera.height, 480);
  EXPECT_EQ(o.calibrationPath, (dir_ / "Ori-T/AutoCal_a.xml").string());
  // X - C = (-2, 1, 10) world; camera x is world +y, camera y is world -x: x_cam = (1, 2, 10).
  // Ideal MicMac pixel (320, 240) + 1000 (0.1, 0.2) = (420, 440); radial: r = (100, 200),
  // |r|^2 = 5e4, factor 1 + 1e-7 * 5e4 = 1.005: (420.5, 441); histoview pixels +0.5.
  const Projection p = o.camera.project({8.0, 21.0, 40.0});
  ASSERT_TRUE(p.inFront);
  EXPECT_NEAR(p.pxIdeal.x, 420.5, 1e-9);
  EXPECT_NEAR(p.pxIdeal.y, 440.5, 1e-9);
  EXPECT_NEAR(p.pxDistorted.x, 421.0, 1e-9);
  EXPECT_NEAR(p.pxDistorted.y, 441.5, 1e-9);
  EXPECT_NEAR(p.depth, 10.0, 1e-12);
  ASSERT_EQ(o.checks.size(), 1u);
  EXPECT_EQ(o.checks[0].pixel, glm::dvec2(420.5, 440.5));
  EXPECT_EQ(o.checkTolerance, 0.001);
}

TEST_F(MicmacTest, InlineInterneAndImageNameFromTheFileName) {
  write("Ori-T/Orientation-b.tif.xml",
        orientationXml("<Interne><PP>320 240</PP><F>1000</F><SzIm>640 480</SzIm>"
                       "<CalibDistortion><ModRad><CDist>320 240</CDist></ModRad></CalibDistortion></Interne>"));
  write("img/b.tif", "x");
  Diagnostics diag;
  const auto photos = readMicmacCameras((dir_ / "Ori-T").string(), (dir_ / "img").string(), diag);
  ASSERT_EQ(photos.size(), 1u) << (diag.errors.empty() ? "" : diag.errors[0]);
  EXPECT_TRUE(diag.ok());
  EXPECT_EQ(photos[0].imagePath, (dir_ / "img/b.tif").string());
  EXPECT_FALSE(photos[0].camera.distortion.has_value());  // CDist without coefficients: pinhole
  EXPECT_NEAR(photos[0].camera.project({8.0, 21.0, 40.0}).pxDistorted.x, 420.5, 1e-9);
}

TEST_F(MicmacTest, MalformedFilesAreReportedAndTheRestLoads) {
  const std::string fi = "<FileInterne>Ori-T/AutoCal_ok.xml</FileInterne>";
  write("Ori-T/AutoCal_ok.xml", calibrationXml("<ModRad><CDist>320 240</CDist></ModRad>"));
  write("Ori-T/AutoCal_unif.xml", calibrationXml("<ModUnif><TypeModele>eModeleEbner</TypeModele></ModUnif>"));
  write("Ori-T/Orientation-good.jpg.xml", orientationXml(fi));
  write("Ori-T/Orientation-badxml.jpg.xml", "<ExportAPERO><OrientationConique><Externe>");
  write("Ori-T/Orientation-nocentre.jpg.xml", orientationXml(fi, ""));
  write("Ori-T/Orientation-l2.jpg.xml", orientationXml(fi, "10 20 30", "1 0"));
  write("Ori-T/Orientation-unif.jpg.xml", orientationXml("<FileInterne>Ori-T/AutoCal_unif.xml</FileInterne>"));
  write("Ori-T/Orientation-nocal.jpg.xml", orientationXml("<FileInterne>Ori-T/missing.xml</FileInterne>"));
  write("Ori-T/Orientation-noimage.jpg.xml", orientationXml(fi));
  for (const char* im : {"good", "badxml", "nocentre", "l2", "unif", "nocal"})
    write(std::string("img/") + im + ".jpg", "x");

  Diagnostics diag;
  const auto photos = readMicmacCameras((dir_ / "Ori-T").string(), (dir_ / "img").string(), diag);
  ASSERT_EQ(photos.size(), 1u);
  EXPECT_EQ(photos[0].camera.id, "good");
  ASSERT_EQ(diag.errors.size(), 6u);
  auto has = [&](const std::string& file, const std::string& a, const std::string& b) {
    for (const std::string& e : diag.errors)
      if (e.find(file) != std::string::npos && e.find(a) != std::string::npos && e.find(b) != std::string::npos)
        return true;
    return false;
  };
  EXPECT_TRUE(has("Orientation-badxml.jpg.xml", "not valid XML", "offset"));
  EXPECT_TRUE(has("Orientation-nocentre.jpg.xml", "ExportAPERO/OrientationConique/Externe/Centre", "missing"));
  EXPECT_TRUE(has("Orientation-l2.jpg.xml", "CodageMatr/L2", "3 finite numbers"));
  EXPECT_TRUE(has("AutoCal_unif.xml", "CalibDistortion/ModUnif", "not supported"));
  EXPECT_TRUE(has("Orientation-nocal.jpg.xml", "FileInterne", "missing.xml"));
  EXPECT_TRUE(has("Orientation-noimage.jpg.xml", "noimage.jpg", "not found"));
  for (const std::string& e : diag.errors) std::printf("  %s\n", e.c_str());
}

TEST_F(MicmacTest, UnsupportedConventionsAreErrors) {
  auto expectError = [&](const std::string& xml, const std::string& what) {
    try {
      parseMicmacOrientation(xml, "o.xml", [](const std::string&) -> std::string { throw InputError("no file"); });
      ADD_FAILURE() << "expected an error about " << what;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  const std::string inl = "<Interne><PP>1 1</PP><F>10</F><SzIm>2 2</SzIm></Interne>";
  std::string xml = orientationXml(inl);
  expectError(std::string(xml).replace(xml.find("<ConvOri><KnownConv>eConvApero_DistM2C"), 35,
                                       "<ConvOri><KnownConv>eConvOriLib"),
              "ConvOri/KnownConv: eConvOriLib");
  expectError(std::string(xml).replace(xml.find("<V10>1 0"), 8, "<V10>2 0"), "OrIntImaM2C");
  expectError(std::string(xml).replace(xml.find("eProjStenope"), 12, "eProjOrthographique"), "TypeProj");
  expectError(orientationXml(inl, "1 2 3", "0 0 1"), "rotation");  // two equal rows: not orthonormal
  EXPECT_NO_THROW(parseMicmacOrientation(xml, "o.xml", {}));  // inline Interne: no file to read
}

TEST_F(MicmacTest, SceneJsonGeoreferencesAndConvertsToNativeCameras) {
  write("Ori-T/AutoCal_a.xml",
        calibrationXml("<ModRad><CDist>320 240</CDist><CoeffDist>1e-8</CoeffDist></ModRad>"));
  // About 44.5 N 6.8 E, 2 km up, in ECEF.
  write("Ori-T/Orientation-a.jpg.xml",
        orientationXml("<FileInterne>Ori-T/AutoCal_a.xml</FileInterne>", "4524741.5855 536647.3997 4450385.28"));
  write("img/a.jpg", "x");
  write("scene.json", R"({"crs": "EPSG:2154", "cameras": {"format": "micmac", "orientations": "Ori-T/", "images": "img/"}})");
  write("scene-ecef.json", R"({"cameras": {"format": "micmac", "orientations": "Ori-T", "images": "img"}})");
  Diagnostics diag;
  const Scene scene = loadScene((dir_ / "scene.json").string(), diag);
  ASSERT_EQ(scene.photos.size(), 1u) << (diag.errors.empty() ? "" : diag.errors[0]);
  EXPECT_TRUE(diag.ok());
  ASSERT_EQ(scene.sourceCrs.size(), 1u);
  EXPECT_EQ(scene.sourceCrs[0].crs, "EPSG:4978");
  const Camera& cam = scene.photos[0].camera;
  // Lambert-93 easting/northing of a point near 44.5 N 6.8 E: around (1 000 km, 6 370 km).
  EXPECT_GT(cam.center.x, 900000.0);
  EXPECT_LT(cam.center.x, 1100000.0);
  EXPECT_GT(cam.center.y, 6300000.0);
  EXPECT_LT(cam.center.y, 6450000.0);

  // cameras convert: native file, reloaded equal to 1e-9.
  const std::string out = (dir_ / "converted.json").string();
  std::ofstream(out) << cameraJson(scene.photos, dir_.string());
  const auto back = readCameraFile(out, CameraFileOptions{}, diag);
  ASSERT_EQ(back.size(), 1u);
  const Camera& b = back[0].camera;
  EXPECT_EQ(back[0].imagePath, (dir_ / "img/a.jpg").string());
  EXPECT_LE(glm::length(b.center - cam.center), 1e-9 * glm::length(cam.center));
  for (int c = 0; c < 3; ++c) EXPECT_LE(glm::length(b.camFromWorld[c] - cam.camFromWorld[c]), 1e-9);
  EXPECT_EQ(b.focal, cam.focal);
  EXPECT_EQ(b.principal, cam.principal);
  const glm::dvec3 x = cam.center + 300.0 * cam.rayDirection({100.0, 400.0});
  EXPECT_LE(glm::length(b.project(x).pxDistorted - cam.project(x).pxDistorted), 1e-9);

  // Without a scene CRS the frame is the cameras' own (ECEF), with the local vertical as up.
  Diagnostics d2;
  const Scene ecef = loadScene((dir_ / "scene-ecef.json").string(), d2);
  ASSERT_EQ(ecef.photos.size(), 1u);
  EXPECT_EQ(ecef.crs, "EPSG:4978");
  EXPECT_NEAR(glm::length(ecef.photos[0].camera.center - glm::dvec3(4524741.5855, 536647.3997, 4450385.28)), 0.0,
              1e-6);
  EXPECT_NEAR(glm::dot(ecef.up, ecefUp(ecef.photos[0].camera.center)), 1.0, 1e-12);
  EXPECT_GT(glm::dot(ecef.up, glm::normalize(ecef.photos[0].camera.center)), 0.99);
}

// ../shared/data/paris-historical-micmac: MicMac's own check points and the ground control points.
TEST(MicmacRealData, VerifAppuisAndGroundControlPoints) {
  const std::string dir = testing::dataset("paris-historical-micmac");
  if (dir.empty()) HV_SKIP_WITHOUT_DATA(std::string("paris-historical-micmac not found under ") + testing::dataDir());
  Diagnostics diag;
  const auto photos = readMicmacCameras(dir + "/Ori-Aspro", dir, diag);
  EXPECT_TRUE(diag.ok()) << diag.errors.front();
  EXPECT_EQ(photos.size(), 3u);

  for (const auto& entry : fs::directory_iterator(dir + "/Ori-Aspro")) {
    if (entry.path().filename().string().rfind("Orientation-", 0) != 0) continue;
    const MicmacOrientation o = readMicmacOrientation(entry.path().string());
    ASSERT_GT(o.checks.size(), 0u);
    ASSERT_GT(o.checkTolerance, 0.0);
    double maxErr = 0.0, sumErr = 0.0;
    for (const MicmacCheckPoint& c : o.checks) {
      const Projection p = o.camera.project(c.world);
      EXPECT_TRUE(p.inFront);
      const double e = glm::length(p.pxDistorted - c.pixel);
      maxErr = std::max(maxErr, e);
      sumErr += e;
      EXPECT_LE(e, o.checkTolerance) << o.imageName << " Verif/Appuis " << c.num;
    }
    std::printf("%s: Verif/Appuis %zu points, max %.2e px, mean %.2e px (Tol %.3g)\n", o.imageName.c_str(),
                o.checks.size(), maxErr, sumErr / double(o.checks.size()), o.checkTolerance);
  }

  // Ground control points (gcp_*.xml, appuis_*.xml) measured by hand on the historical images;
  // the bundle adjustment fits them in the least-squares sense, so their residuals are the
  // measurement noise of a hand-picked landmark on an old photograph: tens of pixels here. A
  // wrong convention is far outside: with the rotation read the other way round, the Verif points
  // of these images land 800 to 11000 px off (or behind the camera). Bound: 100 px for each point
  // (3.5 % of the image diagonal, ~1.5 times the largest residual seen: 74 px), and the mean
  // residual vector below 5 px (a least-squares fit leaves them centred: 0.7 and 1.0 px measured;
  // an origin shift of half a pixel moves PP and the measures alike, so it cannot show here).
  for (const char* name : {"FRAN_0207_0648_L", "FRAN_0207_3299_L"}) {
    const auto gcp = readMicmacGroundPoints(dir + "/gcp_" + name + ".xml");
    const auto measures = readMicmacImageMeasures(dir + "/appuis_" + name + ".xml");
    const MicmacOrientation o = readMicmacOrientation(dir + "/Ori-Aspro/Orientation-" + name + ".jpg.xml");
    ASSERT_TRUE(measures.count(o.imageName));
    double maxErr = 0.0, sumSq = 0.0;
    glm::dvec2 mean(0.0);
    int n = 0;
    for (const auto& [pt, px] : measures.at(o.imageName)) {
      ASSERT_TRUE(gcp.count(pt)) << pt;
      const Projection p = o.camera.project(gcp.at(pt));
      EXPECT_TRUE(p.inImage) << name << " GCP " << pt;
      const glm::dvec2 d = p.pxDistorted - px;
      maxErr = std::max(maxErr, glm::length(d));
      sumSq += glm::dot(d, d);
      mean += d;
      ++n;
      EXPECT_LT(glm::length(d), 100.0) << name << " GCP " << pt;
    }
    mean /= double(n);
    std::printf("%s: %d GCPs, max %.1f px, RMS %.1f px, mean residual (%.1f, %.1f) px\n", name, n, maxErr,
                std::sqrt(sumSq / n), mean.x, mean.y);
    EXPECT_LT(glm::length(mean), 5.0) << name;
  }
}

}  // namespace
}  // namespace hv
