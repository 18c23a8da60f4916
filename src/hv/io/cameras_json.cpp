#include "hv/io/cameras_json.h"

#include "hv/io/json_input.h"
#include "hv/util/dates.h"
#include "hv/util/input_file.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <map>
#include <system_error>

namespace hv {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// What a JSON value is, for messages: scalars as written, containers by type and size (never
// dumped whole: a deeply nested value would recurse for as long as the file is deep).
std::string describe(const json& v) {
  if (v.is_array()) return "an array of " + std::to_string(v.size());
  if (v.is_object()) return "an object";
  if (v.is_null()) return "null";
  if (isNonFiniteLiteral(v)) return v.get<std::string>() + " (not a finite number)";
  std::string s = v.dump();
  return s.size() > 40 ? s.substr(0, 40) + "..." : s;
}

// Field readers: each names what it expected, so the message says file, camera, field, expected.
double number(const json& j, const char* field) {
  if (!j.contains(field)) throw InputError(std::string(field) + ": missing (expected a number)");
  const json& v = j.at(field);
  if (!v.is_number()) throw InputError(std::string(field) + ": expected a number, got " + describe(v));
  const double d = v.get<double>();
  if (!std::isfinite(d)) throw InputError(std::string(field) + ": expected a finite number");
  return d;
}

std::vector<double> numbers(const json& j, const char* field, size_t n) {
  if (!j.contains(field))
    throw InputError(std::string(field) + ": missing (expected " + std::to_string(n) + " numbers)");
  const json& v = j.at(field);
  if (!v.is_array() || v.size() != n)
    throw InputError(std::string(field) + ": expected an array of " + std::to_string(n) + " numbers, got " +
                     describe(v));
  std::vector<double> out;
  for (const auto& e : v) {
    // nlohmann parses NaN/Infinity as invalid JSON, but null sneaks in for them in some writers.
    if (!e.is_number()) throw InputError(std::string(field) + ": expected numbers, got " + describe(e));
    out.push_back(e.get<double>());
    if (!std::isfinite(out.back())) throw InputError(std::string(field) + ": expected finite numbers");
  }
  return out;
}

int positiveInt(const json& j, const char* field) {
  const double d = number(j, field);
  if (d <= 0 || d != std::floor(d) || d > 65536)
    throw InputError(std::string(field) + ": expected a positive integer, got " + std::to_string(d));
  return int(d);
}

// Keys a camera may have (docs/formats.md); `t` is a camera path's time (PATH.json).
const std::vector<std::string> kCameraKeys = {"id",         "image",    "mask",  "width",     "height",
                                              "center",     "rotation", "focal", "principal", "skew",
                                              "distortion", "date",     "t"};

std::string resolve(const std::string& baseDir, const std::string& p, const std::string& field) {
  // The system calls would stop at the NUL and open another file than the one named.
  if (p.find('\0') != std::string::npos) throw InputError(field + ": the path contains a NUL byte");
  // A photograph by URL (docs/services.md) stays a URL.
  if (p.empty() || fs::path(p).is_absolute() || isHttpUrl(p)) return p;
  return (fs::path(baseDir) / p).lexically_normal().string();
}

// "distortion": {"type": "radial" | "opencv" | "fisheye", ...}; docs/formats.md has the fields and
// hv::LensDistortion (camera.h) the models. Needs the camera's focal and principal point (opencv).
LensDistortion parseDistortion(const json& d, const Camera& c, std::vector<std::string>& notes) {
  if (!d.is_object()) throw InputError("distortion: expected an object");
  if (d.contains("type") && !d["type"].is_string())
    throw InputError("distortion.type: expected \"radial\", \"opencv\" or \"fisheye\"");
  const std::string type = d.value("type", "radial");
  static const std::map<std::string, std::vector<std::string>> kKeys = {
      {"radial", {"type", "center", "c3", "c5", "c7", "r2max"}},
      {"opencv", {"type", "k1", "k2", "k3", "p1", "p2", "r2max"}},
      {"fisheye", {"type", "center", "focal", "c3", "c5", "c7", "l1", "l2", "r2max"}}};
  if (const auto known = kKeys.find(type); known != kKeys.end())
    for (const std::string& m : unknownKeys(d, known->second)) notes.push_back("distortion: " + m);
  auto optional = [&](const char* field, double fallback) { return d.contains(field) ? number(d, field) : fallback; };
  LensDistortion lens;
  try {
    if (type == "radial") {
      auto dc = numbers(d, "center", 2);
      lens.center = {dc[0], dc[1]};
      lens.c3 = optional("c3", 0.0);
      lens.c5 = optional("c5", 0.0);
      lens.c7 = optional("c7", 0.0);
    } else if (type == "opencv") {
      lens.center = c.principal;
      lens.scale = c.focal;
      lens.c3 = optional("k1", 0.0);
      lens.c5 = optional("k2", 0.0);
      lens.c7 = optional("k3", 0.0);
      lens.p1 = optional("p1", 0.0);
      lens.p2 = optional("p2", 0.0);
    } else if (type == "fisheye") {
      lens.model = LensDistortion::Model::Fisheye;
      auto dc = numbers(d, "center", 2);
      lens.center = {dc[0], dc[1]};
      const double f = number(d, "focal");
      if (!(f > 0.0)) throw InputError("focal: expected a positive number of pixels");
      lens.scale = {f, f};
      lens.c3 = optional("c3", 0.0);
      lens.c5 = optional("c5", 0.0);
      lens.c7 = optional("c7", 0.0);
      lens.l1 = optional("l1", 0.0);
      lens.l2 = optional("l2", 0.0);
    } else {
      throw InputError("type: expected \"radial\", \"opencv\" or \"fisheye\", got \"" + type + "\"");
    }
    lens.r2max = optional("r2max", 1e30);
    if (!(lens.r2max > 0)) throw InputError("r2max: expected a positive number");
  } catch (const InputError& e) {
    throw InputError(std::string("distortion.") + e.what());
  }
  return lens;
}

json distortionJson(const LensDistortion& d, const Camera& c) {
  using Model = LensDistortion::Model;
  if (d.model == Model::Fisheye) {
    return {{"type", "fisheye"},  {"center", {d.center.x, d.center.y}},
            {"focal", d.scale.x}, {"c3", d.c3},
            {"c5", d.c5},         {"c7", d.c7},
            {"l1", d.l1},         {"l2", d.l2},
            {"r2max", d.r2max}};
  }
  if (d.p1 == 0.0 && d.p2 == 0.0 && d.scale.x == d.scale.y) {
    // A pixel polynomial: normalised by `scale`, so c_k in pixels is c_k / scale^(k-1).
    const double s2 = d.scale.x * d.scale.x;
    return {{"type", "radial"},       {"center", {d.center.x, d.center.y}}, {"c3", d.c3 / s2},
            {"c5", d.c5 / (s2 * s2)}, {"c7", d.c7 / (s2 * s2 * s2)},        {"r2max", std::min(d.r2max * s2, 1e30)}};
  }
  if (d.center != c.principal || d.scale != c.focal)
    throw std::invalid_argument("camera '" + c.id +
                                "': tangential distortion about another centre than the principal point has no "
                                "cameras.json form");
  return {{"type", "opencv"}, {"k1", d.c3}, {"k2", d.c5}, {"k3", d.c7}, {"p1", d.p1}, {"p2", d.p2}, {"r2max", d.r2max}};
}

// `path` relative to `baseDir` through the file system (links resolved), else lexically: a path
// in a loop of links or with a name too long would make std::filesystem::relative throw and
// the whole file unwritable for one photograph.
std::string relativeTo(const std::string& path, const std::string& baseDir) {
  if (isHttpUrl(path)) return path;
  std::error_code ec;
  const fs::path r = fs::relative(path, baseDir, ec);
  if (!ec && !r.empty()) return r.string();
  const fs::path lexical = fs::path(path).lexically_relative(baseDir);
  return lexical.empty() ? path : lexical.string();
}

// One camera; `notes` gets what is read but worth a warning (unknown keys, a date not read).
Photo parseOne(const json& j, const std::string& baseDir, const CameraFileOptions& opt,
               std::vector<std::string>& notes) {
  Photo photo;
  Camera& c = photo.camera;
  if (!j.is_object()) throw InputError("expected an object");
  if (!j.contains("id") || !(j["id"].is_string() || j["id"].is_number_integer()))
    throw InputError("id: missing (expected a string)");
  c.id = j["id"].is_string() ? j["id"].get<std::string>() : std::to_string(j["id"].get<long long>());
  for (const std::string& m : unknownKeys(j, kCameraKeys)) notes.push_back(m + " (ignored)");
  try {
    c.width = positiveInt(j, "width");
    c.height = positiveInt(j, "height");
    auto ctr = numbers(j, "center", 3);
    c.center = {ctr[0], ctr[1], ctr[2]};
    auto rot = numbers(j, "rotation", 9);
    c.camFromWorld = mat3FromRowMajor(rot.data());
    auto f = numbers(j, "focal", 2);
    c.focal = {f[0], f[1]};
    auto pp = numbers(j, "principal", 2);
    c.principal = {pp[0], pp[1]};
    c.skew = j.contains("skew") ? number(j, "skew") : 0.0;
    if (j.contains("distortion") && !j["distortion"].is_null())
      c.distortion = parseDistortion(j["distortion"], c, notes);
    validateCamera(c);
    if (j.contains("image") && j["image"].is_string())
      photo.imagePath = resolve(baseDir, j["image"].get<std::string>(), "image");
    else if (j.contains("image") && !j["image"].is_null())
      throw InputError("image: expected a path string");
    if (opt.requireImages && photo.imagePath.empty())
      throw InputError("image: missing (expected a path to a JPEG or PNG)");
    if (j.contains("mask") && j["mask"].is_string())
      photo.maskPath = resolve(baseDir, j["mask"].get<std::string>(), "mask");
    else if (j.contains("mask") && !j["mask"].is_null())
      throw InputError("mask: expected a path string or null");
    if (opt.checkImageFiles) {
      // A URL is fetched when the photograph is loaded, and a failure then leaves only it out.
      if (!photo.imagePath.empty() && !isHttpUrl(photo.imagePath) && !isRegularFile(photo.imagePath))
        throw InputError("image: " + notRegularFileReason(photo.imagePath) + ": " + photo.imagePath);
      if (!photo.maskPath.empty() && !isHttpUrl(photo.maskPath) && !isRegularFile(photo.maskPath))
        throw InputError("mask: " + notRegularFileReason(photo.maskPath) + ": " + photo.maskPath);
    }
    if (j.contains("date") && !j["date"].is_null()) {
      // A date that cannot be read is left out (the photograph then has none), not guessed.
      if (!j["date"].is_string())
        notes.push_back("date: expected an ISO 8601 date string (\"1905-06-01\"), got " + describe(j["date"]) +
                        " (ignored)");
      else if (!parseDate(j["date"].get<std::string>()))
        notes.push_back("date: expected an ISO 8601 date, got \"" + j["date"].get<std::string>() + "\" (ignored)");
      else
        photo.date = j["date"].get<std::string>();
    }
  } catch (const InputError& e) {
    // validateCamera already names the camera; field readers do not.
    const std::string what = e.what();
    if (what.rfind("camera '", 0) == 0) throw;
    throw InputError("camera '" + c.id + "': " + what);
  }
  return photo;
}

}  // namespace

