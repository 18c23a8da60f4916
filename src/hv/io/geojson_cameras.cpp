#include "hv/io/geojson_cameras.h"

#include "hv/io/camera_properties.h"
#include "hv/io/json_input.h"

#include <nlohmann/json.hpp>

#include <cstdint>

namespace hv {

using json = nlohmann::json;

namespace {

// A property as the camera decoder takes it.
CameraProperty propertyOf(const json& props, const char* name) {
  CameraProperty v;
  const auto it = props.find(name);
  if (it == props.end() || it->is_null()) return v;
  const json& j = *it;
  if (j.is_string()) {
    v.kind = CameraProperty::Kind::Text;
    v.type = "string";
    v.text = j.get<std::string>();
  } else if (j.is_number()) {
    v.kind = CameraProperty::Kind::Number;
    v.type = "number";
    v.number = j.get<double>();
    v.text = j.is_number_float() ? j.dump()
                                 : (j.is_number_unsigned() ? std::to_string(j.get<std::uint64_t>())
                                                           : std::to_string(j.get<std::int64_t>()));
  } else if (j.is_array()) {
    v.kind = CameraProperty::Kind::NumberList;
    v.type = "array";
    for (const json& e : j) {
      if (!e.is_number()) {
        v.kind = CameraProperty::Kind::Other;
        v.type = "array holding a " + std::string(e.type_name());
        v.list.clear();
        break;
      }
      v.list.push_back(e.get<double>());
    }
  } else {
    v.kind = CameraProperty::Kind::Other;
    v.type = j.type_name();
  }
  return v;
}

glm::dvec3 pointOf(const json& f) {
  const auto g = f.find("geometry");
  if (g == f.end() || !g->is_object() || g->value("type", std::string()) != "Point")
    throw InputError("centre: expected a point geometry");
  const auto c = g->find("coordinates");
  if (c == g->end() || !c->is_array() || c->size() < 2) throw InputError("centre: expected a point geometry");
  for (const json& x : *c)
    if (!x.is_number()) throw InputError("centre: expected numbers as the point's coordinates");
  if (c->size() < 3) throw InputError("centre: expected a 3D point (x, y, z), got a 2D one");
  return {(*c)[0].get<double>(), (*c)[1].get<double>(), (*c)[2].get<double>()};
}

}  // namespace

GeoJsonCameraPage parseGeoJsonCameras(const std::string& text, const std::string& name, Diagnostics& diag) {
  GeoJsonCameraPage page;
  const json doc = parseFeatureCollection(text, name, page.next);
  const json noProperties = json::object();
  for (const json& f : doc["features"]) {
    const std::size_t index = page.features++;
    std::string fid = std::to_string(index);
    if (f.is_object() && f.contains("id") && (f["id"].is_string() || f["id"].is_number()))
      fid = f["id"].is_string() ? f["id"].get<std::string>() : f["id"].dump();
    std::string id;
    try {
      if (!f.is_object() || f.value("type", std::string()) != "Feature")
        throw InputError("expected a GeoJSON Feature (\"type\": \"Feature\")");
      const auto p = f.find("properties");
      const json& props = p != f.end() && p->is_object() ? *p : noProperties;
      if (const CameraProperty v = propertyOf(props, "id");
          v.kind == CameraProperty::Kind::Text || v.kind == CameraProperty::Kind::Number)
        id = v.text;
      page.photos.push_back(
          decodeCameraProperties([&](const char* key) { return propertyOf(props, key); }, [&] { return pointOf(f); }));
    } catch (const InputError& e) {
      std::string what = e.what();
      const std::string named = "camera '" + id + "': ";  // validateCamera's own prefix
      if (what.rfind(named, 0) == 0) what = what.substr(named.size());
      diag.error(name + ": feature " + fid + " (camera '" + id + "'): " + what + " (camera skipped)");
    }
  }
  return page;
}

}  // namespace hv
