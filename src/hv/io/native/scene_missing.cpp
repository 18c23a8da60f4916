#include "hv/io/native/scene_missing.h"

#include "hv/io/native/camera_catalog.h"
#include "hv/util/input_file.h"

#include <nlohmann/json.hpp>

namespace hv {

std::string sourceLocation(const nlohmann::json& doc, const std::string& key, const std::string& dir) {
  if (!doc.is_object() || !doc.contains(key) || !doc[key].is_object()) return "";
  const nlohmann::json& s = doc[key];
  if (s.contains("postgis") && s["postgis"].is_string()) return redactConnection(s["postgis"].get<std::string>());
  for (const char* field : {"path", "tileset", "orientations", "url"})
    if (s.contains(field) && s[field].is_string()) return resolveSourcePath(s[field].get<std::string>(), dir);
  return "";
}

void noteMissing(const Scene& scene, const std::string& kind, const std::string& location, const std::string& message) {
  if (scene.missing) scene.missing->add({kind, location, message});
}

}  // namespace hv
