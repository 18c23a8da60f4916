#include "hv/camera/camera_path.h"
#include "hv/io/camera_path_json.h"

#include "hv/io/cameras_json.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>

namespace hv {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Rotation by `deg` about the z axis (as a world -> camera matrix; only its algebra matters here).
glm::dmat3 rotZ(double deg) {
  const double a = deg * kPi / 180.0, c = std::cos(a), s = std::sin(a);
  const double r[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
  return mat3FromRowMajor(r);
}

// A level camera looking along the horizontal direction `headingDeg` (0 = +y), z up.
glm::dmat3 heading(double headingDeg) {
  const double a = headingDeg * kPi / 180.0;
  const glm::dvec3 z(std::sin(a), std::cos(a), 0.0);
  const glm::dvec3 x = glm::normalize(glm::cross(z, glm::dvec3(0, 0, 1)));
  const glm::dvec3 y = glm::cross(z, x);
  return glm::transpose(glm::dmat3(x, y, z));
}

double maxAbsDiff(const glm::dmat3& a, const glm::dmat3& b) {
  double m = 0.0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) m = std::max(m, std::abs(a[c][r] - b[c][r]));
  return m;
}

PathKey key(const std::string& id, double t, glm::dvec3 center, glm::dmat3 rotation = glm::dmat3(1.0)) {
  PathKey k;
  k.time = t;
  k.camera.id = id;
  k.camera.width = 64;
  k.camera.height = 48;
  k.camera.center = center;
  k.camera.camFromWorld = rotation;
  k.camera.focal = {50.0, 50.0};
  k.camera.principal = {32.0, 24.0};
  return k;
}

TEST(CameraPath, SplinePassesThroughTheKeys) {
  // Uneven times and a curved, non-planar course.
  const CameraPath path({key("a", 0.0, {0, 0, 0}, heading(0)), key("b", 0.7, {3, 1, 0.5}, heading(30)),
                         key("c", 2.0, {5, 4, 0.2}, heading(80)), key("d", 2.5, {4, 8, 1.0}, heading(150))});
  for (const auto& k : path.keys()) {
    const Camera c = path.at(k.time);
    EXPECT_LT(glm::length(c.center - k.camera.center), 1e-12) << k.camera.id;
    EXPECT_LT(maxAbsDiff(c.camFromWorld, k.camera.camFromWorld), 1e-12) << k.camera.id;
  }
  // Between keys it leaves the chords (a curve, not a polyline).
  const glm::dvec3 mid = path.position(1.35);
  const glm::dvec3 chordMid = 0.5 * (glm::dvec3(3, 1, 0.5) + glm::dvec3(5, 4, 0.2));
  EXPECT_GT(glm::length(mid - chordMid), 1e-3);
  // Outside the keys' times, the ends.
  EXPECT_EQ(path.position(-1.0), glm::dvec3(0, 0, 0));
  EXPECT_EQ(path.position(9.0), glm::dvec3(4, 8, 1.0));
}

TEST(CameraPath, EvenlySpacedKeysOnALineAreTravelledAtConstantVelocity) {
  // 2 m per second along a slanted line, keys 1 s apart; the duplicated end points keep the end
  // segments at the same velocity as the inner ones.
  const glm::dvec3 p0(10, -4, 2), v(1.2, 1.6, 0.0);  // |v| = 2
  std::vector<PathKey> keys;
  for (int i = 0; i < 5; ++i) keys.push_back(key("k" + std::to_string(i), i, p0 + double(i) * v));
  const CameraPath path(keys);
  const double h = 1e-4;
  for (double t = 0.0; t <= 4.0 - h; t += 0.05) {
    EXPECT_LT(glm::length(path.position(t) - (p0 + t * v)), 1e-12) << t;
    const glm::dvec3 vel = (path.position(t + h) - path.position(t)) / h;
    EXPECT_LT(glm::length(vel - v), 1e-8) << t;
  }
}

TEST(CameraPath, VelocityIsContinuousAtKeysWithUnevenTimes) {
  // Time-parametrised tangents: the Hermite segments meet with one velocity (C1 in time).
  const CameraPath path({key("a", 0.0, {0, 0, 0}), key("b", 0.5, {2, 1, 0}), key("c", 2.0, {3, 5, 1}),
                         key("d", 2.3, {7, 6, 1})});
  const double h = 1e-6;
  for (double t : {0.5, 2.0}) {
    const glm::dvec3 before = (path.position(t) - path.position(t - h)) / h;
    const glm::dvec3 after = (path.position(t + h) - path.position(t)) / h;
    EXPECT_LT(glm::length(before - after), 1e-4 * glm::length(after)) << t;
  }
}

TEST(CameraPath, SlerpHalfwayBetweenRotations90DegreesApartIsThe45DegreeRotation) {
  EXPECT_LT(maxAbsDiff(slerpRotation(glm::dmat3(1.0), rotZ(90), 0.5), rotZ(45)), 1e-12);
  EXPECT_LT(maxAbsDiff(slerpRotation(rotZ(10), rotZ(100), 0.5), rotZ(55)), 1e-12);
  EXPECT_LT(maxAbsDiff(slerpRotation(glm::dmat3(1.0), rotZ(90), 0.25), rotZ(22.5)), 1e-12);
  // Constant angular velocity: a third of the way is a third of the angle.
  EXPECT_LT(maxAbsDiff(slerpRotation(rotZ(0), rotZ(90), 1.0 / 3.0), rotZ(30)), 1e-12);
}

TEST(CameraPath, SlerpTakesTheShorterArc) {
  // 170 deg to -170 deg: 20 deg apart through 180, not 340 deg through 0.
  EXPECT_LT(maxAbsDiff(slerpRotation(rotZ(170), rotZ(-170), 0.5), rotZ(180)), 1e-12);
  EXPECT_LT(maxAbsDiff(slerpRotation(rotZ(-170), rotZ(170), 0.25), rotZ(-175)), 1e-12);
}

TEST(CameraPath, InterpolatedRotationsStayOrthonormal) {
  const CameraPath path({key("a", 0.0, {0, 0, 0}, heading(0)),
                         key("b", 1.0, {1, 0, 0}, heading(175) * rotZ(33)),
                         key("c", 2.0, {2, 1, 0}, rotZ(-120) * heading(-60)),
                         key("d", 3.0, {3, 1, 0}, rotZ(-120) * heading(-60) * rotZ(1e-9))});
  for (double t = 0.0; t <= 3.0; t += 0.01) {
    const glm::dmat3 r = path.at(t).camFromWorld;
    EXPECT_LT(maxAbsDiff(r * glm::transpose(r), glm::dmat3(1.0)), 1e-13) << t;
    EXPECT_NEAR(glm::determinant(r), 1.0, 1e-13) << t;
  }
}

TEST(CameraPath, IntrinsicsAreLinearAndDistortionComesFromTheEarlierKey) {
  PathKey a = key("a", 0.0, {0, 0, 0}), b = key("b", 2.0, {1, 0, 0});
  a.camera.focal = {40, 42};
  b.camera.focal = {60, 58};
  b.camera.principal = {30, 26};
  LensDistortion d;
  d.c3 = 1e-6;
  b.camera.distortion = d;
  const CameraPath path({a, b});
  const Camera mid = path.at(0.5);
  EXPECT_NEAR(mid.focal.x, 45.0, 1e-12);
  EXPECT_NEAR(mid.focal.y, 46.0, 1e-12);
  EXPECT_NEAR(mid.principal.x, 31.5, 1e-12);
  EXPECT_NEAR(mid.principal.y, 24.5, 1e-12);
  EXPECT_FALSE(mid.distortion.has_value());
  EXPECT_TRUE(path.at(2.0).distortion.has_value());  // the last key itself
}

TEST(CameraPath, FrameCountIsFloorOfDurationTimesFpsPlusOne) {
  auto twoKeys = [](double t0, double t1) {
    return CameraPath({key("a", t0, {0, 0, 0}), key("b", t1, {1, 0, 0})});
  };
  EXPECT_EQ(pathFrameCount(twoKeys(0.0, 2.0), 25), 51);  // floor(50) + 1: both ends
  EXPECT_EQ(pathFrameCount(twoKeys(0.0, 2.5), 25), 63);  // floor(62.5) + 1
  EXPECT_EQ(pathFrameCount(twoKeys(1.5, 3.7), 7), 16);   // floor(15.4) + 1
  EXPECT_EQ(pathFrameCount(twoKeys(0.0, 0.3), 10), 4);   // 0.3 * 10 = 2.9999999999999996 in doubles
  EXPECT_EQ(pathFrameCount(CameraPath({key("a", 4.0, {0, 0, 0})}), 25), 1);
  EXPECT_THROW(pathFrameCount(twoKeys(0.0, 1.0), 0.0), std::invalid_argument);

  const CameraPath path = twoKeys(1.5, 3.7);
  const auto frames = pathFrames(path, 7);
  ASSERT_EQ(frames.size(), 16u);
  EXPECT_EQ(frames[0].id, "f00000");
  EXPECT_EQ(frames[15].id, "f00015");
  EXPECT_EQ(frames[0].center, path.position(1.5));
  EXPECT_LT(glm::length(frames[7].center - path.position(1.5 + 7.0 / 7.0)), 1e-12);
  EXPECT_EQ(frameId(123456), "f123456");
}

TEST(CameraPath, LongPathsAreMadeOneFrameAtATime) {
  // 10 hours at 25 fps: 900,001 frames, none built until asked for (building them all up front
  // took seconds and a camera's worth of memory per frame before the first was rendered).
  const CameraPath path({key("a", 0.0, {0, 0, 0}), key("b", 36000.0, {1000, 0, 0})});
  const auto t0 = std::chrono::steady_clock::now();
  const PathFrames frames(path, 25.0);
  ASSERT_EQ(frames.size(), 900001);
  const Camera mid = frames[450000];
  const Camera last = frames[900000];
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 0.05);
  EXPECT_EQ(mid.id, "f450000");
  EXPECT_LT(glm::length(mid.center - path.position(18000.0)), 1e-9);
  EXPECT_EQ(last.center, path.position(36000.0));
  // The same cameras as the eager list.
  const CameraPath shortPath({key("a", 1.5, {0, 0, 0}), key("b", 3.7, {1, 0, 0})});
  const auto eager = pathFrames(shortPath, 7);
  const PathFrames lazy(shortPath, 7);
  ASSERT_EQ(size_t(lazy.size()), eager.size());
  for (int i = 0; i < lazy.size(); ++i) EXPECT_EQ(lazy[i].center, eager[size_t(i)].center);
}

