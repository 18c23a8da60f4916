#include "hv/io/native/ply_points.h"

#include "hv/io/native/private/byte_io.h"
#include "hv/util/diagnostics.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <string_view>
#include <vector>

namespace hv {
namespace {

enum class Type { I8, U8, I16, U16, I32, U32, F32, F64 };

std::optional<Type> typeNamed(std::string_view s) {
  if (s == "char" || s == "int8") return Type::I8;
  if (s == "uchar" || s == "uint8") return Type::U8;
  if (s == "short" || s == "int16") return Type::I16;
  if (s == "ushort" || s == "uint16") return Type::U16;
  if (s == "int" || s == "int32") return Type::I32;
  if (s == "uint" || s == "uint32") return Type::U32;
  if (s == "float" || s == "float32") return Type::F32;
  if (s == "double" || s == "float64") return Type::F64;
  return std::nullopt;
}

std::size_t sizeOf(Type t) {
  switch (t) {
    case Type::I8: case Type::U8: return 1;
    case Type::I16: case Type::U16: return 2;
    case Type::I32: case Type::U32: case Type::F32: return 4;
    case Type::F64: return 8;
  }
  return 0;
}

bool isFloat(Type t) { return t == Type::F32 || t == Type::F64; }

double loadAs(Type t, const std::uint8_t* p, bool bigEndian) {
  switch (t) {
    case Type::I8: return double(std::int8_t(*p));
    case Type::U8: return double(*p);
    case Type::I16: return bytes::load<std::int16_t>(p, bigEndian);
    case Type::U16: return bytes::load<std::uint16_t>(p, bigEndian);
    case Type::I32: return bytes::load<std::int32_t>(p, bigEndian);
    case Type::U32: return bytes::load<std::uint32_t>(p, bigEndian);
    case Type::F32: return bytes::load<float>(p, bigEndian);
    case Type::F64: return bytes::load<double>(p, bigEndian);
  }
  return 0.0;
}

struct Property {
  std::string name;
  Type type = Type::F32;
  std::optional<Type> listCount;  // set for list properties
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
};

enum class Format { Ascii, BinaryLE, BinaryBE };

// What each vertex property feeds, by its index in the element.
enum class Role { None, X, Y, Z, NX, NY, NZ, R, G, B, Intensity, Class };

Role roleOf(const std::string& n) {
  static const std::pair<const char*, Role> names[] = {
      {"x", Role::X},          {"y", Role::Y},           {"z", Role::Z},
      {"nx", Role::NX},        {"ny", Role::NY},         {"nz", Role::NZ},
      {"red", Role::R},        {"green", Role::G},       {"blue", Role::B},
      {"diffuse_red", Role::R}, {"diffuse_green", Role::G}, {"diffuse_blue", Role::B},
      {"intensity", Role::Intensity}, {"scalar_intensity", Role::Intensity},
      {"classification", Role::Class}, {"scalar_classification", Role::Class}};
  for (const auto& [name, role] : names)
    if (n == name) return role;
  return Role::None;
}

class PlyParser {
 public:
  PlyParser(const std::uint8_t* data, std::size_t size, std::string name) : d_(data), n_(size), name_(std::move(name)) {}

  // `wholeFile`: every element after the vertices is read too (and refused when malformed), as a
  // mesh reader would read the faces.
  PointCloud parse(bool wholeFile = false) {
    parseHeader();
    cloud_.sourcePath = name_;
    bool vertices = false;
    for (const Element& e : elements_) {
      if (e.name == "vertex" && !vertices) {
        readVertices(e);
        vertices = true;
        if (!wholeFile) return std::move(cloud_);
        continue;
      }
      skipElement(e);
    }
    if (!vertices) fail("header", "expected a \"vertex\" element");
    return std::move(cloud_);
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw InputError(inputMessage(name_, field, message));
  }

