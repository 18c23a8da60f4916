// Point Cloud tiles (pnts) of the 3D Tiles 1.0 specification: reading, with every field checked
// against the bytes it names, and writing (what `histoview points-tiles` produces).
#include "hv/io/tiles3d.h"

#include "hv/io/tiles3d_json.h"
#include "hv/util/diagnostics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

namespace hv {
namespace {

using nlohmann::json;
using tiles3d_json::numbers;
using tiles3d_json::shown;

}  // namespace

glm::vec3 octDecode16P(std::uint8_t xb, std::uint8_t yb) {
  double x = xb / 255.0 * 2.0 - 1.0, y = yb / 255.0 * 2.0 - 1.0;
  const double z = 1.0 - std::abs(x) - std::abs(y);
  if (z < 0.0) {
    const double ox = x;
    x = (1.0 - std::abs(y)) * (ox >= 0.0 ? 1.0 : -1.0);
    y = (1.0 - std::abs(ox)) * (y >= 0.0 ? 1.0 : -1.0);
  }
  return glm::vec3(glm::normalize(glm::dvec3(x, y, z)));
}

void octEncode16P(const glm::vec3& n, std::uint8_t& xb, std::uint8_t& yb) {
  const glm::dvec3 v(n);
  const double l1 = std::abs(v.x) + std::abs(v.y) + std::abs(v.z);
  double x = l1 > 0 ? v.x / l1 : 0.0, y = l1 > 0 ? v.y / l1 : 0.0;
  if (v.z < 0.0) {
    const double ox = x;
    x = (1.0 - std::abs(y)) * (ox >= 0.0 ? 1.0 : -1.0);
    y = (1.0 - std::abs(ox)) * (y >= 0.0 ? 1.0 : -1.0);
  }
  xb = std::uint8_t(std::lround((std::clamp(x, -1.0, 1.0) * 0.5 + 0.5) * 255.0));
  yb = std::uint8_t(std::lround((std::clamp(y, -1.0, 1.0) * 0.5 + 0.5) * 255.0));
}

glm::u16vec3 rgb565To16(std::uint16_t c) {
  auto scale = [](unsigned v, unsigned max) { return std::uint16_t((v * 65535u + max / 2) / max); };
  return {scale((c >> 11) & 31u, 31), scale((c >> 5) & 63u, 63), scale(c & 31u, 31)};
}

namespace {

std::uint32_t u32(const char* p) {
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;  // little-endian hosts (x86-64, WebAssembly)
}

struct FeatureTable {
  const json& doc;
  std::string_view binary;
  const std::string& url;
  std::size_t points = 0;

  // The bytes of a per-point semantic: byteOffset + stride * points within the binary body.
  const char* perPoint(const char* name, std::size_t stride, const char* layout) const {
    const std::string field = std::string("featureTable.") + name;
    const json& v = doc[name];
    if (!v.is_object() || !v.contains("byteOffset") || !v["byteOffset"].is_number_unsigned())
      throw InputError(inputMessage(
          url, field,
          std::string("expected {\"byteOffset\": n} (") + layout + " a point in the binary body), got " + shown(v)));
    const std::uint64_t offset = v["byteOffset"].get<std::uint64_t>();
    const std::uint64_t need = std::uint64_t(stride) * points;
    if (offset > binary.size() || need > binary.size() - offset)
      throw InputError(inputMessage(url, field + ".byteOffset",
                                    std::to_string(offset) + " + " + std::to_string(stride) +
                                        "·N (N = " + std::to_string(points) + ") = " + std::to_string(offset + need) +
                                        " bytes, past the binary body of " + std::to_string(binary.size()) + " bytes"));
    return binary.data() + offset;
  }

