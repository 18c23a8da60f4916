#include "hv/io/native/itowns_cameras.h"

#include "hv/io/json_input.h"
#include "hv/util/input_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>

namespace hv {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json readJson(const std::string& path, Diagnostics& diag) { return readJsonInput(path, "iTowns file", diag); }

// The largest image side a camera may declare (as cameras.json's width and height): beyond it a
// size is a typing error, and its pixel count would overflow the image loader's arithmetic.
constexpr double kMaxImageSide = 65536;

double num(const json& j, const char* field) {
  if (!j.contains(field) || !j[field].is_number()) throw InputError(std::string(field) + ": expected a number");
  const double v = j[field].get<double>();
  if (!std::isfinite(v)) throw InputError(std::string(field) + ": expected a finite number");
  return v;
}

std::vector<double> nums(const json& j, const char* field, size_t n) {
  if (!j.contains(field) || !j[field].is_array() || j[field].size() != n)
    throw InputError(std::string(field) + ": expected an array of " + std::to_string(n) + " numbers");
  std::vector<double> out;
  for (const auto& e : j[field]) {
    if (!e.is_number() || !std::isfinite(e.get<double>()))
      throw InputError(std::string(field) + ": expected finite numbers");
    out.push_back(e.get<double>());
  }
  return out;
}

std::string idString(const json& j) {
  if (j.contains("id") && j["id"].is_string()) return j["id"].get<std::string>();
  if (j.contains("id") && j["id"].is_number_integer()) return std::to_string(j["id"].get<long long>());
  throw InputError("id: expected a string or an integer");
}

// Right-handed rotations about the axes (angle in radians), as matrices acting on column vectors.
glm::dmat3 rotX(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return glm::transpose(glm::dmat3(1, 0, 0, 0, c, -s, 0, s, c));
}
glm::dmat3 rotY(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return glm::transpose(glm::dmat3(c, 0, s, 0, 1, 0, -s, 0, c));
}
glm::dmat3 rotZ(double a) {
  const double c = std::cos(a), s = std::sin(a);
  return glm::transpose(glm::dmat3(c, -s, 0, s, c, 0, 0, 0, 1));
}

struct RigCamera {
  std::string id;
  glm::dmat3 camFromPano{1.0};
  glm::dvec3 positionInPano{0.0};
  glm::dvec2 focal{1.0}, principal{0.0};
  int width = 0, height = 0;
  std::optional<LensDistortion> distortion;
  std::string mask;
};

RigCamera parseRigCamera(const json& j) {
  RigCamera r;
  r.id = idString(j);
  auto rot = nums(j, "rotation", 9);
  // Given to ~6 digits: re-orthonormalised here (iTowns uses them as they are; the change is
  // below 1e-5, far below a pixel), so that camera validation need not accept a defect.
  r.camFromPano = orthonormalize(mat3FromRowMajor(rot.data()));
  const auto pos = nums(j, "position", 3);
  r.positionInPano = {pos[0], pos[1], pos[2]};
  const auto proj = nums(j, "projection", 9);
  r.focal = {proj[0], proj[4]};
  r.principal = {proj[2], proj[5]};
  if (proj[1] != 0.0) throw InputError("projection: skew is not supported (expected 0 at [0][1])");
  const auto size = nums(j, "size", 2);
  for (double s : size)
    if (!(s >= 1 && s <= kMaxImageSide) || s != std::floor(s))
      throw InputError("size: expected two positive integers up to " + std::to_string(int(kMaxImageSide)) +
                       " (pixels), got " + std::to_string(s));
  r.width = int(size[0]);
  r.height = int(size[1]);
  if (j.contains("distortion") && !j["distortion"].is_null()) {
    const json& d = j["distortion"];
    LensDistortion rd;
    const auto pps = nums(d, "pps", 2);
    rd.center = {pps[0], pps[1]};
    const auto poly = nums(d, "poly357", 3);
    rd.c3 = poly[0];
    rd.c5 = poly[1];
    rd.c7 = poly[2];
    if (d.contains("l1l2") || d.contains("etats")) {
      // The equilinear fish-eye (iTowns' projective_texturing shader): normalised by etats, the
      // polynomial over the angle, affine terms l1l2. iTowns applies them in its y-up texture frame
      // (pps.y flipped to H - pps.y); in histoview's y-down pixels the affine term reads
      // (l1 x - l2 y, -l2 x), which is what hv::LensDistortion implements. iTowns checks no `limit`
      // on this branch; the domain is fitted to the profile and the depth map's reach instead.
      const auto l = nums(d, "l1l2", 2);
      const double etats = num(d, "etats");
      if (!(etats > 0.0)) throw InputError("distortion.etats: expected a positive focal length (pixels)");
      rd.model = LensDistortion::Model::Fisheye;
      rd.scale = {etats, etats};
      rd.l1 = l[0];
      rd.l2 = l[1];
    } else {
      const double limit = d.contains("limit") ? num(d, "limit") : 1e15;
      if (limit <= 0.0) throw InputError("distortion.limit: expected a positive radius");
      rd.r2max = limit * limit;
    }
    r.distortion = rd;
  }
  if (j.contains("mask") && j["mask"].is_string()) r.mask = j["mask"].get<std::string>();
  return r;
}

std::string replaceAll(std::string s, const std::string& what, const std::string& with) {
  for (size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + with.size())) s.replace(p, what.size(), with);
  return s;
}

std::string resolve(const std::string& baseDir, const std::string& p) {
  if (p.empty() || fs::path(p).is_absolute()) return p;
  return (fs::path(baseDir) / p).lexically_normal().string();
}

}  // namespace