  // ---- header ---------------------------------------------------------------------------------
  void parseHeader() {
    const std::string_view all(reinterpret_cast<const char*>(d_), n_);
    std::size_t at = 0;
    auto nextLine = [&]() -> std::optional<std::string_view> {
      if (at >= all.size()) return std::nullopt;
      const std::size_t end = all.find('\n', at);
      if (end == std::string_view::npos) return std::nullopt;  // the header ends with a newline
      std::string_view line = all.substr(at, end - at);
      at = end + 1;
      if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
      return line;
    };
    const auto magic = nextLine();
    if (!magic || *magic != "ply") fail("header", "expected the magic line \"ply\" (not a PLY file)");
    bool haveFormat = false;
    int lineNo = 1;
    while (true) {
      const auto line = nextLine();
      ++lineNo;
      if (!line) fail("header", "expected \"end_header\" (truncated header?)");
      const std::vector<std::string> w = words(*line);
      const std::string where = "header line " + std::to_string(lineNo);
      if (w.empty()) continue;
      if (w[0] == "end_header") break;
      if (w[0] == "format") {
        if (w.size() != 3) fail(where, "expected \"format <ascii|binary_little_endian|binary_big_endian> 1.0\"");
        if (w[1] == "ascii") format_ = Format::Ascii;
        else if (w[1] == "binary_little_endian") format_ = Format::BinaryLE;
        else if (w[1] == "binary_big_endian") format_ = Format::BinaryBE;
        else fail(where, "unknown format \"" + w[1] + "\"");
        haveFormat = true;
      } else if (w[0] == "comment") {
        if (w.size() >= 3 && w[1] == "crs") {
          const std::size_t p = line->find("crs") + 3;
          std::string crs(line->substr(p));
          crs.erase(0, crs.find_first_not_of(" \t"));
          cloud_.crs = crs;
        }
      } else if (w[0] == "obj_info") {
      } else if (w[0] == "element") {
        if (w.size() != 3) fail(where, "expected \"element <name> <count>\"");
        Element e;
        e.name = w[1];
        const auto r = std::from_chars(w[2].data(), w[2].data() + w[2].size(), e.count);
        if (r.ec != std::errc() || r.ptr != w[2].data() + w[2].size())
          fail(where, "element " + w[1] + ": expected a non-negative count, got \"" + w[2] + "\"");
        elements_.push_back(std::move(e));
      } else if (w[0] == "property") {
        if (elements_.empty()) fail(where, "a property before any element");
        Property p;
        if (w.size() == 5 && w[1] == "list") {
          const auto c = typeNamed(w[2]);
          const auto t = typeNamed(w[3]);
          if (!c || !t || isFloat(*c)) fail(where, "expected \"property list <integer type> <type> <name>\"");
          p = {w[4], *t, *c};
        } else if (w.size() == 3) {
          const auto t = typeNamed(w[1]);
          if (!t) fail(where, "unknown property type \"" + w[1] + "\"");
          p = {w[2], *t, std::nullopt};
        } else {
          fail(where, "expected \"property <type> <name>\" or \"property list <type> <type> <name>\"");
        }
        elements_.back().properties.push_back(std::move(p));
      } else {
        fail(where, "unknown keyword \"" + w[0] + "\"");
      }
    }
    if (!haveFormat) fail("header", "expected a \"format\" line");
    body_ = at;
  }

  static std::vector<std::string> words(std::string_view line) {
    std::vector<std::string> out;
    std::size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
      const std::size_t start = i;
      while (i < line.size() && line[i] != ' ' && line[i] != '\t') ++i;
      if (i > start) out.emplace_back(line.substr(start, i - start));
    }
    return out;
  }

  // ---- body -----------------------------------------------------------------------------------
  // The next ASCII number; throws at the end of the data or on a non-number.
  double asciiValue(const std::string& field) {
    while (body_ < n_ && std::isspace(d_[body_])) ++body_;
    if (body_ >= n_) fail(field, "expected a number, the file ends (truncated?)");
    const char* begin = reinterpret_cast<const char*>(d_ + body_);
    const char* end = reinterpret_cast<const char*>(d_ + n_);
    double v = 0.0;
    auto r = std::from_chars(begin, end, v);
    if (r.ec == std::errc::result_out_of_range) {
      v = std::numeric_limits<double>::infinity();  // rejected where finiteness matters
      while (r.ptr < end && !std::isspace(static_cast<unsigned char>(*r.ptr))) ++r.ptr;
    } else if (r.ec != std::errc() || (r.ptr < end && !std::isspace(static_cast<unsigned char>(*r.ptr)))) {
      fail(field, "expected a number");
    }
    body_ += std::size_t(r.ptr - begin);
    return v;
  }

