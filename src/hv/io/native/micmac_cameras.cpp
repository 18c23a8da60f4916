#include "hv/io/native/micmac_cameras.h"

#include "hv/util/input_file.h"

#include <pugixml.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace hv {
namespace {

namespace fs = std::filesystem;

// MicMac image positions have the top-left pixel's centre at (0, 0); histoview's at (0.5, 0.5).
constexpr double kMicmacToHvPixel = 0.5;

std::string readText(const std::string& path) {
  return readTextFile(path, kMaxTextBytes, "MicMac XML");
}

// "ExportAPERO/OrientationConique/Externe/Centre": where an element sits, for error messages.
std::string elementPath(pugi::xml_node node) {
  std::string out;
  for (; node && node.type() == pugi::node_element; node = node.parent())
    out = out.empty() ? std::string(node.name()) : std::string(node.name()) + "/" + out;
  return out;
}

std::string childPath(pugi::xml_node parent, const char* name) {
  const std::string p = elementPath(parent);
  return p.empty() ? name : p + "/" + name;
}

pugi::xml_document parseXml(const std::string& xml, const std::string& file) {
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_buffer(xml.data(), xml.size());
  if (!r)
    throw InputError(file + ": not valid XML: " + r.description() + " at offset " + std::to_string(r.offset));
  return doc;
}

pugi::xml_node need(pugi::xml_node parent, const char* name, const std::string& file, const std::string& what) {
  const pugi::xml_node n = parent.child(name);
  if (!n) throw InputError(file + ": " + childPath(parent, name) + ": missing, expected " + what);
  return n;
}

// Whitespace-separated finite numbers of an element's text.
std::vector<double> numbers(pugi::xml_node node) {
  std::vector<double> out;
  const std::string text = node.text().get();
  const char* p = text.data();
  const char* end = p + text.size();
  while (p < end) {
    while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    if (p == end) break;
    double v = 0.0;
    if (*p == '+') ++p;  // from_chars does not take a leading '+'
    const auto [next, ec] = std::from_chars(p, end, v);
    if (ec != std::errc() || !std::isfinite(v) || (next < end && !std::isspace(static_cast<unsigned char>(*next))))
      return {std::nan("")};  // a token that is not a finite number
    p = next;
    out.push_back(v);
  }
  return out;
}

std::vector<double> needNumbers(pugi::xml_node node, size_t n, const std::string& file, const std::string& what) {
  std::vector<double> v = numbers(node);
  if (v.size() != n || std::any_of(v.begin(), v.end(), [](double x) { return !std::isfinite(x); }))
    throw InputError(file + ": " + elementPath(node) + ": expected " + what + " (" + std::to_string(n) +
                     " finite number" + (n > 1 ? "s" : "") + "), got '" + node.text().get() + "'");
  return v;
}

glm::dvec2 needVec2(pugi::xml_node parent, const char* name, const std::string& file, const std::string& what) {
  const auto v = needNumbers(need(parent, name, file, what), 2, file, what);
  return {v[0], v[1]};
}

glm::dvec3 needVec3(pugi::xml_node parent, const char* name, const std::string& file, const std::string& what) {
  const auto v = needNumbers(need(parent, name, file, what), 3, file, what);
  return {v[0], v[1], v[2]};
}

bool allZero(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return x == 0.0; });
}

// The radial part of a distortion model: CDist and CoeffDist (k1 r^2 + k2 r^4 + ...).
struct Radial {
  glm::dvec2 centerMicmac{0.0};
  std::vector<double> coeffs;
  double usefulRadius = 0.0;  // 0: none given
};

Radial readRadial(pugi::xml_node model, const std::string& file) {
  Radial r;
  r.centerMicmac = needVec2(model, "CDist", file, "the distortion centre (x y, pixels)");
  for (pugi::xml_node c : model.children("CoeffDist")) {
    const auto v = needNumbers(c, 1, file, "a radial coefficient");
    r.coeffs.push_back(v[0]);
  }
  if (r.coeffs.size() > 3 && !allZero(std::vector<double>(r.coeffs.begin() + 3, r.coeffs.end())))
    throw InputError(file + ": " + childPath(model, "CoeffDist") + ": " + std::to_string(r.coeffs.size()) +
                     " radial coefficients; this version reads up to three (r^3, r^5, r^7)");
  r.coeffs.resize(3, 0.0);
  if (const pugi::xml_node ru = model.child("RayonUtile")) r.usefulRadius = needNumbers(ru, 1, file, "a radius")[0];
  return r;
}

