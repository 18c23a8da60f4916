// The glTF vehicle models (hv/io/native/gltf_model.h): a model read in the vehicle frame and fitted
// to the unit box, its materials' colours and paint, and broken files named with what was expected.
// The files are written here byte by byte (a base64 buffer of known floats), not by the demo's
// generator, so that the reader is checked against values it did not make.
#include "hv/io/native/gltf_model.h"

#include "hv/io/native/scene_loader.h"
#include "hv/traffic/trajectories.h"
#include "hv/traffic/vehicle_model.h"
#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

std::string base64(const std::vector<float>& f) {
  std::vector<unsigned char> b(f.size() * 4);
  std::memcpy(b.data(), f.data(), b.size());
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < b.size(); i += 3) {
    const std::uint32_t n = std::uint32_t(b[i]) << 16 | (i + 1 < b.size() ? std::uint32_t(b[i + 1]) << 8 : 0) |
                            (i + 2 < b.size() ? b[i + 2] : 0);
    out += k[n >> 18 & 63];
    out += k[n >> 12 & 63];
    out += i + 1 < b.size() ? k[n >> 6 & 63] : '=';
    out += i + 2 < b.size() ? k[n & 63] : '=';
  }
  return out;
}

// Two triangles of a wedge in glTF axes (X left, Y up, Z forward), metres: one "paint" triangle
// standing at the back (Z = -2), from X = -1 to 1 and Y = 0 to 1.5, and one red triangle lying on
// the ground towards the front (Z up to 2). `extra` goes into the top-level object.
std::string wedge(const std::string& bufferUri = "", const std::string& extra = "", int count = 3) {
  const std::vector<float> p = {-1, 0, -2, 1, 0, -2, 0, 1.5f, -2,   // standing, facing +Z
                                -1, 0, -2, 0, 0, 2,  1, 0,    -2};  // lying, facing +Y
  const std::string uri = bufferUri.empty() ? "data:application/octet-stream;base64," + base64(p) : bufferUri;
  return R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
  "nodes": [{"mesh": 0, "translation": [10, 0, 0]}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0},
                             {"attributes": {"POSITION": 1}, "material": 1}]}],
  "materials": [{"name": "paint"}, {"name": "red", "pbrMetallicRoughness": {"baseColorFactor": [1, 0, 0, 1]}}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": )" +
         std::to_string(count) + R"(, "type": "VEC3"},
                {"bufferView": 0, "byteOffset": 36, "componentType": 5126, "count": 3, "type": "VEC3"}],
  "bufferViews": [{"buffer": 0, "byteLength": 72}],
  "buffers": [{"byteLength": 72, "uri": ")" +
         uri + "\"}]" + extra + "}";
}

VehicleModel parse(const std::string& text) {
  return parseGltfVehicle(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), "wedge.gltf");
}

std::string errorOf(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(GltfVehicle, ReadInTheVehicleFrameAndFittedToTheUnitBox) {
  const VehicleModel m = parse(wedge());
  ASSERT_EQ(m.vertices.size(), 6u);
  EXPECT_EQ(m.source, "wedge.gltf");
  // glTF (X, Y, Z) is the vehicle's (-x, z, y); the node's translation moves it, and the fit takes
  // the box x in [-1, 1] (width 2), y in [-2, 2] (length 4), z in [0, 1.5] to the unit box.
  const glm::vec3 expect[6] = {{0.5f, -0.5f, 0}, {-0.5f, -0.5f, 0}, {0, -0.5f, 1},
                               {0.5f, -0.5f, 0}, {0, 0.5f, 0},      {-0.5f, -0.5f, 0}};
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(m.vertices[std::size_t(i)].local[k], expect[i][k], 1e-6) << i << " " << k;
  // Normals from the windings (the file has none): the standing one faces forwards (+y), the
  // lying one up (+z); the paint flag and the red material.
  EXPECT_NEAR(m.vertices[0].normal.y, 1.0f, 1e-6);
  EXPECT_NEAR(m.vertices[3].normal.z, 1.0f, 1e-6);
  EXPECT_EQ(m.vertices[0].paint, 1.0f);
  EXPECT_EQ(m.vertices[3].paint, 0.0f);
  EXPECT_EQ(m.vertices[3].colour, glm::vec3(1, 0, 0));
}

TEST(GltfVehicle, BrokenFilesSayWhatWasExpected) {
  EXPECT_NE(errorOf("not json").find("wedge.gltf: expected glTF 2.0"), std::string::npos) << errorOf("not json");
  // A buffer beside the file is not read.
  const std::string external = errorOf(wedge("wedge.bin"));
  EXPECT_NE(external.find("wedge.gltf: expected glTF 2.0 (JSON with its buffers embedded"), std::string::npos)
      << external;
  // An accessor past its buffer.
  const std::string past = errorOf(wedge("", "", 7));
  EXPECT_NE(past.find("POSITION: expected the accessor inside its bufferView"), std::string::npos) << past;
  // No triangles: the primitives are points.
  std::string points = wedge();
  for (std::size_t at = 0; (at = points.find("\"material\": ", at)) != std::string::npos; at += 20)
    points.insert(at, "\"mode\": 0, ");
  EXPECT_NE(errorOf(points).find("expected triangles"), std::string::npos) << errorOf(points);
  // A node that is not there.
  std::string node = wedge();
  node.replace(node.find("\"nodes\": [0]"), 12, "\"nodes\": [4]");
  EXPECT_NE(errorOf(node).find("node 4: no such node"), std::string::npos) << errorOf(node);
}

class VehicleModelsScene : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("hv_vehicle_models_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    write("t.csv", "t,id,x,y,angle,type\n0,a,0,0,0,car\n1,a,0,10,0,car\n");
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream((dir_ / name).string()) << text;
    return (dir_ / name).string();
  }
  fs::path dir_;
};

// scene.json traffic.models: the bus's file read; the car's missing file reported by name, its
// class left to the built-in box with wheels; the rest of the traffic loads.
TEST_F(VehicleModelsScene, AModelPerClassAndTheFallbackReported) {
  write("bus.gltf", wedge());
  Diagnostics diag;
  const Scene s = loadScene(write("scene.json", R"({"terrain": {"height": 0}, "traffic": {"csv": "t.csv",
      "models": {"bus": "bus.gltf", "car": "nowhere/car.gltf"}}})"),
                            diag);
  ASSERT_NE(s.traffic, nullptr);
  ASSERT_NE(s.traffic->models, nullptr);
  EXPECT_EQ(s.traffic->models->of(VehicleClass::Bus).vertices.size(), 6u);
  EXPECT_EQ(s.traffic->models->of(VehicleClass::Bus).source, (dir_ / "bus.gltf").string());
  EXPECT_EQ(&s.traffic->models->of(VehicleClass::Car), &boxWithWheelsModel());
  ASSERT_EQ(diag.errors.size(), 1u);
  EXPECT_NE(diag.errors[0].find("traffic.models.car: " + (dir_ / "nowhere/car.gltf").string()), std::string::npos)
      << diag.errors[0];
  EXPECT_NE(diag.errors[0].find("built-in box with wheels"), std::string::npos) << diag.errors[0];
  // An unknown class is refused with the list of classes.
  Diagnostics diag2;
  const Scene s2 =
      loadScene(write("scene.json", R"({"traffic": {"csv": "t.csv", "models": {"tank": "bus.gltf"}}})"), diag2);
  ASSERT_FALSE(diag2.ok());
  EXPECT_NE(diag2.errors[0].find("traffic.models.tank: expected one of the classes car, bus"), std::string::npos)
      << diag2.errors[0];
}

}  // namespace
}  // namespace hv