  double binaryValue(Type t, const std::string& field) {
    if (n_ - body_ < sizeOf(t)) fail(field, "the binary data end early (truncated file?)");
    const double v = loadAs(t, d_ + body_, format_ == Format::BinaryBE);
    body_ += sizeOf(t);
    return v;
  }

  double value(Type t, const std::string& field) {
    return format_ == Format::Ascii ? asciiValue(field) : binaryValue(t, field);
  }

  // A list's length: a non-negative integer, each item needing at least one byte.
  std::uint64_t listLength(const Property& p, const std::string& field) {
    const double c = value(*p.listCount, field);
    if (!(c >= 0.0) || c != std::floor(c) || c > double(n_ - body_))
      fail(field, "list length " + std::to_string(c) + " is negative, fractional or longer than the rest of the file");
    return std::uint64_t(c);
  }

  void skipList(const Property& p, const std::string& field) {
    const std::uint64_t len = listLength(p, field);
    if (format_ == Format::Ascii) {
      for (std::uint64_t i = 0; i < len; ++i) asciiValue(field);
    } else {
      if (len > (n_ - body_) / sizeOf(p.type)) fail(field, "the list runs past the end of the file");
      body_ += std::size_t(len * sizeOf(p.type));
    }
  }

  // Fails before allocating when `count` rows cannot fit in what is left of the file.
  void checkCount(const Element& e) const {
    std::size_t minRow = 0;
    for (const Property& p : e.properties) minRow += format_ == Format::Ascii ? 1 : sizeOf(p.listCount.value_or(p.type));
    if (minRow > 0 && e.count > (n_ - body_) / minRow)
      fail("element " + e.name, std::to_string(e.count) + " rows need at least " + std::to_string(minRow) +
                                    " bytes each, only " + std::to_string(n_ - body_) + " bytes are left (truncated file?)");
  }

  void skipElement(const Element& e) {
    checkCount(e);
    if (e.properties.empty()) return;
    const std::string field = "element " + e.name;
    for (std::uint64_t r = 0; r < e.count; ++r)
      for (const Property& p : e.properties) {
        if (p.listCount) skipList(p, field);
        else value(p.type, field);
      }
  }

  void readVertices(const Element& e) {
    std::vector<Role> roles;
    bool has[int(Role::Class) + 1] = {};
    for (const Property& p : e.properties) {
      const Role r = p.listCount ? Role::None : roleOf(p.name);
      roles.push_back(r);
      has[int(r)] = true;
    }
    for (Role r : {Role::X, Role::Y, Role::Z})
      if (!has[int(r)]) fail("element vertex", "expected the properties x, y and z");
    if (e.count > std::numeric_limits<std::uint32_t>::max())
      fail("element vertex", "more than 2^32 - 1 points are not supported");
    checkCount(e);
    const PointFields fields{.intensity = has[int(Role::Intensity)],
                             .classification = has[int(Role::Class)],
                             .rgb = has[int(Role::R)] || has[int(Role::G)] || has[int(Role::B)],
                             .normals = has[int(Role::NX)] && has[int(Role::NY)] && has[int(Role::NZ)]};
    cloud_.resize(std::size_t(e.count), fields);

    const std::string field = "element vertex";
    for (std::size_t i = 0; i < e.count; ++i) {
      glm::dvec3 pos{0.0};
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const Property& p = e.properties[k];
        if (p.listCount) {
          skipList(p, field);
          continue;
        }
        const double v = value(p.type, field);
        switch (roles[k]) {
          case Role::X: pos.x = v; break;
          case Role::Y: pos.y = v; break;
          case Role::Z: pos.z = v; break;
          case Role::NX: if (fields.normals) cloud_.normals[i].x = float(v); break;
          case Role::NY: if (fields.normals) cloud_.normals[i].y = float(v); break;
          case Role::NZ: if (fields.normals) cloud_.normals[i].z = float(v); break;
          case Role::R: cloud_.rgb[i].r = colour(p.type, v); break;
          case Role::G: cloud_.rgb[i].g = colour(p.type, v); break;
          case Role::B: cloud_.rgb[i].b = colour(p.type, v); break;
          case Role::Intensity: cloud_.intensity[i] = std::uint16_t(clampRound(v, 65535.0)); break;
          case Role::Class: cloud_.classification[i] = std::uint8_t(clampRound(v, 255.0)); break;
          case Role::None: break;
        }
      }
      if (!std::isfinite(pos.x) || !std::isfinite(pos.y) || !std::isfinite(pos.z))
        fail("vertex " + std::to_string(i), "expected finite x, y, z");
      cloud_.positions[i] = pos;
    }
  }