bool hasPrefix(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

void checkKnownConv(pugi::xml_node parent, const std::string& file, bool& distC2M) {
  const pugi::xml_node kc = parent.child("KnownConv");
  if (!kc) return;
  const std::string conv = kc.text().get();
  if (conv == "eConvApero_DistM2C") return;
  if (conv == "eConvApero_DistC2M") {
    distC2M = true;
    return;
  }
  throw InputError(file + ": " + elementPath(kc) + ": " + conv +
                   " is not supported (expected eConvApero_DistM2C or eConvApero_DistC2M)");
}

void readCalibrationNode(pugi::xml_node cal, const std::string& file, Camera& camera, bool distC2M) {
  checkKnownConv(cal, file, distC2M);
  const glm::dvec2 pp = needVec2(cal, "PP", file, "the principal point (x y, pixels)");
  const double f = needNumbers(need(cal, "F", file, "the focal length (pixels)"), 1, file, "the focal length")[0];
  const glm::dvec2 size = needVec2(cal, "SzIm", file, "the image size (width height, pixels)");
  if (!(f > 0.0)) throw InputError(file + ": " + childPath(cal, "F") + ": expected a positive focal length");
  if (!(size.x >= 1.0 && size.y >= 1.0 && size.x < 1e6 && size.y < 1e6) || size != glm::floor(size))
    throw InputError(file + ": " + childPath(cal, "SzIm") + ": expected two positive integers");
  camera.width = static_cast<int>(size.x);
  camera.height = static_cast<int>(size.y);
  camera.focal = {f, f};
  camera.principal = pp + kMicmacToHvPixel;
  camera.skew = 0.0;

  // Distortion: one or more CalibDistortion elements (MicMac composes them); at most one may be
  // non-identity here.
  std::optional<Radial> radial;
  for (pugi::xml_node cd : cal.children("CalibDistortion")) {
    pugi::xml_node model = cd.first_child();
    while (model && model.type() != pugi::node_element) model = model.next_sibling();
    if (!model) throw InputError(file + ": " + elementPath(cd) + ": expected a distortion model (ModRad)");
    const std::string name = model.name();
    Radial r;
    if (name == "ModRad") {
      r = readRadial(model, file);
    } else if (name == "ModPhgrStd") {
      r = readRadial(need(model, "RadialePart", file, "the radial part (CDist, CoeffDist)"), file);
      for (const char* term : {"P1", "P2", "b1", "b2"}) {
        if (const pugi::xml_node t = model.child(term); t && !allZero(needNumbers(t, 1, file, "a number")))
          throw InputError(file + ": " + elementPath(t) +
                           ": non-zero decentric/affine terms are not supported by this version (radial only)");
      }
    } else {
      throw InputError(file + ": " + elementPath(model) + ": distortion model " + name +
                       " is not supported by this version (expected ModRad, or ModPhgrStd with zero P1 P2 b1 b2)");
    }
    if (allZero(r.coeffs)) continue;
    if (radial) throw InputError(file + ": " + elementPath(cd) + ": more than one non-identity distortion");
    if (distC2M)
      throw InputError(file + ": " + elementPath(model) +
                       ": distortion under eConvApero_DistC2M (camera to ideal) is not supported by this version");
    radial = r;
  }
  if (radial) {
    const glm::dvec2 center = radial->centerMicmac + kMicmacToHvPixel;
    const double r2max = radial->usefulRadius > 0.0 ? radial->usefulRadius * radial->usefulRadius : 1e30;
    camera.distortion =
        LensDistortion{.center = center, .c3 = radial->coeffs[0], .c5 = radial->coeffs[1], .c7 = radial->coeffs[2],
                         .r2max = r2max};
  } else {
    camera.distortion.reset();
  }
}

}  // namespace

void parseMicmacCalibration(const std::string& xml, const std::string& pathForErrors, Camera& camera) {
  const pugi::xml_document doc = parseXml(xml, pathForErrors);
  pugi::xml_node cal = doc.child("ExportAPERO").child("CalibrationInternConique");
  if (!cal) cal = doc.child("CalibrationInternConique");
  if (!cal) throw InputError(pathForErrors + ": ExportAPERO/CalibrationInternConique: missing, expected a MicMac "
                             "intrinsic calibration");
  readCalibrationNode(cal, pathForErrors, camera, false);
}