std::vector<Photo> readITownsCameras(const ITownsSource& src, Diagnostics& diag, bool checkImageFiles) {
  const json calib = readJson(src.calibration, diag);
  if (!calib.is_array()) throw InputError(src.calibration + ": expected an array of cameras");
  std::vector<RigCamera> rig;
  for (size_t i = 0; i < calib.size(); ++i) {
    try {
      RigCamera r = parseRigCamera(calib[i]);
      for (const RigCamera& other : rig)
        if (other.id == r.id)
          throw InputError("id '" + r.id + "': duplicate camera id in the rig (the first is kept)");
      rig.push_back(std::move(r));
    } catch (const InputError& e) {
      diag.error(src.calibration + ": camera #" + std::to_string(i) + ": " + e.what() + " (camera skipped)");
    }
  }
  const json geo = readJson(src.orientations, diag);
  if (!geo.is_object() || !geo.contains("features") || !geo["features"].is_array())
    throw InputError(src.orientations + ": expected a GeoJSON FeatureCollection");

  // Image patterns: one string, or a JSON file {"patterns": {panoId: pattern}}.
  std::string pattern = src.images;
  json perPano;
  const std::string imageDir =
      src.baseDir.empty() ? fs::path(src.orientations).parent_path().string() : src.baseDir;
  if (fs::path(src.images).extension() == ".json" && isRegularFile(src.images)) {
    const json p = readJson(src.images, diag);
    if (!p.contains("patterns") || !p["patterns"].is_object())
      throw InputError(src.images + ": patterns: expected an object of panorama id -> pattern");
    perPano = p["patterns"];
  }
  std::vector<std::string> missingMasks;  // warned once per rig camera, not per panorama

  std::vector<Photo> out;
  std::set<std::string> panoramas, ids;  // the first of a duplicate is kept
  for (size_t f = 0; f < geo["features"].size(); ++f) {
    const json& feature = geo["features"][f];
    std::string panoId = "#" + std::to_string(f);
    try {
      if (!feature.contains("properties") || !feature["properties"].is_object())
        throw InputError("properties: expected an object");
      const json& p = feature["properties"];
      panoId = idString(p);
      if (!panoramas.insert(panoId).second)
        throw InputError("duplicate panorama id (the first feature with it is kept)");
      glm::dvec3 position;
      if (p.contains("easting")) {
        position = {num(p, "easting"), num(p, "northing"), num(p, "altitude")};
      } else {
        if (!feature.contains("geometry") || !feature["geometry"].is_object())
          throw InputError("geometry: expected a Point");
        const auto c = nums(feature["geometry"], "coordinates", 3);
        position = {c[0], c[1], c[2]};
      }
      if (p.contains("omega") || p.contains("phi") || p.contains("kappa"))
        throw InputError("omega/phi/kappa attitudes are not supported by this version (expected roll/pitch/heading)");
      const double deg = M_PI / 180.0;
      const glm::dmat3 worldFromPano =
          rotY(-num(p, "roll") * deg) * rotX(-num(p, "pitch") * deg) * rotZ(-num(p, "heading") * deg);
      std::string panoPattern = pattern;
      if (!perPano.is_null()) {
        if (!perPano.contains(panoId) || !perPano[panoId].is_string())
          throw InputError(src.images + ": patterns." + panoId + ": no image pattern for this panorama");
        panoPattern = perPano[panoId].get<std::string>();
      }
      for (const RigCamera& r : rig) {
        Photo photo;
        Camera& cam = photo.camera;
        const std::string file = replaceAll(replaceAll(panoPattern, "{panoId}", panoId), "{cameraId}", r.id);
        photo.imagePath = resolve(imageDir, file);
        cam.id = fs::path(file).stem().string();
        cam.width = r.width;
        cam.height = r.height;
        cam.center = position + worldFromPano * r.positionInPano;
        cam.camFromWorld = r.camFromPano * glm::transpose(worldFromPano);
        cam.focal = r.focal;
        cam.principal = r.principal;
        cam.distortion = r.distortion;
        if (!r.mask.empty()) photo.maskPath = resolve(imageDir, r.mask);  // page-relative, like the images
        if (p.contains("date") && p["date"].is_string()) photo.date = p["date"].get<std::string>();
        try {
          validateCamera(cam);
          if (ids.count(cam.id))
            throw InputError("camera '" + cam.id + "': duplicate camera id (its image name " + file +
                             " is another camera's too; the first is kept)");
          fitLensDomain(cam, src.calibration, diag);
          if (checkImageFiles && !isRegularFile(photo.imagePath))
            throw InputError("camera '" + cam.id + "': image: " + notRegularFileReason(photo.imagePath) + ": " +
                             photo.imagePath);
          if (!photo.maskPath.empty() && !isRegularFile(photo.maskPath)) {
            if (std::find(missingMasks.begin(), missingMasks.end(), r.id) == missingMasks.end()) {
              missingMasks.push_back(r.id);
              diag.warn(src.calibration + ": camera " + r.id + ": mask: " + notRegularFileReason(photo.maskPath) +
                        ": " + photo.maskPath +
                        " (its images are used without a mask)");
            }
            photo.maskPath.clear();
          }
          ids.insert(cam.id);
          out.push_back(photo);
        } catch (const InputError& e) {
          diag.error(src.orientations + ": panorama " + panoId + ": " + e.what() + " (camera skipped)");
        }
      }
    } catch (const InputError& e) {
      diag.error(src.orientations + ": panorama " + panoId + ": " + e.what() + " (panorama skipped)");
    }
  }
  return out;
}

}  // namespace hv
