#include "hv/io/cameras_json.h"

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

namespace hv {
namespace {

const char* kGood = R"({"id": "good", "width": 640, "height": 480, "center": [651000.5, 6862000.25, 40],
  "rotation": [1, 0, 0, 0, 0, -1, 0, 1, 0], "focal": [500, 500], "principal": [320, 240], "skew": 0,
  "distortion": {"type": "radial", "center": [321, 241], "c3": 1e-7, "c5": 0, "c7": 0, "r2max": 1e6},
  "image": "img/good.jpg", "mask": "m.png", "date": "1905-06-01"})";

std::vector<Photo> parse(const std::string& cams, Diagnostics& diag) {
  CameraFileOptions opt;
  opt.checkImageFiles = false;
  return parseCameraJson("{\"cameras\": [" + cams + "]}", "cams.json", "/data", opt, diag);
}

TEST(CameraJson, ReadsEveryField) {
  Diagnostics diag;
  const auto photos = parse(kGood, diag);
  ASSERT_EQ(photos.size(), 1u);
  EXPECT_TRUE(diag.ok());
  const Camera& c = photos[0].camera;
  EXPECT_EQ(c.id, "good");
  EXPECT_EQ(c.center, glm::dvec3(651000.5, 6862000.25, 40.0));
  EXPECT_EQ(c.camFromWorld[1][2], 1.0);  // row 2, column 1
  EXPECT_EQ(c.camFromWorld[2][1], -1.0);
  ASSERT_TRUE(c.distortion.has_value());
  EXPECT_EQ(c.distortion->c3, 1e-7);
  EXPECT_EQ(photos[0].imagePath, "/data/img/good.jpg");
  EXPECT_EQ(photos[0].maskPath, "/data/m.png");
  EXPECT_EQ(photos[0].date, "1905-06-01");
}

TEST(CameraJson, BadCamerasAreSkippedWithNamedErrors) {
  struct Case {
    std::string json, field;
  };
  const std::string base = R"("width": 64, "height": 48, "center": [0, 0, 0], "principal": [32, 24], "image": "a.png")";
  const std::vector<Case> cases = {
      {R"({"id": "nofocal", )" + base + R"(, "rotation": [1,0,0,0,1,0,0,0,1]})", "focal"},
      {R"({"id": "negfocal", )" + base + R"(, "rotation": [1,0,0,0,1,0,0,0,1], "focal": [-5, 5]})", "focal"},
      {R"({"id": "shortrot", )" + base + R"(, "rotation": [1,0,0,0,1,0,0,0], "focal": [5, 5]})", "rotation"},
      {R"({"id": "skewed", )" + base + R"(, "rotation": [1,0.1,0,0,1,0,0,0,1], "focal": [5, 5]})", "rotation"},
      {R"({"id": "nullnum", )" + base + R"(, "rotation": [1,0,0,0,1,0,0,0,null], "focal": [5, 5]})", "rotation"},
      {R"({"id": "noimage", "width": 64, "height": 48, "center": [0, 0, 0], "principal": [32, 24],
          "rotation": [1,0,0,0,1,0,0,0,1], "focal": [5, 5]})", "image"},
  };
  for (const auto& c : cases) {
    Diagnostics diag;
    const auto photos = parse(std::string(kGood) + "," + c.json, diag);
    EXPECT_EQ(photos.size(), 1u) << c.json;  // the good one still loads
    ASSERT_EQ(diag.errors.size(), 1u) << c.json;
    const std::string& m = diag.errors[0];
    EXPECT_NE(m.find("cams.json"), std::string::npos) << m;
    EXPECT_NE(m.find(c.field), std::string::npos) << m;
    const std::string id = c.json.substr(8, c.json.find('"', 8) - 8);
    EXPECT_NE(m.find(id), std::string::npos) << m;
  }
}