TEST(CameraPath, AbsurdFrameCountsAreRefusedNamingTheLimit) {
  // 10^7 frames (a `t` typed in milliseconds, or --fps 25000): refused before anything is built.
  const CameraPath path({key("a", 0.0, {0, 0, 0}), key("b", 400000.0, {1, 0, 0})});
  try {
    PathFrames frames(path, 25.0);
    FAIL() << "a path of 10^7 frames was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(std::to_string(kMaxPathFrames)), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--fps"), std::string::npos) << e.what();
  }
  EXPECT_THROW(pathFrameCount(path, 1e300), std::invalid_argument);
  EXPECT_EQ(pathFrameCount(CameraPath({key("a", 0.0, {0, 0, 0}), key("b", 39999.0, {1, 0, 0})}), 25.0),
            999976);  // just under the limit
}

// A PATH.json: cameras.json cameras with an optional t.
nlohmann::json camJson(const std::string& id, double x, const nlohmann::json& t = nullptr) {
  nlohmann::json j = {{"id", id},
                      {"width", 64},
                      {"height", 48},
                      {"center", {x, 0.0, 2.0}},
                      {"rotation", {1, 0, 0, 0, 0, -1, 0, 1, 0}},
                      {"focal", {50, 50}},
                      {"principal", {32, 24}}};
  if (!t.is_null()) j["t"] = t;
  return j;
}

