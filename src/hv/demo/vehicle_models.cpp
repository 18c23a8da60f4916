#include "hv/demo/vehicle_models.h"

#include "hv/traffic/trajectories.h"
#include "hv/util/diagnostics.h"

#include <nlohmann/json.hpp>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

namespace hv::demo {

namespace {

using json = nlohmann::ordered_json;

struct Material {
  const char* name;
  glm::vec3 colour;  // linear
};
constexpr Material kMaterials[] = {{"paint", {0.6f, 0.6f, 0.6f}},
                                   {"glass", {0.06f, 0.08f, 0.11f}},
                                   {"tyre", {0.025f, 0.025f, 0.025f}},
                                   {"cargo", {0.80f, 0.80f, 0.78f}},
                                   {"light", {0.95f, 0.92f, 0.75f}}};
enum Mat { kPaint, kGlass, kTyre, kCargo, kLight, kMatCount };

// Triangles per material, in the vehicle frame (x right, y forward, z up), metres.
struct Builder {
  std::array<std::vector<glm::vec3>, kMatCount> triangles;

  // A convex polygon in the (y, z) plane (any winding), extruded from x0 to x1: a box when it is a
  // rectangle, a wheel when it is a many-sided polygon. Triangles wound counter-clockwise from
  // outside (checked against the prism's centre).
  void prism(const std::vector<glm::vec2>& yz, float x0, float x1, Mat m) {
    glm::vec3 centre(0.5f * (x0 + x1), 0.0f, 0.0f);
    for (const glm::vec2& p : yz) centre += glm::vec3(0.0f, p.x, p.y) / float(yz.size());
    auto tri = [&](glm::vec3 a, glm::vec3 b, glm::vec3 c) {
      const glm::vec3 n = glm::cross(b - a, c - a);
      if (glm::dot(n, (a + b + c) / 3.0f - centre) < 0.0f) std::swap(b, c);
      triangles[m].insert(triangles[m].end(), {a, b, c});
    };
    const std::size_t k = yz.size();
    for (const float x : {x0, x1})
      for (std::size_t i = 1; i + 1 < k; ++i)
        tri({x, yz[0].x, yz[0].y}, {x, yz[i].x, yz[i].y}, {x, yz[i + 1].x, yz[i + 1].y});
    for (std::size_t i = 0; i < k; ++i) {
      const glm::vec2 a = yz[i], b = yz[(i + 1) % k];
      tri({x0, a.x, a.y}, {x1, a.x, a.y}, {x1, b.x, b.y});
      tri({x0, a.x, a.y}, {x1, b.x, b.y}, {x0, b.x, b.y});
    }
  }
  void box(glm::vec3 lo, glm::vec3 hi, Mat m) {
    prism({{lo.y, lo.z}, {hi.y, lo.z}, {hi.y, hi.z}, {lo.y, hi.z}}, lo.x, hi.x, m);
  }
  // A wheel of radius r, centred at (y, r) on the ground, from x0 to x1: a 10-sided prism.
  void wheel(float y, float r, float x0, float x1) {
    std::vector<glm::vec2> yz;
    for (int i = 0; i < 10; ++i) {
      const float a = float(i) * 6.2831853f / 10.0f;
      yz.push_back({y + r * std::cos(a), r + r * std::sin(a)});
    }
    prism(yz, x0, x1, kTyre);
  }
  // Four wheels (or more axles) at the given ys, their outer faces at +-w/2.
  void wheels(const std::vector<float>& ys, float r, float w, float tyreWidth) {
    for (const float y : ys) {
      wheel(y, r, -0.5f * w, -0.5f * w + tyreWidth);
      wheel(y, r, 0.5f * w - tyreWidth, 0.5f * w);
    }
  }
};

Builder car() {
  const VehicleSize s = vehicleSizeOf("car");
  const float L = float(s.length), W = float(s.width), H = float(s.height);
  Builder b;
  const float hw = 0.48f * W;
  // The body: bonnet and boot, from the sills to the belt line.
  b.box({-hw, -0.5f * L, 0.28f}, {hw, 0.5f * L, 0.78f}, kPaint);
  // The cabin: windscreen and rear window sloped (a trapezoid in the side view), glass.
  b.prism({{-0.34f * L, 0.78f}, {0.18f * L, 0.78f}, {0.02f * L, H}, {-0.26f * L, H}}, -0.44f * W, 0.44f * W, kGlass);
  // Headlights.
  b.box({-0.42f * W, 0.5f * L, 0.58f}, {-0.24f * W, 0.5f * L + 0.02f, 0.68f}, kLight);
  b.box({0.24f * W, 0.5f * L, 0.58f}, {0.42f * W, 0.5f * L + 0.02f, 0.68f}, kLight);
  b.wheels({-0.3f * L, 0.3f * L}, 0.32f, W, 0.2f);
  return b;
}

Builder bus() {
  const VehicleSize s = vehicleSizeOf("bus");
  const float L = float(s.length), W = float(s.width), H = float(s.height);
  Builder b;
  const float hw = 0.48f * W;
  b.box({-hw, -0.5f * L, 0.35f}, {hw, 0.5f * L, 1.15f}, kPaint);
  // The window band, a hair wider than the body so that it shows, and the roof.
  b.box({-hw - 0.01f, -0.48f * L, 1.15f}, {hw + 0.01f, 0.5f * L + 0.01f, 2.75f}, kGlass);
  b.box({-hw, -0.5f * L, 2.75f}, {hw, 0.5f * L, H}, kPaint);
  b.box({-hw, -0.5f * L, 1.15f}, {hw, -0.48f * L, 2.75f}, kPaint);
  b.wheels({-0.28f * L, 0.32f * L}, 0.5f, W, 0.3f);
  return b;
}

Builder truck() {
  const VehicleSize s = vehicleSizeOf("truck");
  const float L = float(s.length), W = float(s.width), H = float(s.height);
  Builder b;
  const float hw = 0.48f * W;
  // The cab in front (paint, windscreen glass), the cargo box behind, a chassis under both.
  const float cabBack = 0.5f * L - 1.9f;
  b.box({-hw, cabBack, 0.45f}, {hw, 0.5f * L, 1.45f}, kPaint);
  b.box({-0.45f * W, cabBack + 0.2f, 1.45f}, {0.45f * W, 0.5f * L - 0.05f, 0.86f * H}, kGlass);
  b.box({-hw, cabBack, 0.86f * H}, {hw, 0.5f * L - 0.05f, 0.9f * H}, kPaint);
  b.box({-0.5f * W, -0.5f * L, 0.55f}, {0.5f * W, cabBack - 0.1f, H}, kCargo);
  b.box({-0.4f * W, -0.5f * L + 0.2f, 0.3f}, {0.4f * W, cabBack, 0.55f}, kTyre);
  b.wheels({-0.3f * L, 0.3f * L}, 0.45f, W, 0.3f);
  return b;
}

std::string base64(const std::vector<unsigned char>& bytes) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t n = std::uint32_t(bytes[i]) << 16 |
                            (i + 1 < bytes.size() ? std::uint32_t(bytes[i + 1]) << 8 : 0) |
                            (i + 2 < bytes.size() ? bytes[i + 2] : 0);
    out += k[n >> 18 & 63];
    out += k[n >> 12 & 63];
    out += i + 1 < bytes.size() ? k[n >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? k[n & 63] : '=';
  }
  return out;
}

std::string toGltf(const Builder& b, const std::string& name) {
  std::vector<unsigned char> buffer;
  auto append = [&](const std::vector<glm::vec3>& v) {
    const std::size_t offset = buffer.size();
    buffer.resize(offset + v.size() * 12);
    std::memcpy(buffer.data() + offset, v.data(), v.size() * 12);
    return offset;
  };
  json materials = json::array(), accessors = json::array(), views = json::array(), primitives = json::array();
  for (int m = 0; m < kMatCount; ++m) {
    const glm::vec3 c = kMaterials[m].colour;
    materials.push_back(
        {{"name", kMaterials[m].name},
         {"pbrMetallicRoughness", {{"baseColorFactor", {c.r, c.g, c.b, 1.0f}}, {"metallicFactor", 0.0f}}}});
  }
  for (int m = 0; m < kMatCount; ++m) {
    const std::vector<glm::vec3>& t = b.triangles[std::size_t(m)];
    if (t.empty()) continue;
    std::vector<glm::vec3> positions, normals;
    glm::vec3 lo(1e30f), hi(-1e30f);
    for (std::size_t i = 0; i < t.size(); i += 3) {
      const glm::vec3 n = glm::normalize(glm::cross(t[i + 1] - t[i], t[i + 2] - t[i]));
      for (int k = 0; k < 3; ++k) {
        // The vehicle frame (x right, y forward, z up) to glTF's (X left, Y up, Z forward).
        const glm::vec3 p = t[i + std::size_t(k)];
        const glm::vec3 g(-p.x, p.z, p.y);
        positions.push_back(g);
        normals.push_back({-n.x, n.z, n.y});
        lo = glm::min(lo, g);
        hi = glm::max(hi, g);
      }
    }
    const int first = int(accessors.size());
    for (const auto* v : {&positions, &normals}) {
      const std::size_t offset = append(*v);
      views.push_back({{"buffer", 0}, {"byteOffset", offset}, {"byteLength", v->size() * 12}, {"target", 34962}});
      json a = {{"bufferView", views.size() - 1}, {"componentType", 5126}, {"count", v->size()}, {"type", "VEC3"}};
      if (v == &positions) {
        a["min"] = {lo.x, lo.y, lo.z};
        a["max"] = {hi.x, hi.y, hi.z};
      }
      accessors.push_back(a);
    }
    primitives.push_back({{"attributes", {{"POSITION", first}, {"NORMAL", first + 1}}}, {"material", m}, {"mode", 4}});
  }
  const json doc = {
      {"asset", {{"version", "2.0"}, {"generator", "histoview demo (src/hv/demo/vehicle_models.cpp)"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}}}},
      {"nodes", {{{"mesh", 0}, {"name", name}}}},
      {"meshes", {{{"name", name}, {"primitives", primitives}}}},
      {"materials", materials},
      {"accessors", accessors},
      {"bufferViews", views},
      {"buffers",
       {{{"byteLength", buffer.size()}, {"uri", "data:application/octet-stream;base64," + base64(buffer)}}}}};
  return doc.dump(1) + "\n";
}

}  // namespace

const std::vector<VehicleClass>& generatedVehicleClasses() {
  static const std::vector<VehicleClass> k = {VehicleClass::Car, VehicleClass::Bus, VehicleClass::Truck};
  return k;
}

std::string vehicleModelGltf(VehicleClass c) {
  switch (c) {
    case VehicleClass::Bus:
      return toGltf(bus(), "bus");
    case VehicleClass::Truck:
      return toGltf(truck(), "truck");
    default:
      return toGltf(car(), "car");
  }
}

std::vector<std::string> writeVehicleModels(const std::string& dir) {
  std::filesystem::create_directories(dir);
  std::vector<std::string> names;
  for (const VehicleClass c : generatedVehicleClasses()) {
    const std::string name = std::string(vehicleClassName(c)) + ".gltf";
    const std::string path = (std::filesystem::path(dir) / name).string();
    std::ofstream out(path, std::ios::binary);
    out << vehicleModelGltf(c);
    if (!out) throw InputError(path + ": could not write the vehicle model");
    names.push_back(name);
  }
  return names;
}

}  // namespace hv::demo
