#include "hv/io/native/colmap_cameras.h"

#include "hv/util/input_file.h"

#include <glm/gtc/quaternion.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

struct ColmapCamera {
  int width = 0, height = 0;
  glm::dvec2 focal{1.0}, principal{0.0};
  std::optional<LensDistortion> distortion;
};

std::vector<double> readNumbers(std::istringstream& in, size_t n, const std::string& what) {
  std::vector<double> v(n);
  for (auto& x : v)
    if (!(in >> x) || !std::isfinite(x)) throw InputError(what + ": expected " + std::to_string(n) + " numbers");
  return v;
}

ColmapCamera parseCamera(const std::string& model, std::istringstream& in) {
  ColmapCamera c;
  // Capped as cameras.json's width and height: beyond it a size is a typing error, and its pixel
  // count would overflow the image loader's arithmetic.
  constexpr int kMaxSide = 65536;
  if (!(in >> c.width >> c.height) || c.width <= 0 || c.height <= 0 || c.width > kMaxSide || c.height > kMaxSide)
    throw InputError("WIDTH HEIGHT: expected two positive integers up to " + std::to_string(kMaxSide));
  // COLMAP distorts normalised coordinates u = (p - c) / f: exactly hv::LensDistortion with
  // centre c and scale f (its radial k1 k2 k3 are c3 c5 c7).
  auto lens = [&](LensDistortion::Model model, double k1, double k2, double k3, double p1, double p2) {
    LensDistortion d;
    d.model = model;
    d.center = c.principal;
    d.scale = c.focal;
    d.c3 = k1;
    d.c5 = k2;
    d.c7 = k3;
    d.p1 = p1;
    d.p2 = p2;
    if (!d.isIdentity()) c.distortion = d;
  };
  using Model = LensDistortion::Model;
  if (model == "SIMPLE_PINHOLE") {
    const auto p = readNumbers(in, 3, "PARAMS (f, cx, cy)");
    c.focal = {p[0], p[0]};
    c.principal = {p[1], p[2]};
  } else if (model == "PINHOLE") {
    const auto p = readNumbers(in, 4, "PARAMS (fx, fy, cx, cy)");
    c.focal = {p[0], p[1]};
    c.principal = {p[2], p[3]};
  } else if (model == "SIMPLE_RADIAL" || model == "SIMPLE_RADIAL_FISHEYE") {
    const auto p = readNumbers(in, 4, "PARAMS (f, cx, cy, k)");
    c.focal = {p[0], p[0]};
    c.principal = {p[1], p[2]};
    lens(model == "SIMPLE_RADIAL" ? Model::Polynomial : Model::Fisheye, p[3], 0.0, 0.0, 0.0, 0.0);
  } else if (model == "RADIAL" || model == "RADIAL_FISHEYE") {
    const auto p = readNumbers(in, 5, "PARAMS (f, cx, cy, k1, k2)");
    c.focal = {p[0], p[0]};
    c.principal = {p[1], p[2]};
    lens(model == "RADIAL" ? Model::Polynomial : Model::Fisheye, p[3], p[4], 0.0, 0.0, 0.0);
  } else if (model == "OPENCV") {
    const auto p = readNumbers(in, 8, "PARAMS (fx, fy, cx, cy, k1, k2, p1, p2)");
    c.focal = {p[0], p[1]};
    c.principal = {p[2], p[3]};
    lens(Model::Polynomial, p[4], p[5], 0.0, p[6], p[7]);
  } else if (model == "OPENCV_FISHEYE") {
    const auto p = readNumbers(in, 8, "PARAMS (fx, fy, cx, cy, k1, k2, k3, k4)");
    if (p[7] != 0.0) throw InputError("PARAMS: OPENCV_FISHEYE k4 (theta^9) is not supported (expected 0)");
    c.focal = {p[0], p[1]};
    c.principal = {p[2], p[3]};
    lens(Model::Fisheye, p[4], p[5], p[6], 0.0, 0.0);
    if (!c.distortion) lens(Model::Fisheye, 0.0, 0.0, 0.0, 0.0, 0.0);  // still a fish-eye
  } else {
    throw InputError("MODEL: " + model +
                     " is not supported by this version (expected SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, "
                     "OPENCV, SIMPLE_RADIAL_FISHEYE, RADIAL_FISHEYE or OPENCV_FISHEYE)");
  }
  return c;
}