std::vector<Photo> parseCameraJson(const std::string& text, const std::string& path, const std::string& baseDir,
                                   const CameraFileOptions& opt, Diagnostics& diag) {
  const json doc = parseJsonInput(text, path, diag);
  if (!doc.is_object() || !doc.contains("cameras") || !doc["cameras"].is_array())
    throw InputError(path + ": cameras: missing (expected an object with a \"cameras\" array)");
  for (const std::string& m : unknownKeys(doc, {"cameras"})) diag.warn(inputMessage(path, "", m + " (ignored)"));
  std::vector<Photo> out;
  std::map<std::string, size_t> seen;  // id -> index of the camera kept
  size_t index = 0;
  for (const auto& j : doc["cameras"]) {
    try {
      std::vector<std::string> notes;
      Photo photo = parseOne(j, baseDir, opt, notes);
      for (const std::string& m : notes) diag.warn(inputMessage(path, "camera '" + photo.camera.id + "'", m));
      // Two cameras of one id would be one in every view selection, every output file name and the
      // page: the first is kept.
      if (const auto [it, added] = seen.emplace(photo.camera.id, index); !added)
        throw InputError("camera '" + photo.camera.id + "': duplicate id (camera #" + std::to_string(it->second) +
                         " has it too and is kept)");
      fitLensDomain(photo.camera, path, diag);
      out.push_back(std::move(photo));
    } catch (const InputError& e) {
      std::string msg = e.what();
      if (msg.rfind("camera '", 0) != 0) msg = "camera #" + std::to_string(index) + ": " + msg;
      diag.error(path + ": " + msg + " (camera skipped)");
    } catch (const json::exception& e) {
      diag.error(path + ": camera #" + std::to_string(index) + ": " + e.what() + " (camera skipped)");
    }
    ++index;
  }
  return out;
}

