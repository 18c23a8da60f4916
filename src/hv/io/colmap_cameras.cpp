#include "hv/io/colmap_cameras.h"

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
  std::optional<RadialDistortion> distortion;
};

std::vector<double> readNumbers(std::istringstream& in, size_t n, const std::string& what) {
  std::vector<double> v(n);
  for (auto& x : v)
    if (!(in >> x) || !std::isfinite(x)) throw InputError(what + ": expected " + std::to_string(n) + " numbers");
  return v;
}

ColmapCamera parseCamera(const std::string& model, std::istringstream& in) {
  ColmapCamera c;
  if (!(in >> c.width >> c.height) || c.width <= 0 || c.height <= 0)
    throw InputError("WIDTH HEIGHT: expected two positive integers");
  auto radial = [&](double f, double k1, double k2) {
    RadialDistortion d;
    d.center = c.principal;
    d.c3 = k1 / (f * f);
    d.c5 = k2 / (f * f * f * f);
    d.r2max = monotonicRadius2(d.c3, d.c5, 1e30);
    if (!d.isIdentity()) c.distortion = d;
  };
  if (model == "SIMPLE_PINHOLE") {
    const auto p = readNumbers(in, 3, "PARAMS (f, cx, cy)");
    c.focal = {p[0], p[0]};
    c.principal = {p[1], p[2]};
  } else if (model == "PINHOLE") {
    const auto p = readNumbers(in, 4, "PARAMS (fx, fy, cx, cy)");
    c.focal = {p[0], p[1]};
    c.principal = {p[2], p[3]};
  } else if (model == "SIMPLE_RADIAL") {
    const auto p = readNumbers(in, 4, "PARAMS (f, cx, cy, k)");
    c.focal = {p[0], p[0]};
    c.principal = {p[1], p[2]};
    radial(p[0], p[3], 0.0);
  } else if (model == "RADIAL") {
    const auto p = readNumbers(in, 5, "PARAMS (f, cx, cy, k1, k2)");
    c.focal = {p[0], p[0]};
    c.principal = {p[1], p[2]};
    radial(p[0], p[3], p[4]);
  } else {
    throw InputError("MODEL: " + model +
                     " is not supported by this version (expected SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL or RADIAL)");
  }
  return c;
}

// Lines that are neither empty nor comments, with their line numbers.
std::vector<std::pair<int, std::string>> dataLines(const std::string& path, bool keepEmpty) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open file");
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

double monotonicRadius2(double c3, double c5, double fallback) {
  // d/dr [r (1 + c3 r^2 + c5 r^4)] = 1 + 3 c3 s + 5 c5 s^2 with s = r^2: the smallest positive root.
  const double a = 5.0 * c5, b = 3.0 * c3, c = 1.0;
  double root = fallback;
  if (a == 0.0) {
    if (b < 0.0) root = -c / b;
  } else {
    const double disc = b * b - 4.0 * a * c;
    if (disc >= 0.0) {
      const double s1 = (-b - std::sqrt(disc)) / (2.0 * a), s2 = (-b + std::sqrt(disc)) / (2.0 * a);
      for (double s : {s1, s2})
        if (s > 0.0) root = std::min(root, s);
    }
  }
  return root;
}

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
      if (cam.distortion && cam.distortion->r2max < 1e29) {
        double corner2 = 0.0;
        for (const glm::dvec2 corner : {glm::dvec2(0.0), glm::dvec2(cam.width, 0.0), glm::dvec2(0.0, cam.height),
                                        glm::dvec2(cam.width, cam.height)})
          corner2 = std::max(corner2, glm::dot(corner - cam.principal, corner - cam.principal));
        if (cam.distortion->r2max < corner2)
          diag.warn(camerasPath + ":" + std::to_string(lineNo) + ": camera " + std::to_string(id) +
                    ": the radial polynomial turns back before the image corners; its domain is cut there");
      }
      cameras[id] = cam;
    } catch (const InputError& e) {
      diag.error(camerasPath + ":" + std::to_string(lineNo) + ": camera " + std::to_string(id) + ": " + e.what() +
                 " (camera skipped)");
    }
  }
  // images.txt: two lines per image, the second (2D points) possibly empty.
  const auto lines = dataLines(imagesPath, true);
  std::vector<Photo> out;
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
      p.imagePath = (fs::path(imageDir) / name).lexically_normal().string();
      if (checkImageFiles && !fs::is_regular_file(p.imagePath)) throw InputError("NAME: file not found: " + p.imagePath);
      out.push_back(p);
    } catch (const InputError& e) {
      diag.error(where + ": image " + name + ": " + e.what() + " (image skipped)");
    }
  }
  return out;
}

}  // namespace hv