  // A global semantic of `n` float32 values: a JSON array, or {"byteOffset"} into the binary body.
  std::vector<double> global(const char* name, std::size_t n) const {
    const std::string field = std::string("featureTable.") + name;
    const json& v = doc[name];
    if (v.is_array()) return numbers(v, n, url, field, std::to_string(n) + " numbers");
    if (v.is_object() && v.contains("byteOffset") && v["byteOffset"].is_number_unsigned()) {
      const std::uint64_t offset = v["byteOffset"].get<std::uint64_t>();
      if (offset > binary.size() || 4 * n > binary.size() - offset)
        throw InputError(inputMessage(url, field + ".byteOffset",
                                      std::to_string(offset) + " + " + std::to_string(4 * n) +
                                          " bytes, past the binary body of " + std::to_string(binary.size()) +
                                          " bytes"));
      std::vector<double> out(n);
      for (std::size_t i = 0; i < n; ++i) {
        float f;
        std::memcpy(&f, binary.data() + offset + 4 * i, 4);
        if (!std::isfinite(f)) throw InputError(inputMessage(url, field, "expected finite numbers"));
        out[i] = f;
      }
      return out;
    }
    throw InputError(
        inputMessage(url, field, "expected " + std::to_string(n) + " numbers or {\"byteOffset\": n}, got " + shown(v)));
  }
};

// The per-point batch table (no BATCH_ID): "Classification" read into the cloud, when it is
// 0..255 integers for every point (a JSON array, or a binary SCALAR of an integer componentType);
// a malformed one is a note and the tile keeps its other fields. Other properties are named as
// ignored.
void readBatchTable(std::string_view text, std::string_view binary, const std::string& url, PntsTile& out) {
  while (!text.empty() && (text.back() == ' ' || text.back() == '\0')) text.remove_suffix(1);
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    out.notes.push_back(inputMessage(url, "batchTable", std::string("expected a JSON object: ") + e.what()));
    return;
  }
  if (!doc.is_object()) {
    out.notes.push_back(inputMessage(url, "batchTable", "expected a JSON object, got " + shown(doc)));
    return;
  }
  std::string ignored;
  for (auto it = doc.begin(); it != doc.end(); ++it)
    if (it.key() != "Classification") ignored += (ignored.empty() ? "" : ", ") + it.key();
  if (!ignored.empty()) out.notes.push_back(inputMessage(url, "batchTable", "ignored: " + ignored));
  if (!doc.contains("Classification")) return;
  const std::string field = "batchTable.Classification";
  const json& v = doc["Classification"];
  const std::size_t n = out.points.size();
  std::vector<std::uint8_t> classes(n);
  auto fail = [&](const std::string& what) { out.notes.push_back(inputMessage(url, field, what + "; not read")); };
  if (v.is_array()) {
    if (v.size() != n) return fail("expected " + std::to_string(n) + " classes (one a point), got " + shown(v));
    for (std::size_t i = 0; i < n; ++i) {
      if (!v[i].is_number_integer() || v[i].get<std::int64_t>() < 0 || v[i].get<std::int64_t>() > 255)
        return fail("point " + std::to_string(i) + ": expected an integer 0..255, got " + shown(v[i]));
      classes[i] = std::uint8_t(v[i].get<std::int64_t>());
    }
    out.points.classification = std::move(classes);
    return;
  }
  static const std::pair<const char*, int> kTypes[] = {{"UNSIGNED_BYTE", 1}, {"BYTE", -1},        {"UNSIGNED_SHORT", 2},
                                                       {"SHORT", -2},        {"UNSIGNED_INT", 4}, {"INT", -4}};
  const auto type = v.is_object() && v.contains("componentType") && v["componentType"].is_string()
                        ? std::find_if(std::begin(kTypes), std::end(kTypes),
                                       [&](const auto& t) { return v["componentType"] == t.first; })
                        : std::end(kTypes);
  if (!v.is_object() || !v.contains("byteOffset") || !v["byteOffset"].is_number_unsigned() ||
      type == std::end(kTypes) || v.value("type", json()) != "SCALAR")
    return fail(
        "expected an array of classes or {\"byteOffset\": n, \"componentType\": \"UNSIGNED_BYTE\" (or "
        "another integer type), \"type\": \"SCALAR\"}, got " +
        shown(v));
  const std::size_t size = std::size_t(std::abs(type->second));
  const std::uint64_t offset = v["byteOffset"].get<std::uint64_t>(), need = std::uint64_t(size) * n;
  if (offset > binary.size() || need > binary.size() - offset)
    return fail("byteOffset " + std::to_string(offset) + " + " + std::to_string(size) + "·N (N = " + std::to_string(n) +
                ") = " + std::to_string(offset + need) + " bytes, past the batch table's binary body of " +
                std::to_string(binary.size()) + " bytes");
  for (std::size_t i = 0; i < n; ++i) {
    const char* p = binary.data() + offset + size * i;
    std::int64_t c = 0;
    switch (type->second) {
      case 1:
        c = std::uint8_t(*p);
        break;
      case -1:
        c = std::int8_t(*p);
        break;
      case 2: {
        std::uint16_t x;
        std::memcpy(&x, p, 2);
        c = x;
        break;
      }
      case -2: {
        std::int16_t x;
        std::memcpy(&x, p, 2);
        c = x;
        break;
      }
      case 4: {
        std::uint32_t x;
        std::memcpy(&x, p, 4);
        c = x;
        break;
      }
      default: {
        std::int32_t x;
        std::memcpy(&x, p, 4);
        c = x;
        break;
      }
    }
    if (c < 0 || c > 255)
      return fail("point " + std::to_string(i) + ": expected a class 0..255, got " + std::to_string(c));
    classes[i] = std::uint8_t(c);
  }
  out.points.classification = std::move(classes);
}

}  // namespace

