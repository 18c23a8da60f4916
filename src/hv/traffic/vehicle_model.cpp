#include "hv/traffic/vehicle_model.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>

namespace hv {

const char* vehicleClassName(VehicleClass c) {
  switch (c) {
    case VehicleClass::Car:
      return "car";
    case VehicleClass::Bus:
      return "bus";
    case VehicleClass::Truck:
      return "truck";
    case VehicleClass::Motorcycle:
      return "motorcycle";
    case VehicleClass::Bicycle:
      return "bicycle";
  }
  return "car";
}

VehicleClass vehicleClassOf(const std::string& type) {
  std::string t = type;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  const auto has = [&](const char* key) { return t.find(key) != std::string::npos; };
  if (has("bus") || has("coach") || has("tram")) return VehicleClass::Bus;
  if (has("truck") || has("trailer") || has("delivery")) return VehicleClass::Truck;
  if (has("motorcycle") || has("moped")) return VehicleClass::Motorcycle;
  if (has("bicycle")) return VehicleClass::Bicycle;
  return VehicleClass::Car;
}

namespace {

// An axis-aligned box, its faces counter-clockwise from outside.
void addBox(std::vector<ModelVertex>& out, glm::vec3 lo, glm::vec3 hi, glm::vec3 colour, float paint) {
  for (int a = 0; a < 3; ++a)
    for (const int s : {-1, 1}) {
      const int b = (a + 1) % 3, c = (a + 2) % 3;
      glm::vec3 n(0.0f);
      n[a] = float(s);
      auto corner = [&](int ub, int uc) {
        glm::vec3 p;
        p[a] = s < 0 ? lo[a] : hi[a];
        p[b] = ub ? hi[b] : lo[b];
        p[c] = uc ? hi[c] : lo[c];
        return ModelVertex{p, n, colour, paint};
      };
      const ModelVertex q[4] = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
      if (s > 0)
        out.insert(out.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
      else
        out.insert(out.end(), {q[0], q[2], q[1], q[0], q[3], q[2]});
    }
}

}  // namespace

const VehicleModel& boxWithWheelsModel() {
  static const VehicleModel model = [] {
    VehicleModel m;
    const glm::vec3 glass{0.08f, 0.10f, 0.13f}, tyre{0.03f, 0.03f, 0.03f};
    // The body from a ground clearance to the belt line, the cabin set back from the bonnet.
    addBox(m.vertices, {-0.48f, -0.5f, 0.12f}, {0.48f, 0.5f, 0.58f}, glm::vec3(0.5f), 1.0f);
    addBox(m.vertices, {-0.43f, -0.30f, 0.58f}, {0.43f, 0.22f, 1.0f}, glass, 0.0f);
    // The wheels under the axles, at +-wheelbase / 2 (0.3 of the length: hv/traffic/lift.h).
    for (const float y : {-0.3f, 0.3f})
      for (const float x : {-1.0f, 1.0f})
        addBox(m.vertices, {x < 0 ? -0.5f : 0.36f, y - 0.09f, 0.0f}, {x < 0 ? -0.36f : 0.5f, y + 0.09f, 0.3f}, tyre,
               0.0f);
    return m;
  }();
  return model;
}

bool fitToUnitBox(VehicleModel& model) {
  if (model.vertices.empty()) return false;
  glm::vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const ModelVertex& v : model.vertices) {
    lo = glm::min(lo, v.local);
    hi = glm::max(hi, v.local);
  }
  const glm::vec3 span = hi - lo;
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(span[k]) || !(span[k] > 0.0f)) return false;
  const glm::vec3 centre(0.5f * (lo.x + hi.x), 0.5f * (lo.y + hi.y), lo.z);
  for (ModelVertex& v : model.vertices) {
    v.local = (v.local - centre) / span;
    // A normal transforms by the inverse transpose of the scaling: here diag(span).
    const glm::vec3 n = v.normal * span;
    const float len = glm::length(n);
    v.normal = len > 0.0f && std::isfinite(len) ? n / len : glm::vec3(0.0f, 0.0f, 1.0f);
  }
  return true;
}

const VehicleModel& VehicleModels::of(VehicleClass c) const {
  const auto& m = byClass[std::size_t(c)];
  return m ? *m : boxWithWheelsModel();
}

double rayModelEntry(const VehicleModel& model, const glm::dvec3& position, const glm::dvec3& right,
                     const glm::dvec3& forward, const glm::dvec3& up, const glm::dvec3& size, const glm::dvec3& origin,
                     const glm::dvec3& dir) {
  const auto place = [&](const glm::vec3& l) {
    return position + double(l.x) * size.y * right + double(l.y) * size.x * forward + double(l.z) * size.z * up;
  };
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 2 < model.vertices.size(); i += 3) {
    const glm::dvec3 a = place(model.vertices[i].local), b = place(model.vertices[i + 1].local),
                     c = place(model.vertices[i + 2].local);
    // Möller & Trumbore, "Fast, minimum storage ray-triangle intersection" (1997).
    const glm::dvec3 e1 = b - a, e2 = c - a, p = glm::cross(dir, e2);
    const double det = glm::dot(e1, p);
    if (std::abs(det) < 1e-14) continue;
    const double inv = 1.0 / det;
    const glm::dvec3 s = origin - a;
    const double u = glm::dot(s, p) * inv;
    if (u < 0.0 || u > 1.0) continue;
    const glm::dvec3 q = glm::cross(s, e1);
    const double v = glm::dot(dir, q) * inv;
    if (v < 0.0 || u + v > 1.0) continue;
    const double t = glm::dot(e2, q) * inv;
    if (t >= 0.0 && t < best) best = t;
  }
  return std::isfinite(best) ? best : -1.0;
}

}  // namespace hv