// Lines that are neither empty nor comments, with their line numbers.
std::vector<std::pair<int, std::string>> dataLines(const std::string& path, bool keepEmpty) {
  std::istringstream in(readTextFile(path, kMaxTextBytes, "COLMAP model"));
  std::vector<std::pair<int, std::string>> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (!line.empty() && line[0] == '#') continue;
    if (line.empty() && !keepEmpty) continue;
    out.emplace_back(n, line);
  }
  return out;
}

}  // namespace

std::vector<Photo> readColmapModel(const std::string& modelDir, const std::string& imageDir, Diagnostics& diag,
                                   bool checkImageFiles) {
  const std::string camerasPath = (fs::path(modelDir) / "cameras.txt").string();
  const std::string imagesPath = (fs::path(modelDir) / "images.txt").string();
  std::map<long, ColmapCamera> cameras;
  for (const auto& [lineNo, text] : dataLines(camerasPath, false)) {
    std::istringstream in(text);
    long id = 0;
    std::string model;
    try {
      if (!(in >> id >> model)) throw InputError("expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS[]");
      ColmapCamera cam = parseCamera(model, in);
      if (!cameras.emplace(id, cam).second)
        throw InputError("duplicate CAMERA_ID (the first line with it is kept)");
    } catch (const InputError& e) {
      diag.error(camerasPath + ":" + std::to_string(lineNo) + ": camera " + std::to_string(id) + ": " + e.what() +
                 " (camera skipped)");
    }
  }
  // images.txt: two lines per image, the second (2D points) possibly empty.
  const auto lines = dataLines(imagesPath, true);
  std::vector<Photo> out;
  std::map<long, std::string> imageIds;        // IMAGE_ID -> where it was first
  std::map<std::string, std::string> names;    // camera id (the name's stem) -> where it was first
  for (size_t i = 0; i < lines.size(); ++i) {
    const auto& [lineNo, text] = lines[i];
    if (text.find_first_not_of(" \t") == std::string::npos) continue;
    std::istringstream in(text);
    long imageId = 0, cameraId = 0;
    double qw, qx, qy, qz, tx, ty, tz;
    std::string name;
    const std::string where = imagesPath + ":" + std::to_string(lineNo);
    ++i;  // skip the 2D points line
    if (!(in >> imageId >> qw >> qx >> qy >> qz >> tx >> ty >> tz >> cameraId >> name)) {
      diag.error(where + ": expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME (image skipped)");
      continue;
    }
    try {
      if (const auto [first, added] = imageIds.emplace(imageId, where); !added)
        throw InputError("IMAGE_ID " + std::to_string(imageId) + ": duplicate (first at " + first->second +
                         ", which is kept)");
      const auto it = cameras.find(cameraId);
      if (it == cameras.end()) throw InputError("CAMERA_ID " + std::to_string(cameraId) + ": no such camera");
      const double qn = std::sqrt(qw * qw + qx * qx + qy * qy + qz * qz);
      if (!(qn > 0.5 && qn < 2.0)) throw InputError("QW QX QY QZ: expected a unit quaternion");
      const glm::dquat q(qw / qn, qx / qn, qy / qn, qz / qn);  // glm: (w, x, y, z)
      Photo p;
      Camera& c = p.camera;
      c.id = fs::path(name).stem().string();
      c.width = it->second.width;
      c.height = it->second.height;
      c.camFromWorld = glm::mat3_cast(q);
      c.center = -(glm::transpose(c.camFromWorld) * glm::dvec3(tx, ty, tz));
      c.focal = it->second.focal;
      c.principal = it->second.principal;
      c.distortion = it->second.distortion;
      validateCamera(c);
      fitLensDomain(c, camerasPath, diag);
      p.imagePath = (fs::path(imageDir) / name).lexically_normal().string();
      if (checkImageFiles && !isRegularFile(p.imagePath))
        throw InputError("NAME: " + notRegularFileReason(p.imagePath) + ": " + p.imagePath);
      if (const auto [first, added] = names.emplace(c.id, where); !added)
        throw InputError("camera id '" + c.id + "' (the name's stem): duplicate (first at " + first->second +
                         ", which is kept)");
      out.push_back(p);
    } catch (const InputError& e) {
      diag.error(where + ": image " + name + ": " + e.what() + " (image skipped)");
    }
  }
  return out;
}

}  // namespace hv