PntsTile parsePnts(std::string_view bytes, const std::string& url) {
  constexpr std::size_t kHeader = 28;
  if (bytes.size() < kHeader)
    throw InputError(inputMessage(url, "header", "expected 28 bytes at least, got " + std::to_string(bytes.size())));
  if (bytes.substr(0, 4) != "pnts") {
    std::string magic;
    for (char c : bytes.substr(0, 4)) magic += std::isprint(static_cast<unsigned char>(c)) ? std::string(1, c) : "?";
    throw InputError(inputMessage(url, "magic", "expected \"pnts\" (a 3D Tiles Point Cloud), got \"" + magic + "\""));
  }
  const std::uint32_t version = u32(bytes.data() + 4), byteLength = u32(bytes.data() + 8);
  const std::uint64_t ftJson = u32(bytes.data() + 12), ftBin = u32(bytes.data() + 16), btJson = u32(bytes.data() + 20),
                      btBin = u32(bytes.data() + 24);
  if (version != 1) throw InputError(inputMessage(url, "version", "expected 1, got " + std::to_string(version)));
  if (byteLength != bytes.size())
    throw InputError(inputMessage(url, "byteLength",
                                  std::to_string(byteLength) + " bytes, but the tile has " +
                                      std::to_string(bytes.size()) + " (expected the same)"));
  if (kHeader + ftJson + ftBin + btJson + btBin > byteLength)
    throw InputError(inputMessage(url, "header",
                                  "28 + " + std::to_string(ftJson) + " + " + std::to_string(ftBin) + " + " +
                                      std::to_string(btJson) + " + " + std::to_string(btBin) +
                                      " bytes of header and tables, past byteLength " + std::to_string(byteLength)));
  PntsTile out;
  std::string_view jsonText = bytes.substr(kHeader, ftJson);
  while (!jsonText.empty() && (jsonText.back() == ' ' || jsonText.back() == '\0')) jsonText.remove_suffix(1);
  json doc;
  try {
    doc = json::parse(jsonText);
  } catch (const json::exception& e) {
    throw InputError(inputMessage(url, "featureTable", std::string("expected a JSON object: ") + e.what()));
  }
  if (!doc.is_object())
    throw InputError(inputMessage(url, "featureTable", "expected a JSON object, got " + shown(doc)));
  FeatureTable ft{doc, bytes.substr(kHeader + ftJson, ftBin), url};
  if (!doc.contains("POINTS_LENGTH") || !doc["POINTS_LENGTH"].is_number_unsigned())
    throw InputError(inputMessage(url, "featureTable.POINTS_LENGTH",
                                  "expected the number of points (an integer >= 0), got " +
                                      (doc.contains("POINTS_LENGTH") ? shown(doc["POINTS_LENGTH"]) : "nothing")));
  const std::uint64_t n = doc["POINTS_LENGTH"].get<std::uint64_t>();
  // Every point takes 6 bytes of position at least: more points than that cannot be in the body.
  if (n > ft.binary.size() / 6 + 1)
    throw InputError(inputMessage(
        url, "featureTable.POINTS_LENGTH",
        std::to_string(n) + " points cannot fit in a binary body of " + std::to_string(ft.binary.size()) + " bytes"));
  ft.points = std::size_t(n);

  static const char* kKnown[] = {"POINTS_LENGTH",
                                 "POSITION",
                                 "POSITION_QUANTIZED",
                                 "QUANTIZED_VOLUME_OFFSET",
                                 "QUANTIZED_VOLUME_SCALE",
                                 "RGB",
                                 "RGBA",
                                 "RGB565",
                                 "CONSTANT_RGBA",
                                 "NORMAL",
                                 "NORMAL_OCT16P",
                                 "RTC_CENTER",
                                 "BATCH_ID",
                                 "BATCH_LENGTH",
                                 "extensions",
                                 "extras"};
  std::string unknown;
  for (auto it = doc.begin(); it != doc.end(); ++it) {
    const std::string& key = it.key();
    if (std::find_if(std::begin(kKnown), std::end(kKnown), [&](const char* k) { return key == k; }) == std::end(kKnown))
      unknown += (unknown.empty() ? "" : ", ") + key;
  }
  if (!unknown.empty()) out.notes.push_back(inputMessage(url, "featureTable", "ignored: " + unknown));
  const bool perBatch = doc.contains("BATCH_ID") || doc.contains("BATCH_LENGTH");
  if (perBatch && btJson + btBin > 0)
    out.notes.push_back(
        inputMessage(url, "batchTable",
                     "ignored (" + std::to_string(btJson + btBin) + " bytes; properties per BATCH_ID are not read)"));

  PointFields fields;
  const bool rgba = doc.contains("RGBA"), rgb = doc.contains("RGB"), rgb565 = doc.contains("RGB565"),
             constant = doc.contains("CONSTANT_RGBA");
  fields.rgb = rgba || rgb || rgb565 || constant;
  fields.normals = doc.contains("NORMAL") || doc.contains("NORMAL_OCT16P");
  PointCloud& cloud = out.points;
  cloud.sourcePath = url;
  cloud.resize(ft.points, fields);

  glm::dvec3 rtc(0.0);
  if (doc.contains("RTC_CENTER")) {
    const std::vector<double> c = ft.global("RTC_CENTER", 3);
    rtc = {c[0], c[1], c[2]};
  }
  if (doc.contains("POSITION")) {
    const char* p = ft.perPoint("POSITION", 12, "3 float32");
    for (std::size_t i = 0; i < ft.points; ++i) {
      float v[3];
      std::memcpy(v, p + 12 * i, 12);
      if (!std::isfinite(v[0]) || !std::isfinite(v[1]) || !std::isfinite(v[2]))
        throw InputError(
            inputMessage(url, "featureTable.POSITION", "point " + std::to_string(i) + ": expected finite numbers"));
      cloud.positions[i] = rtc + glm::dvec3(v[0], v[1], v[2]);
    }
  } else if (doc.contains("POSITION_QUANTIZED")) {
    for (const char* g : {"QUANTIZED_VOLUME_OFFSET", "QUANTIZED_VOLUME_SCALE"})
      if (!doc.contains(g))
        throw InputError(inputMessage(url, std::string("featureTable.") + g,
                                      "expected 3 numbers with POSITION_QUANTIZED, got nothing"));
    const std::vector<double> o = ft.global("QUANTIZED_VOLUME_OFFSET", 3), s = ft.global("QUANTIZED_VOLUME_SCALE", 3);
    const char* p = ft.perPoint("POSITION_QUANTIZED", 6, "3 uint16");
    for (std::size_t i = 0; i < ft.points; ++i) {
      std::uint16_t q[3];
      std::memcpy(q, p + 6 * i, 6);
      cloud.positions[i] =
          rtc + glm::dvec3(o[0], o[1], o[2]) + glm::dvec3(q[0], q[1], q[2]) * glm::dvec3(s[0], s[1], s[2]) / 65535.0;
    }
  } else {
    throw InputError(
        inputMessage(url, "featureTable.POSITION", "expected POSITION or POSITION_QUANTIZED, got neither"));
  }

  // Colours: RGBA, then RGB, then RGB565, then CONSTANT_RGBA (the specification's precedence).
  if (rgba || rgb) {
    const std::size_t stride = rgba ? 4 : 3;
    const char* p = ft.perPoint(rgba ? "RGBA" : "RGB", stride, rgba ? "4 uint8" : "3 uint8");
    for (std::size_t i = 0; i < ft.points; ++i) {
      const auto* c = reinterpret_cast<const std::uint8_t*>(p + stride * i);
      cloud.rgb[i] = glm::u16vec3(c[0] * 257u, c[1] * 257u, c[2] * 257u);
    }
    if (rgba) out.notes.push_back(inputMessage(url, "featureTable.RGBA", "alpha ignored"));
  } else if (rgb565) {
    const char* p = ft.perPoint("RGB565", 2, "1 uint16");
    for (std::size_t i = 0; i < ft.points; ++i) {
      std::uint16_t c;
      std::memcpy(&c, p + 2 * i, 2);
      cloud.rgb[i] = rgb565To16(c);
    }
  } else if (constant) {
    const std::vector<double> c =
        numbers(doc["CONSTANT_RGBA"], 4, url, "featureTable.CONSTANT_RGBA", "4 numbers 0..255");
    for (double v : c)
      if (v < 0 || v > 255)
        throw InputError(inputMessage(url, "featureTable.CONSTANT_RGBA",
                                      "expected 4 numbers 0..255, got " + shown(doc["CONSTANT_RGBA"])));
    std::fill(cloud.rgb.begin(), cloud.rgb.end(),
              glm::u16vec3(std::lround(c[0] * 257), std::lround(c[1] * 257), std::lround(c[2] * 257)));
  }
  if (doc.contains("NORMAL")) {
    const char* p = ft.perPoint("NORMAL", 12, "3 float32");
    for (std::size_t i = 0; i < ft.points; ++i) {
      float v[3];
      std::memcpy(v, p + 12 * i, 12);
      const glm::dvec3 d(v[0], v[1], v[2]);
      const double len = glm::length(d);
      if (!std::isfinite(len) || len < 1e-6)
        throw InputError(inputMessage(url, "featureTable.NORMAL",
                                      "point " + std::to_string(i) + ": expected a non-zero, finite normal"));
      cloud.normals[i] = glm::vec3(d / len);
    }
  } else if (doc.contains("NORMAL_OCT16P")) {
    const char* p = ft.perPoint("NORMAL_OCT16P", 2, "2 uint8");
    for (std::size_t i = 0; i < ft.points; ++i)
      cloud.normals[i] = octDecode16P(std::uint8_t(p[2 * i]), std::uint8_t(p[2 * i + 1]));
  }
  // The batch table without BATCH_ID is per point: its "Classification" is the ASPRS class.
  if (!perBatch && btJson > 0)
    readBatchTable(bytes.substr(kHeader + ftJson + ftBin, btJson),
                   bytes.substr(kHeader + ftJson + ftBin + btJson, btBin), url, out);
  return out;
}

