#include "hv/viewer/view_state.h"

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace hv::viewer {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

CameraPose poseOf(const Camera& camera) {
  CameraPose p;
  p.center = camera.center;
  p.camFromWorld = glm::normalize(glm::quat_cast(camera.camFromWorld));
  if (p.camFromWorld.w < 0.0) p.camFromWorld = -p.camFromWorld;  // one of the two signs, for stable links
  p.fovYDeg = 2.0 * std::atan(camera.height / 2.0 / camera.focal.y) * 180.0 / kPi;
  return p;
}

Camera cameraAt(const CameraPose& pose, int width, int height, const std::string& id) {
  Camera c;
  c.id = id;
  c.width = width;
  c.height = height;
  c.center = pose.center;
  c.camFromWorld = glm::mat3_cast(glm::normalize(pose.camFromWorld));
  const double f = height / 2.0 / std::tan(pose.fovYDeg * kPi / 360.0);
  c.focal = {f, f};
  c.principal = {width / 2.0, height / 2.0};
  return c;
}

std::string formatPose(const CameraPose& p) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "%.4f,%.4f,%.4f,%.8f,%.8f,%.8f,%.8f,%.6f", p.center.x, p.center.y, p.center.z,
                p.camFromWorld.w, p.camFromWorld.x, p.camFromWorld.y, p.camFromWorld.z, p.fovYDeg);
  return buf;
}

CameraPose parsePose(std::string_view text, const std::string& what) {
  const std::string expected = what +
                               ": expected eight numbers x,y,z,qw,qx,qy,qz,fov (the camera centre, its rotation "
                               "as a quaternion, the vertical field of view in degrees), got '" +
                               std::string(text) + "'";
  double v[8];
  std::size_t at = 0;
  for (int i = 0; i < 8; ++i) {
    const std::size_t comma = i < 7 ? text.find(',', at) : text.size();
    if (comma == std::string_view::npos) throw std::invalid_argument(expected);
    const std::string field(text.substr(at, comma - at));
    char* end = nullptr;
    v[i] = std::strtod(field.c_str(), &end);
    if (field.empty() || end != field.c_str() + field.size() || !std::isfinite(v[i]))
      throw std::invalid_argument(expected);
    at = comma + 1;
  }
  CameraPose p;
  p.center = {v[0], v[1], v[2]};
  const glm::dquat q(v[3], v[4], v[5], v[6]);
  if (!(glm::length(q) > 1e-9)) throw std::invalid_argument(what + ": the rotation quaternion is zero");
  p.camFromWorld = glm::normalize(q);
  if (!(v[7] > 0.0 && v[7] < 180.0))
    throw std::invalid_argument(what + ": the field of view must be in (0, 180) degrees, got " + std::to_string(v[7]));
  p.fovYDeg = v[7];
  return p;
}

std::string urlEncode(std::string_view text) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isalnum(c) || c == '-' || c == '_' || c == '.' || c == '~' || c == ',' || c == ':') {
      out += char(c);  // ',' and ':' are allowed in a query as they are (RFC 3986 sub-delims, pchar)
    } else {
      out += '%';
      out += hex[c >> 4];
      out += hex[c & 15];
    }
  }
  return out;
}

std::string urlDecode(std::string_view text, const std::string& what) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '+') {
      out += ' ';
    } else if (text[i] == '%') {
      auto digit = [](char c) {
        return c >= '0' && c <= '9'   ? c - '0'
               : c >= 'a' && c <= 'f' ? c - 'a' + 10
               : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                      : -1;
      };
      const int hi = i + 2 < text.size() ? digit(text[i + 1]) : -1;
      const int lo = i + 2 < text.size() ? digit(text[i + 2]) : -1;
      if (hi < 0 || lo < 0)
        throw std::invalid_argument(what + ": expected two hexadecimal digits after '%' at character " +
                                    std::to_string(i));
      out += char(hi * 16 + lo);
      i += 2;
    } else {
      out += text[i];
    }
  }
  return out;
}

std::string encodeViewState(const ViewState& state) {
  std::string q;
  if (state.pose) q = "pose=" + urlEncode(formatPose(*state.pose));
  for (const auto& [name, value] : state.params) {
    if (!q.empty()) q += '&';
    q += urlEncode(name) + "=" + urlEncode(value);
  }
  return q;
}

ViewState decodeViewState(std::string_view query) {
  if (!query.empty() && query.front() == '?') query.remove_prefix(1);
  ViewState s;
  std::size_t at = 0;
  while (at <= query.size()) {
    std::size_t amp = query.find('&', at);
    if (amp == std::string_view::npos) amp = query.size();
    const std::string_view pair = query.substr(at, amp - at);
    at = amp + 1;
    if (pair.empty()) continue;
    const std::size_t eq = pair.find('=');
    const std::string name = urlDecode(pair.substr(0, eq));
    const std::string value = eq == std::string_view::npos ? std::string() : urlDecode(pair.substr(eq + 1), name);
    if (name == "pose") {
      s.pose = parsePose(value, "pose");
      continue;
    }
    bool replaced = false;
    for (auto& p : s.params)
      if (p.first == name) p.second = value, replaced = true;  // the last of a repeated name
    if (!replaced) s.params.emplace_back(name, value);
  }
  return s;
}

}  // namespace hv::viewer
