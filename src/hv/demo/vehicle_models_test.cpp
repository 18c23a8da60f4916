// The demo's vehicle models made by code: the committed data/vehicles/*.gltf are the generator's
// output (regenerate: HV_UPDATE_VEHICLE_MODELS=1 build/hv_tests --gtest_filter='DemoVehicleModels.*'),
// and each reads back through the glTF reader with the proportions of its class's size.
#include "hv/demo/vehicle_models.h"

#include "hv/io/native/gltf_model.h"
#include "hv/traffic/trajectories.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hv::demo {
namespace {

namespace fs = std::filesystem;

TEST(DemoVehicleModels, CommittedFilesAreTheGeneratorsOutput) {
  const fs::path dir = fs::path(HV_SOURCE_DIR) / "data" / "vehicles";
  if (std::getenv("HV_UPDATE_VEHICLE_MODELS")) writeVehicleModels(dir.string());
  for (const VehicleClass c : generatedVehicleClasses()) {
    const fs::path path = dir / (std::string(vehicleClassName(c)) + ".gltf");
    std::ifstream in(path, std::ios::binary);
    ASSERT_TRUE(in) << path << " is missing";
    std::stringstream text;
    text << in.rdbuf();
    EXPECT_EQ(text.str(), vehicleModelGltf(c)) << path
                                               << " differs from the generator's output (regenerate: "
                                                  "HV_UPDATE_VEHICLE_MODELS=1 build/hv_tests "
                                                  "--gtest_filter='DemoVehicleModels.*')";
    EXPECT_LT(text.str().size(), 64u * 1024u) << "a small low-poly model";
  }
}

// Read back: in the unit box, with paint, glass and tyres (four wheels' worth of tyre triangles on
// the ground), the bus's windows a band along its whole length.
TEST(DemoVehicleModels, ReadBackWithTheirMaterials) {
  for (const VehicleClass c : generatedVehicleClasses()) {
    const std::string text = vehicleModelGltf(c);
    const VehicleModel m =
        parseGltfVehicle(reinterpret_cast<const std::uint8_t*>(text.data()), text.size(), vehicleClassName(c));
    int paint = 0, dark = 0;
    glm::vec3 lo(1e9f), hi(-1e9f);
    for (const ModelVertex& v : m.vertices) {
      lo = glm::min(lo, v.local);
      hi = glm::max(hi, v.local);
      paint += v.paint > 0.5f;
      dark += v.paint < 0.5f && v.colour.r < 0.1f;
    }
    EXPECT_NEAR(lo.x, -0.5f, 1e-5) << vehicleClassName(c);
    EXPECT_NEAR(hi.y, 0.5f, 1e-5) << vehicleClassName(c);
    EXPECT_NEAR(lo.z, 0.0f, 1e-6) << vehicleClassName(c);
    EXPECT_NEAR(hi.z, 1.0f, 1e-6) << vehicleClassName(c);
    EXPECT_GT(paint, 0) << vehicleClassName(c);
    EXPECT_GT(dark, 0) << vehicleClassName(c);
    EXPECT_LT(m.vertices.size() / 3, 2000u) << "low-poly";
  }
}

}  // namespace
}  // namespace hv::demo