// ------------------------------------------------------------------------------------------------
// Writing

namespace {

void pad(std::string& s, std::size_t to, char with) {
  while (s.size() % to) s.push_back(with);
}

template <typename T>
void put(std::string& s, const T& v) {
  s.append(reinterpret_cast<const char*>(&v), sizeof v);
}

}  // namespace

std::string writePnts(const PointCloud& cloud) {
  Aabb box = cloud.bounds();
  if (box.empty()) box = Aabb{glm::dvec3(0.0), glm::dvec3(0.0)};
  const glm::dvec3 centre = box.center();
  const glm::dvec3 size = glm::max(box.hi - box.lo, glm::dvec3(1e-3));
  json ft;
  ft["POINTS_LENGTH"] = cloud.size();
  ft["RTC_CENTER"] = {centre.x, centre.y, centre.z};
  ft["QUANTIZED_VOLUME_OFFSET"] = {box.lo.x - centre.x, box.lo.y - centre.y, box.lo.z - centre.z};
  ft["QUANTIZED_VOLUME_SCALE"] = {size.x, size.y, size.z};
  std::string bin;
  ft["POSITION_QUANTIZED"] = {{"byteOffset", 0}};
  for (const glm::dvec3& p : cloud.positions)
    for (int a = 0; a < 3; ++a)
      put(bin, std::uint16_t(std::clamp(std::lround((p[a] - box.lo[a]) / size[a] * 65535.0), 0L, 65535L)));
  if (!cloud.rgb.empty()) {
    pad(bin, 4, '\0');
    ft["RGB"] = {{"byteOffset", bin.size()}};
    for (const glm::u16vec3& c : cloud.rgb)
      for (int a = 0; a < 3; ++a) put(bin, std::uint8_t((unsigned(c[a]) * 255u + 32767u) / 65535u));
  }
  if (!cloud.normals.empty()) {
    pad(bin, 4, '\0');
    ft["NORMAL"] = {{"byteOffset", bin.size()}};
    for (const glm::vec3& n : cloud.normals) put(bin, n);
  }
  pad(bin, 8, '\0');
  std::string text = ft.dump();
  while ((28 + text.size()) % 8) text.push_back(' ');
  // The ASPRS classes as the per-point batch table's "Classification" (no BATCH_ID): its JSON
  // padded with spaces and its binary body with zeros to 8-byte boundaries, as the feature table's.
  std::string batchText, batchBin;
  if (!cloud.classification.empty()) {
    batchText =
        json{{"Classification", {{"byteOffset", 0}, {"componentType", "UNSIGNED_BYTE"}, {"type", "SCALAR"}}}}.dump();
    while ((28 + text.size() + bin.size() + batchText.size()) % 8) batchText.push_back(' ');
    batchBin.assign(reinterpret_cast<const char*>(cloud.classification.data()), cloud.classification.size());
    pad(batchBin, 8, '\0');
  }
  std::string out = "pnts";
  put(out, std::uint32_t(1));
  put(out, std::uint32_t(28 + text.size() + bin.size() + batchText.size() + batchBin.size()));
  put(out, std::uint32_t(text.size()));
  put(out, std::uint32_t(bin.size()));
  put(out, std::uint32_t(batchText.size()));
  put(out, std::uint32_t(batchBin.size()));
  return out + text + bin + batchText + batchBin;
}

}  // namespace hv