std::vector<Photo> readCameraFile(const std::string& path, const CameraFileOptions& opt, Diagnostics& diag) {
  const std::string text = readTextFile(path, kMaxJsonBytes, "cameras file");
  const std::string dir = fs::path(path).parent_path().string();
  return parseCameraJson(text, path, dir.empty() ? "." : dir, opt, diag);
}

std::string cameraJson(const std::vector<Photo>& photos, const std::string& baseDir) {
  json arr = json::array();
  for (const auto& p : photos) {
    const Camera& c = p.camera;
    double r[9];
    mat3ToRowMajor(c.camFromWorld, r);
    json j = {{"id", c.id},
              {"width", c.width},
              {"height", c.height},
              {"center", {c.center.x, c.center.y, c.center.z}},
              {"rotation", std::vector<double>(r, r + 9)},
              {"focal", {c.focal.x, c.focal.y}},
              {"principal", {c.principal.x, c.principal.y}},
              {"skew", c.skew}};
    if (!p.imagePath.empty()) j["image"] = baseDir.empty() ? p.imagePath : relativeTo(p.imagePath, baseDir);
    if (!p.maskPath.empty()) j["mask"] = baseDir.empty() ? p.maskPath : relativeTo(p.maskPath, baseDir);
    if (c.distortion) j["distortion"] = distortionJson(*c.distortion, c);
    if (!p.date.empty()) j["date"] = p.date;
    arr.push_back(j);
  }
  return json{{"cameras", arr}}.dump(1);
}

}  // namespace hv