TEST(CameraJson, MissingImageFileIsAnError) {
  Diagnostics diag;
  CameraFileOptions opt;  // checks files
  const auto photos = parseCameraJson(std::string("{\"cameras\": [") + kGood + "]}", "cams.json", "/nonexistent",
                                      opt, diag);
  EXPECT_TRUE(photos.empty());
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("image"), std::string::npos);
  EXPECT_NE(diag.errors[0].find("good"), std::string::npos);
}

TEST(CameraJson, BrokenDocumentsThrowNamingTheFile) {
  Diagnostics diag;
  CameraFileOptions opt;
  EXPECT_THROW(parseCameraJson("{not json", "x.json", ".", opt, diag), InputError);
  EXPECT_THROW(parseCameraJson("{\"cams\": []}", "x.json", ".", opt, diag), InputError);
  EXPECT_THROW(readCameraFile("/nonexistent/cameras.json", opt, diag), InputError);
}

TEST(CameraJson, WritesWhatItReads) {
  Diagnostics diag;
  const auto photos = parse(kGood, diag);
  const std::string text = cameraJson(photos, "/data");
  const auto again = parse(text.substr(text.find('[') + 1, text.rfind(']') - text.find('[') - 1), diag);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(again[0].camera.center, photos[0].camera.center);
  EXPECT_EQ(again[0].camera.focal, photos[0].camera.focal);
  EXPECT_EQ(again[0].imagePath, photos[0].imagePath);
}

TEST(CameraJson, EveryLensModelSurvivesARoundTrip) {
  const std::string base = R"("width": 640, "height": 480, "center": [1, 2, 3], "rotation": [1, 0, 0, 0, 1, 0, 0, 0, 1],
    "focal": [500, 490], "principal": [320, 240], "image": "a.png", )";
  Diagnostics diag;
  const auto photos = parse(
      "{\"id\": \"cv\", " + base +
          R"("distortion": {"type": "opencv", "k1": -0.1, "k2": 0.02, "p1": 0.001, "p2": -0.002, "k3": 0.003}}, )" +
          "{\"id\": \"fe\", " + base +
          R"("distortion": {"type": "fisheye", "center": [322, 239], "focal": 300, "c3": -0.01, "l1": 1e-4, "l2": -2e-4}}, )" +
          "{\"id\": \"bad\", " + base + R"("distortion": {"type": "fisheye", "center": [322, 239]}})",
      diag);
  ASSERT_EQ(photos.size(), 2u);
  ASSERT_EQ(diag.errors.size(), 1u);  // the fish-eye without its focal
  EXPECT_NE(diag.errors[0].find("distortion.focal"), std::string::npos) << diag.errors[0];
  const LensDistortion& cv = *photos[0].camera.distortion;
  EXPECT_EQ(cv.scale, glm::dvec2(500, 490));  // OpenCV normalises by the camera's focal
  EXPECT_EQ(cv.center, glm::dvec2(320, 240));
  EXPECT_EQ(cv.p2, -0.002);
  EXPECT_EQ(photos[1].camera.distortion->model, LensDistortion::Model::Fisheye);
  const std::string text = cameraJson(photos, "/data");
  const auto again = parse(text.substr(text.find('[') + 1, text.rfind(']') - text.find('[') - 1), diag);
  ASSERT_EQ(again.size(), 2u);
  for (size_t i = 0; i < 2; ++i)
    for (glm::dvec2 p : {glm::dvec2(10, 20), glm::dvec2(600, 400)}) {
      const glm::dvec2 a = photos[i].camera.distort(p), b = again[i].camera.distort(p);
      EXPECT_NEAR(a.x, b.x, 1e-9);
      EXPECT_NEAR(a.y, b.y, 1e-9);
    }
}

// A camera as kGood but with `id` and the fields in `extra` (replacing or adding keys).
std::string camera(const std::string& id, const std::string& extra = "") {
  return R"({"id": ")" + id + R"(", "width": 64, "height": 48, "center": [0, 0, 0], "rotation": [1,0,0,0,1,0,0,0,1],
    "focal": [50, 50], "principal": [32, 24], "image": "a.png")" + (extra.empty() ? "" : ", " + extra) + "}";
}