  static double clampRound(double v, double hi) { return std::isnan(v) ? 0.0 : std::round(std::clamp(v, 0.0, hi)); }

  static std::uint16_t colour(Type t, double v) {
    if (t == Type::U8 || t == Type::I8) return std::uint16_t(clampRound(v, 255.0) * 257.0);
    if (isFloat(t)) return std::uint16_t(clampRound(v * 65535.0, 65535.0));
    return std::uint16_t(clampRound(v, 65535.0));
  }

  const std::uint8_t* d_;
  std::size_t n_;
  std::string name_;
  Format format_ = Format::Ascii;
  std::vector<Element> elements_;
  std::size_t body_ = 0;
  PointCloud cloud_;
};

}  // namespace

void validatePly(const std::uint8_t* data, std::size_t size, const std::string& name) {
  (void)PlyParser(data, size, name).parse(true);
}

PointCloud parsePlyPoints(const std::uint8_t* data, std::size_t size, const std::string& name) {
  return PlyParser(data, size, name).parse();
}

PointCloud readPlyPoints(const std::string& path) {
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  return parsePlyPoints(bytes.data(), bytes.size(), path);
}

std::string plyPointBytes(const PointCloud& cloud) {
  const PointFields f = cloud.fields();
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\ncomment written by histoview\n";
  if (!cloud.crs.empty() && cloud.crs.find('\n') == std::string::npos) h << "comment crs " << cloud.crs << "\n";
  h << "element vertex " << cloud.size() << "\n";
  h << "property double x\nproperty double y\nproperty double z\n";
  if (f.normals) h << "property float nx\nproperty float ny\nproperty float nz\n";
  if (f.rgb) h << "property uchar red\nproperty uchar green\nproperty uchar blue\n";
  if (f.intensity) h << "property ushort intensity\n";
  if (f.classification) h << "property uchar classification\n";
  h << "end_header\n";
  std::string out = h.str();
  out.reserve(out.size() + cloud.size() * 48);
  for (std::size_t i = 0; i < cloud.size(); ++i) {
    for (int k = 0; k < 3; ++k) bytes::appendLE<double>(out, cloud.positions[i][k]);
    if (f.normals)
      for (int k = 0; k < 3; ++k) bytes::appendLE<float>(out, cloud.normals[i][k]);
    if (f.rgb)
      for (int k = 0; k < 3; ++k) out.push_back(char(std::lround(cloud.rgb[i][k] / 257.0)));
    if (f.intensity) bytes::appendLE<std::uint16_t>(out, cloud.intensity[i]);
    if (f.classification) out.push_back(char(cloud.classification[i]));
  }
  return out;
}

void writePlyPoints(const std::string& path, const PointCloud& cloud) {
  const std::string bytes = plyPointBytes(cloud);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), std::streamsize(bytes.size()));
  f.close();
  if (!f) throw std::runtime_error("cannot write " + path);
}

}  // namespace hv