TEST(CameraPathFile, ReadsTimesAndSpacesMissingOnes1sApart) {
  const nlohmann::json doc = {
      {"cameras", {camJson("a", 0), camJson("b", 1), camJson("c", 2, 5.0), camJson("d", 3)}}};
  Diagnostics diag;
  const CameraPath path = parseCameraPath(doc.dump(), "path.json", diag);
  ASSERT_EQ(path.keys().size(), 4u);
  EXPECT_EQ(path.keys()[0].time, 0.0);
  EXPECT_EQ(path.keys()[1].time, 1.0);
  EXPECT_EQ(path.keys()[2].time, 5.0);
  EXPECT_EQ(path.keys()[3].time, 6.0);
  EXPECT_EQ(path.keys()[2].camera.id, "c");
  EXPECT_TRUE(diag.ok());
}

TEST(CameraPathFile, RejectsWhatIsNotAPath) {
  Diagnostics diag;
  auto parse = [&](const nlohmann::json& cams) {
    return parseCameraPath(nlohmann::json{{"cameras", cams}}.dump(), "p.json", diag);
  };
  auto message = [&](const nlohmann::json& cams) {
    try {
      parse(cams);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(message(nlohmann::json::array()).find("at least one key"), std::string::npos);
  EXPECT_NE(message({camJson("a", 0, 1.0), camJson("b", 1, 1.0)}).find("camera 'b': t:"), std::string::npos);
  EXPECT_EQ(parse({camJson("a", 0, 2.0), camJson("b", 1)}).keys()[1].time, 3.0);  // 1 s after a given t
  EXPECT_NE(message({camJson("a", 0, 2.0), camJson("b", 1, 1.5)}).find("camera 'b': t:"), std::string::npos);
  EXPECT_NE(message({camJson("a", 0), camJson("b", 1, "soon")}).find("camera 'b': t: expected a number"),
            std::string::npos);
  nlohmann::json bad = camJson("b", 1);
  bad["focal"] = {-1, 50};
  EXPECT_NE(message({camJson("a", 0), bad}).find("every key camera"), std::string::npos);
  nlohmann::json big = camJson("b", 1);
  big["width"] = 128;
  big["principal"] = {64, 24};
  EXPECT_NE(message({camJson("a", 0), big}).find("camera 'b': width, height"), std::string::npos);
}

}  // namespace
}  // namespace hv