std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += l + "\n";
  return out;
}

TEST(CameraJson, ANonFiniteLiteralSkipsOnlyItsCamera) {
  // Python's json.dump writes float('nan') and float('inf') as bare NaN and Infinity.
  Diagnostics diag;
  const auto photos = parse(camera("a") + "," + camera("nan", R"("skew": NaN)") + "," +
                                camera("inf", R"("center": [Infinity, 0, -Infinity])") + "," + camera("b"),
                            diag);
  ASSERT_EQ(photos.size(), 2u) << joined(diag.errors);
  EXPECT_EQ(photos[0].camera.id, "a");
  EXPECT_EQ(photos[1].camera.id, "b");
  ASSERT_EQ(diag.errors.size(), 2u) << joined(diag.errors);
  EXPECT_NE(diag.errors[0].find("camera 'nan': skew"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[0].find("NaN"), std::string::npos) << diag.errors[0];
  EXPECT_NE(diag.errors[1].find("camera 'inf': center"), std::string::npos) << diag.errors[1];
  EXPECT_NE(diag.errors[1].find("Infinity"), std::string::npos) << diag.errors[1];
  // Inside a string the words are text: an id "NaN" is an id.
  Diagnostics quoted;
  EXPECT_EQ(parse(camera("NaN"), quoted).at(0).camera.id, "NaN");
}

TEST(CameraJson, MisspeltKeysAreWarnedWithTheNearestKnownOne) {
  Diagnostics diag;
  const auto photos = parse(camera("a", R"("distorsion": {"type": "radial", "center": [32, 24], "c3": 1e-7},
                                          "masque": "m.png", "colour": 1)") +
                                "," + camera("b", R"("distortion": {"type": "opencv", "k_1": 0.1})"),
                            diag);
  ASSERT_EQ(photos.size(), 2u);
  EXPECT_TRUE(diag.ok());
  const std::string all = joined(diag.warnings);
  ASSERT_EQ(diag.warnings.size(), 4u) << all;
  EXPECT_NE(all.find("cams.json: camera 'a': unknown key 'distorsion' (did you mean 'distortion'?)"), std::string::npos)
      << all;
  EXPECT_NE(all.find("unknown key 'masque' (did you mean 'mask'?)"), std::string::npos) << all;
  EXPECT_NE(all.find("unknown key 'colour' (ignored)"), std::string::npos) << all;
  EXPECT_NE(all.find("camera 'b': distortion: unknown key 'k_1' (did you mean 'k1'?)"), std::string::npos) << all;
}

TEST(CameraJson, ADateThatIsNotAnIsoDateIsWarnedAndLeftOut) {
  Diagnostics diag;
  const auto photos =
      parse(camera("num", R"("date": 1905)") + "," + camera("text", R"("date": "June 1905")") + "," +
                camera("ok", R"("date": "1905-06")"),
            diag);
  ASSERT_EQ(photos.size(), 3u);
  ASSERT_EQ(diag.warnings.size(), 2u) << joined(diag.warnings);
  EXPECT_NE(diag.warnings[0].find("camera 'num': date: expected an ISO 8601 date string"), std::string::npos)
      << diag.warnings[0];
  EXPECT_NE(diag.warnings[1].find("camera 'text': date"), std::string::npos) << diag.warnings[1];
  EXPECT_EQ(photos[0].date, "");
  EXPECT_EQ(photos[1].date, "");
  EXPECT_EQ(photos[2].date, "1905-06");
}

TEST(CameraJson, DuplicateKeysAreNamedWithTheCamera) {
  Diagnostics diag;
  const auto photos =
      parse(camera("a", R"("skew": 0, "skew": 1, "distortion": {"type": "radial", "center": [32, 24], "c3": 0, "c3": 1e-9})"),
            diag);
  ASSERT_EQ(photos.size(), 1u);
  EXPECT_EQ(photos[0].camera.skew, 1.0);  // nlohmann keeps the last
  const std::string all = joined(diag.warnings);
  ASSERT_EQ(diag.warnings.size(), 2u) << all;
  EXPECT_NE(all.find("cams.json: id 'a': duplicate key 'skew'"), std::string::npos) << all;
  EXPECT_NE(all.find("cams.json: id 'a': duplicate key 'distortion.c3'"), std::string::npos) << all;
}

TEST(CameraJson, DuplicateIdsKeepTheFirstCamera) {
  Diagnostics diag;
  const auto photos = parse(camera("a") + "," + camera("a", R"("skew": 2)") + "," + camera("b"), diag);
  ASSERT_EQ(photos.size(), 2u);
  EXPECT_EQ(photos[0].camera.skew, 0.0);
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("camera 'a': duplicate id"), std::string::npos) << diag.errors[0];
}