MicmacOrientation parseMicmacOrientation(const std::string& xml, const std::string& pathForErrors,
                                         const MicmacFileReader& readFile) {
  const std::string& file = pathForErrors;
  const pugi::xml_document doc = parseXml(xml, file);
  pugi::xml_node oc = doc.child("ExportAPERO").child("OrientationConique");
  if (!oc) oc = doc.child("OrientationConique");
  if (!oc) throw InputError(file + ": ExportAPERO/OrientationConique: missing, expected a MicMac orientation");

  MicmacOrientation out;
  Camera& cam = out.camera;
  bool distC2M = false;
  if (const pugi::xml_node conv = oc.child("ConvOri")) checkKnownConv(conv, file, distC2M);
  if (const pugi::xml_node tp = oc.child("TypeProj"); tp && std::string(tp.text().get()) != "eProjStenope")
    throw InputError(file + ": " + elementPath(tp) + ": " + tp.text().get() +
                     " is not supported (expected eProjStenope, a pinhole)");
  if (const pugi::xml_node ori = oc.child("OrIntImaM2C")) {
    const glm::dvec2 i00 = needVec2(ori, "I00", file, "a 2D offset");
    const glm::dvec2 v10 = needVec2(ori, "V10", file, "a 2D vector");
    const glm::dvec2 v01 = needVec2(ori, "V01", file, "a 2D vector");
    if (i00 != glm::dvec2(0.0) || v10 != glm::dvec2(1.0, 0.0) || v01 != glm::dvec2(0.0, 1.0))
      throw InputError(file + ": " + elementPath(ori) +
                       ": a non-identity interior orientation (scanned film) is not supported by this version "
                       "(expected I00 0 0, V10 1 0, V01 0 1)");
  }

  // Intrinsics: inline, or the FileInterne.
  if (const pugi::xml_node inl = oc.child("Interne")) {
    readCalibrationNode(inl, file, cam, distC2M);
  } else {
    const pugi::xml_node fi = need(oc, "FileInterne", file, "the calibration file name (or an inline Interne)");
    const std::string name = fi.text().get();
    if (name.empty()) throw InputError(file + ": " + elementPath(fi) + ": expected a file name");
    out.calibrationPath = name;
    const std::string text = readFile(name);
    try {
      parseMicmacCalibration(text, name, cam);
    } catch (const InputError& e) {
      throw InputError(std::string(e.what()) + " (calibration of " + file + ")");
    }
  }

  const pugi::xml_node ext = need(oc, "Externe", file, "the pose (Centre, ParamRotation)");
  checkKnownConv(ext, file, distC2M);
  cam.center = needVec3(ext, "Centre", file, "the camera centre (x y z)");
  const pugi::xml_node rot = need(ext, "ParamRotation", file, "the rotation (CodageMatr)");
  const pugi::xml_node matr = rot.child("CodageMatr");
  if (!matr) {
    const pugi::xml_node other = rot.first_child();
    throw InputError(file + ": " + childPath(rot, "CodageMatr") + ": missing, expected the rotation matrix L1 L2 L3" +
                     (other ? std::string(" (") + other.name() + " is not supported by this version)" : ""));
  }
  // L1..L3 are the rows of the camera -> world matrix (see the header); camFromWorld is its transpose.
  glm::dmat3 worldFromCam(1.0);
  for (int row = 0; row < 3; ++row) {
    const std::string name = "L" + std::to_string(row + 1);
    const auto v = needNumbers(need(matr, name.c_str(), file, "a matrix row (3 numbers)"), 3, file, "a matrix row");
    for (int col = 0; col < 3; ++col) worldFromCam[col][row] = v[col];
  }
  cam.camFromWorld = glm::transpose(worldFromCam);

  if (const pugi::xml_node nf = oc.child("NameFileImage")) out.imageName = nf.text().get();
  if (out.imageName.empty()) {
    std::string stem = fs::path(file).filename().string();
    if (hasPrefix(stem, "Orientation-")) stem = stem.substr(12);
    if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ".xml") == 0) stem.resize(stem.size() - 4);
    out.imageName = stem;
  }
  cam.id = fs::path(out.imageName).stem().string();
  if (cam.id.empty()) cam.id = out.imageName;
  try {
    validateCamera(cam, 1e-5);
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }

  if (const pugi::xml_node verif = oc.child("Verif")) {
    if (const pugi::xml_node tol = verif.child("Tol")) out.checkTolerance = needNumbers(tol, 1, file, "a tolerance")[0];
    for (pugi::xml_node a : verif.children("Appuis")) {
      MicmacCheckPoint p;
      if (const pugi::xml_node n = a.child("Num")) {
        const double num = needNumbers(n, 1, file, "a point number")[0];
        if (!(std::abs(num) < 1e9) || num != std::floor(num))
          throw InputError(file + ": " + elementPath(n) + ": expected an integer point number");
        p.num = static_cast<int>(num);
      }
      p.pixel = needVec2(a, "Im", file, "an image position (x y)") + kMicmacToHvPixel;
      p.world = needVec3(a, "Ter", file, "a terrain point (x y z)");
      out.checks.push_back(p);
    }
  }
  return out;
}

