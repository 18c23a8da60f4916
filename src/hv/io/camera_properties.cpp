#include "hv/io/camera_properties.h"

#include "hv/camera/camera.h"
#include "hv/util/dates.h"
#include "hv/util/diagnostics.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <string>

namespace hv {

std::optional<double> parseNumber(std::string_view text) {
  auto space = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r'; };
  while (!text.empty() && space(text.front())) text.remove_prefix(1);
  while (!text.empty() && space(text.back())) text.remove_suffix(1);
  if (!text.empty() && text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  double v = 0;
#if defined(__EMSCRIPTEN__)
  // Emscripten's libc++ has no floating-point from_chars: strtod (correctly rounded, "C" locale)
  // on the characters from_chars would take (no hexadecimal, no inf or nan).
  if (text.find_first_not_of("0123456789+-.eE") != std::string_view::npos) return std::nullopt;
  const std::string copy(text);
  char* end = nullptr;
  v = std::strtod(copy.c_str(), &end);
  if (end != copy.c_str() + copy.size() || !std::isfinite(v)) return std::nullopt;
#else
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) return std::nullopt;
#endif
  return v;
}

std::optional<std::vector<double>> parseNumberList(std::string_view text) {
  auto space = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r'; };
  while (!text.empty() && space(text.front())) text.remove_prefix(1);
  while (!text.empty() && space(text.back())) text.remove_suffix(1);
  if (text.size() < 2) return std::nullopt;
  const char open = text.front(), close = text.back();
  if (!((open == '{' && close == '}') || (open == '[' && close == ']'))) return std::nullopt;
  text = text.substr(1, text.size() - 2);
  std::vector<double> out;
  const bool blank = std::all_of(text.begin(), text.end(), space);
  if (blank) return out;
  while (true) {
    const std::size_t comma = text.find(',');
    const std::optional<double> v = parseNumber(text.substr(0, comma));
    if (!v) return std::nullopt;
    out.push_back(*v);
    if (comma == std::string_view::npos) break;
    text.remove_prefix(comma + 1);
  }
  return out;
}

namespace {

constexpr std::size_t kDistortionNumbers = 12;

std::string clipped(const std::string& text) { return text.size() > 80 ? text.substr(0, 80) + "..." : text; }

// A property as text (id, paths, date, model) as the layer writes it, empty when missing.
std::string textProperty(const CameraProperty& v) {
  return v.kind == CameraProperty::Kind::NumberList || v.kind == CameraProperty::Kind::Missing ? std::string() : v.text;
}

double realProperty(const CameraProperty& v, const char* name) {
  switch (v.kind) {
    case CameraProperty::Kind::Missing:
      throw InputError(std::string(name) + ": missing (expected a number)");
    case CameraProperty::Kind::Text: {
      const std::optional<double> n = parseNumber(v.text);
      if (!n) throw InputError(std::string(name) + ": expected a number, got \"" + clipped(v.text) + "\"");
      return *n;
    }
    case CameraProperty::Kind::Number:
      if (!std::isfinite(v.number)) throw InputError(std::string(name) + ": not finite");
      return v.number;
    default:
      throw InputError(std::string(name) + ": expected a number, got " + (v.type.empty() ? "a list" : v.type));
  }
}

int intProperty(const CameraProperty& v, const char* name) {
  const double n = realProperty(v, name);
  if (n != std::floor(n) || n < 1 || n > 1e9)
    throw InputError(std::string(name) + ": expected a positive whole number of pixels");
  return int(n);
}

// Empty when missing.
std::vector<double> realListProperty(const CameraProperty& v, const char* name) {
  switch (v.kind) {
    case CameraProperty::Kind::Missing:
      return {};
    case CameraProperty::Kind::NumberList:
      return v.list;
    case CameraProperty::Kind::Text: {
      std::optional<std::vector<double>> list = parseNumberList(v.text);
      if (!list)
        throw InputError(std::string(name) + ": expected a list of numbers, \"{a,b,...}\" or \"[a,b,...]\", got \"" +
                         clipped(v.text) + "\"");
      return std::move(*list);
    }
    default:
      throw InputError(std::string(name) + ": expected a list of numbers, got a field of type " + v.type);
  }
}

LensDistortion distortionFrom(const std::string& model, const std::vector<double>& v) {
  LensDistortion d;
  if (model == "polynomial")
    d.model = LensDistortion::Model::Polynomial;
  else if (model == "fisheye")
    d.model = LensDistortion::Model::Fisheye;
  else
    throw InputError("distortion_model: expected \"polynomial\", \"fisheye\" or NULL, got \"" + model + "\"");
  if (v.size() != kDistortionNumbers)
    throw InputError("distortion: expected " + std::to_string(kDistortionNumbers) + " numbers, got " +
                     std::to_string(v.size()));
  d.center = {v[0], v[1]};
  d.scale = {v[2], v[3]};
  d.c3 = v[4], d.c5 = v[5], d.c7 = v[6], d.p1 = v[7], d.p2 = v[8], d.l1 = v[9], d.l2 = v[10], d.r2max = v[11];
  return d;
}

}  // namespace

Photo decodeCameraProperties(const CameraPropertyLookup& property, const std::function<glm::dvec3()>& point) {
  Photo p;
  Camera& c = p.camera;
  c.id = textProperty(property("id"));
  if (c.id.empty()) throw InputError("id: missing (expected the camera's name)");
  c.width = intProperty(property("width"), "width");
  c.height = intProperty(property("height"), "height");
  if (const CameraProperty x = property("centre_x"); x.kind != CameraProperty::Kind::Missing) {
    c.center = {realProperty(x, "centre (x)"), realProperty(property("centre_y"), "centre (y)"),
                realProperty(property("centre_z"), "centre (z)")};
  } else {
    c.center = point();
    if (!std::isfinite(c.center.x) || !std::isfinite(c.center.y) || !std::isfinite(c.center.z))
      throw InputError("centre: not finite");
  }
  c.focal = {realProperty(property("focal_x"), "focal_x"), realProperty(property("focal_y"), "focal_y")};
  c.principal = {realProperty(property("principal_x"), "principal_x"),
                 realProperty(property("principal_y"), "principal_y")};
  c.skew = realProperty(property("skew"), "skew");
  const std::vector<double> rot = realListProperty(property("cam_from_world"), "cam_from_world");
  if (rot.size() != 9)
    throw InputError("cam_from_world: expected 9 numbers (row-major), got " + std::to_string(rot.size()));
  c.camFromWorld = mat3FromRowMajor(rot.data());
  const std::string model = textProperty(property("distortion_model"));
  if (!model.empty()) c.distortion = distortionFrom(model, realListProperty(property("distortion"), "distortion"));
  p.imagePath = textProperty(property("image"));
  p.maskPath = textProperty(property("mask"));
  p.date = textProperty(property("date"));
  if (!p.date.empty() && !parseDate(p.date))
    throw InputError("date: expected an ISO 8601 date (YYYY, YYYY-MM, YYYY-MM-DD), got \"" + p.date + "\"");
  const std::vector<double> gain = realListProperty(property("colour_gain"), "colour_gain"),
                            offset = realListProperty(property("colour_offset"), "colour_offset");
  if (!gain.empty() || !offset.empty()) {
    if (gain.size() != 3 || offset.size() != 3) throw InputError("colour_gain/colour_offset: expected 3 numbers each");
    p.colour.gain = {gain[0], gain[1], gain[2]};
    p.colour.offset = {offset[0], offset[1], offset[2]};
  }
  Camera probe = c;
  validateCamera(probe);
  return p;
}

}  // namespace hv