TEST(CameraJson, NulBytesInPathsAndNonStringMasksAreRefused) {
  Diagnostics diag;
  const auto photos = parse(camera("nul", R"("image": "a.png\u0000.jpg")") + "," +
                                camera("masknum", R"("mask": 3)") + "," + camera("ok"),
                            diag);
  ASSERT_EQ(photos.size(), 1u);
  ASSERT_EQ(diag.errors.size(), 2u);
  EXPECT_NE(diag.errors[0].find("camera 'nul': image: the path contains a NUL byte"), std::string::npos)
      << diag.errors[0];
  EXPECT_NE(diag.errors[1].find("camera 'masknum': mask"), std::string::npos) << diag.errors[1];
}

TEST(CameraJson, AFifoOrDeviceAsCamerasFileIsRefusedAtOnce) {
  Diagnostics diag;
  CameraFileOptions opt;
  const auto fifo =
      std::filesystem::temp_directory_path() / ("hv-cameras-fifo-" + std::to_string(::getpid()) + ".json");
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  for (const std::string& p : {fifo.string(), std::string("/dev/zero")}) {
    try {
      readCameraFile(p, opt, diag);
      ADD_FAILURE() << p;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
  std::filesystem::remove(fifo);
}

TEST(CameraJson, AbsurdLensCoefficientsAreWarned) {
  // c3 = 1 per pixel^2 moves the corner (32, 24 px from the centre) by 40^3 = 64000 pixels: a
  // coefficient of a normalised model typed into the pixel polynomial. A real lens's c3 is ~1e-8.
  Diagnostics diag;
  const auto photos =
      parse(camera("absurd", R"("distortion": {"type": "radial", "center": [32, 24], "c3": 1})") + "," +
                camera("real", R"("distortion": {"type": "radial", "center": [32, 24], "c3": 1e-5})"),
            diag);
  ASSERT_EQ(photos.size(), 2u);
  ASSERT_EQ(diag.warnings.size(), 1u) << joined(diag.warnings);
  EXPECT_NE(diag.warnings[0].find("camera 'absurd': distortion: moves a corner"), std::string::npos)
      << diag.warnings[0];
}

TEST(CameraJson, WritingAPathInALoopOfLinksDoesNotThrow) {
  const auto dir = std::filesystem::temp_directory_path() / ("hv-cameras-loop-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::filesystem::create_symlink(dir / "b", dir / "a");
  std::filesystem::create_symlink(dir / "a", dir / "b");
  Diagnostics diag;
  std::vector<Photo> photos = parse(camera("a"), diag);
  ASSERT_EQ(photos.size(), 1u);
  photos[0].imagePath = (dir / "a" / "photo.jpg").string();
  std::string text;
  ASSERT_NO_THROW(text = cameraJson(photos, dir.string()));
  EXPECT_NE(text.find("a/photo.jpg"), std::string::npos) << text;
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace hv
