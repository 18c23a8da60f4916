// PATH.json: a cameras file (hv/io/cameras_json.h) whose cameras may carry a time `t` (seconds).
#include "hv/io/camera_path_json.h"

#include "hv/io/cameras_json.h"
#include "hv/io/json_input.h"
#include "hv/util/input_file.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace hv {

CameraPath parseCameraPath(const std::string& text, const std::string& file, Diagnostics& diag) {
  CameraFileOptions opts;
  opts.requireImages = false;
  opts.checkImageFiles = false;
  const std::string dir = std::filesystem::path(file).parent_path().string();
  Diagnostics local;
  std::vector<Photo> photos = parseCameraJson(text, file, dir.empty() ? "." : dir, opts, local);
  diag.warnings.insert(diag.warnings.end(), local.warnings.begin(), local.warnings.end());
  if (!local.ok())
    throw InputError(
        local.errors.front() +
        (local.errors.size() > 1 ? " (and " + std::to_string(local.errors.size() - 1) + " more)" : "") +
        "; every key camera of a path must be readable");
  // parseCameraJson has already parsed and checked the document: every camera loaded, in order.
  Diagnostics again;  // the same document: its warnings are already in `diag`
  const nlohmann::json doc = parseJsonInput(text, file, again);
  const nlohmann::json& cams = doc.at("cameras");
  std::vector<PathKey> keys;
  for (size_t i = 0; i < photos.size(); ++i) {
    PathKey k;
    k.camera = std::move(photos[i].camera);
    const nlohmann::json& j = cams.at(i);
    if (j.contains("t") && !j["t"].is_null()) {
      if (!j["t"].is_number())
        throw InputError(file + ": camera '" + k.camera.id + "': t: expected a number of seconds, got " +
                         std::string(j["t"].type_name()));
      k.time = j["t"].get<double>();
    } else {
      k.time = keys.empty() ? 0.0 : keys.back().time + 1.0;
    }
    keys.push_back(std::move(k));
  }
  try {
    return CameraPath(std::move(keys));
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
}

std::string cameraPathJson(const std::vector<PathKey>& keys) {
  std::vector<Photo> cams;
  for (const auto& k : keys) cams.push_back(Photo{k.camera, "", "", ""});
  nlohmann::json doc = nlohmann::json::parse(cameraJson(cams, ""));
  for (size_t i = 0; i < keys.size(); ++i) doc["cameras"][i]["t"] = keys[i].time;
  return doc.dump(1);
}

CameraPath readCameraPath(const std::string& path, Diagnostics& diag) {
  return parseCameraPath(readTextFile(path, kMaxJsonBytes, "camera path"), path, diag);
}

}  // namespace hv