MicmacOrientation readMicmacOrientation(const std::string& path) {
  const fs::path oriDir = fs::path(path).parent_path();
  const fs::path projectDir = oriDir.parent_path();
  std::string resolved;
  auto reader = [&](const std::string& name) {
    const fs::path p(name);
    std::vector<fs::path> candidates;
    if (p.is_absolute()) {
      candidates.push_back(p);
    } else {
      candidates.push_back(projectDir / p);
      candidates.push_back(oriDir / p.filename());
    }
    for (const fs::path& c : candidates) {
      if (isRegularFile(c.string())) {
        resolved = c.lexically_normal().string();
        return readText(resolved);
      }
    }
    throw InputError(path + ": " + "ExportAPERO/OrientationConique/FileInterne: calibration file not found: " + name +
                     " (looked in " + projectDir.string() + " and " + oriDir.string() + ")");
  };
  MicmacOrientation o = parseMicmacOrientation(readText(path), path, reader);
  if (!resolved.empty()) o.calibrationPath = resolved;
  return o;
}

std::vector<Photo> readMicmacCameras(const std::string& oriDir, const std::string& imageDir, Diagnostics& diag,
                                     bool checkImageFiles) {
  std::error_code ec;
  if (!fs::is_directory(oriDir, ec)) throw InputError(oriDir + ": not a directory (expected a MicMac Ori- folder)");
  std::vector<std::string> files;
  // The error_code forms throughout: a link loop or an unreadable entry is one file left out, not
  // an exception that takes the whole folder down.
  fs::directory_iterator it(oriDir, ec), end;
  if (ec) throw InputError(oriDir + ": cannot list the folder: " + ec.message());
  for (; it != end; it.increment(ec)) {
    if (ec) {
      diag.error(oriDir + ": cannot list the folder further: " + ec.message());
      break;
    }
    const std::string name = it->path().filename().string();
    if (!hasPrefix(name, "Orientation-") || it->path().extension() != ".xml") continue;
    const std::string reason = notRegularFileReason(it->path().string());
    if (reason.empty()) files.push_back(it->path().string());
    else diag.error(it->path().string() + ": " + reason + " (camera skipped)");
  }
  std::sort(files.begin(), files.end());
  if (files.empty()) diag.warn(oriDir + ": no Orientation-*.xml file");
  std::vector<Photo> out;
  for (const std::string& f : files) {
    try {
      MicmacOrientation o = readMicmacOrientation(f);
      Photo p;
      p.imagePath = (fs::path(imageDir) / o.imageName).lexically_normal().string();
      if (checkImageFiles && !isRegularFile(p.imagePath))
        throw InputError(f + ": image " + o.imageName + ": " + notRegularFileReason(p.imagePath) + ": " + p.imagePath);
      p.camera = std::move(o.camera);
      fitLensDomain(p.camera, f, diag);
      out.push_back(std::move(p));
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (camera skipped)");
    }
  }
  return out;
}

std::map<std::string, glm::dvec3> readMicmacGroundPoints(const std::string& path) {
  const pugi::xml_document doc = parseXml(readText(path), path);
  const pugi::xml_node dico = doc.select_node("//DicoAppuisFlottant").node();
  if (!dico) throw InputError(path + ": DicoAppuisFlottant: missing, expected MicMac ground control points");
  std::map<std::string, glm::dvec3> out;
  for (pugi::xml_node a : dico.children("OneAppuisDAF")) {
    const std::string name = need(a, "NamePt", path, "the point name").text().get();
    out[name] = needVec3(a, "Pt", path, "a 3D point (x y z)");
  }
  return out;
}

std::map<std::string, std::map<std::string, glm::dvec2>> readMicmacImageMeasures(const std::string& path) {
  const pugi::xml_document doc = parseXml(readText(path), path);
  const pugi::xml_node set = doc.select_node("//SetOfMesureAppuisFlottants").node();
  if (!set) throw InputError(path + ": SetOfMesureAppuisFlottants: missing, expected MicMac image measures");
  std::map<std::string, std::map<std::string, glm::dvec2>> out;
  for (pugi::xml_node im : set.children("MesureAppuiFlottant1Im")) {
    const std::string image = need(im, "NameIm", path, "the image name").text().get();
    for (pugi::xml_node m : im.children("OneMesureAF1I")) {
      const std::string name = need(m, "NamePt", path, "the point name").text().get();
      out[image][name] = needVec2(m, "PtIm", path, "an image position (x y)") + kMicmacToHvPixel;
    }
  }
  return out;
}

}  // namespace hv
