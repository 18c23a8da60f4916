#include "hv/io/native/cityjson.h"

#include "hv/io/json_input.h"
#include "hv/scene/native/lod1.h"
#include "hv/util/input_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>

namespace hv {
namespace {

using nlohmann::json;

// A surface farther from its plane than this (relative to its extent) is not planar: triangulated
// in a plane it does not lie in, its triangles would not be the surface.
constexpr double kPlanarityTolerance = 1e-3;

// "EPSG:n" from the forms CityJSON versions write; anything else as written.
std::string crsOf(const json& doc) {
  if (!doc.contains("metadata") || !doc["metadata"].is_object()) return "";
  const json& m = doc["metadata"];
  if (!m.contains("referenceSystem") || !m["referenceSystem"].is_string()) return "";
  const std::string rs = m["referenceSystem"].get<std::string>();
  for (const std::string prefix : {"urn:ogc:def:crs:EPSG::", "urn:ogc:def:crs:EPSG:",
                                   "http://www.opengis.net/def/crs/EPSG/0/", "https://www.opengis.net/def/crs/EPSG/0/"})
    if (rs.rfind(prefix, 0) == 0) {
      const std::string code = rs.substr(prefix.size());
      if (!code.empty() && std::all_of(code.begin(), code.end(), [](unsigned char c) { return std::isdigit(c); }))
        return "EPSG:" + code;
    }
  return rs;
}

int lodOf(const json& g) {
  if (!g.contains("lod")) return 0;
  const json& l = g["lod"];
  if (l.is_number()) return int(std::floor(l.get<double>()));
  if (l.is_string()) {
    try {
      return int(std::floor(std::stod(l.get<std::string>())));
    } catch (const std::exception&) {
    }
  }
  return 0;
}

class Reader {
 public:
  Reader(const std::string& path, std::vector<glm::dvec3> vertices) : path_(path), vertices_(std::move(vertices)) {}

  // Appends the triangles of geometry `g` (of the object `id`) to `mesh`, tagged `tag`.
  void geometry(const json& g, const std::string& field, std::uint32_t tag, Mesh& mesh) {
    const std::string type = g.value("type", "");
    if (!g.contains("boundaries")) fail(field + ".boundaries", "missing");
    const json& b = g["boundaries"];
    if (type == "MultiSurface" || type == "CompositeSurface") {
      surfaces(b, field + ".boundaries", tag, mesh);
    } else if (type == "Solid") {
      solid(b, field + ".boundaries", tag, mesh);
    } else if (type == "MultiSolid" || type == "CompositeSolid") {
      array(b, field + ".boundaries");
      for (size_t s = 0; s < b.size(); ++s) solid(b[s], field + ".boundaries[" + std::to_string(s) + "]", tag, mesh);
    } else {
      fail(field + ".type",
           "expected MultiSurface, CompositeSurface, Solid, MultiSolid or CompositeSolid, got '" + type + "'");
    }
  }

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw InputError(inputMessage(path_, field, message));
  }

 private:
  void array(const json& j, const std::string& field) const {
    if (!j.is_array()) fail(field, "expected an array");
  }
  void solid(const json& shells, const std::string& field, std::uint32_t tag, Mesh& mesh) {
    array(shells, field);
    for (size_t s = 0; s < shells.size(); ++s) surfaces(shells[s], field + "[" + std::to_string(s) + "]", tag, mesh);
  }
  void surfaces(const json& list, const std::string& field, std::uint32_t tag, Mesh& mesh) {
    array(list, field);
    for (size_t s = 0; s < list.size(); ++s) surface(list[s], field + "[" + std::to_string(s) + "]", tag, mesh);
  }

  // One polygon: its rings of vertex indices, outer first.
  void surface(const json& rings, const std::string& field, std::uint32_t tag, Mesh& mesh) {
    array(rings, field);
    if (rings.empty()) fail(field, "expected at least an outer ring");
    std::vector<std::vector<glm::dvec3>> pts;
    for (size_t r = 0; r < rings.size(); ++r) {
      const std::string rf = field + "[" + std::to_string(r) + "]";
      array(rings[r], rf);
      std::vector<glm::dvec3> ring;
      for (const json& i : rings[r]) {
        if (!i.is_number_unsigned() || i.get<std::uint64_t>() >= vertices_.size())
          fail(rf, "expected vertex indices below " + std::to_string(vertices_.size()) + ", got " + i.dump());
        const glm::dvec3& p = vertices_[size_t(i.get<std::uint64_t>())];
        if (ring.empty() || ring.back() != p) ring.push_back(p);  // repeated points are no edge
      }
      while (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();  // explicitly closed
      if (ring.size() < 3) {
        if (r == 0)
          fail(rf, "the outer ring has " + std::to_string(ring.size()) + " distinct points, expected 3 or more");
        continue;  // a degenerate hole cuts nothing
      }
      pts.push_back(std::move(ring));
    }
    // The plane: Newell's normal of the outer ring (robust for any simple polygon), its
    // orientation that of the ring.
    glm::dvec3 n(0.0);
    const auto& outer = pts[0];
    for (size_t k = 0; k < outer.size(); ++k) {
      const glm::dvec3& a = outer[k];
      const glm::dvec3& b = outer[(k + 1) % outer.size()];
      n += glm::dvec3((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) fail(field, "the outer ring has zero area");
    n /= len;
    const glm::dvec3 origin = outer[0];
    const glm::dvec3 u =
        glm::normalize(std::abs(n.z) < 0.9 ? glm::cross(glm::dvec3(0, 0, 1), n) : glm::cross(glm::dvec3(1, 0, 0), n));
    const glm::dvec3 v = glm::cross(n, u);  // u x v = n: counter-clockwise around n is counter-clockwise in (u, v)
    double extent = 0.0, off = 0.0;
    std::vector<std::vector<glm::dvec2>> flat;
    for (const auto& ring : pts) {
      std::vector<glm::dvec2> f;
      for (const glm::dvec3& p : ring) {
        const glm::dvec3 d = p - origin;
        f.emplace_back(glm::dot(d, u), glm::dot(d, v));
        extent = std::max(extent, glm::length(d));
        off = std::max(off, std::abs(glm::dot(d, n)));
      }
      flat.push_back(std::move(f));
    }
    if (off > kPlanarityTolerance * std::max(extent, 1.0))
      fail(field, "not planar: a vertex lies " + std::to_string(off) + " from the polygon's plane");
    const std::vector<glm::uvec3> tris = triangulatePolygon(flat, inputMessage(path_, field, "polygon"));
    const auto base = std::uint32_t(mesh.positions.size());
    for (const auto& ring : pts) mesh.positions.insert(mesh.positions.end(), ring.begin(), ring.end());
    for (const glm::uvec3& t : tris) {
      mesh.triangles.push_back(t + base);
      mesh.triangleTags.push_back(tag);
    }
  }

  std::string path_;
  std::vector<glm::dvec3> vertices_;
};

std::vector<glm::dvec3> readVertices(const json& doc, const std::string& path) {
  glm::dvec3 scale(1.0), translate(0.0);
  if (doc.contains("transform")) {
    const json& t = doc["transform"];
    auto vec = [&](const char* key, glm::dvec3& out) {
      if (!t.is_object() || !t.contains(key) || !t[key].is_array() || t[key].size() != 3 ||
          !std::all_of(t[key].begin(), t[key].end(), [](const json& x) { return x.is_number(); }))
        throw InputError(inputMessage(path, std::string("transform.") + key, "expected [x, y, z] numbers"));
      out = {t[key][0].get<double>(), t[key][1].get<double>(), t[key][2].get<double>()};
    };
    vec("scale", scale);
    vec("translate", translate);
  }
  const json& vs = doc["vertices"];
  std::vector<glm::dvec3> out;
  out.reserve(vs.size());
  for (size_t i = 0; i < vs.size(); ++i) {
    const json& v = vs[i];
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      throw InputError(inputMessage(path, "vertices[" + std::to_string(i) + "]",
                                    "expected [x, y, z] numbers, got " + v.dump().substr(0, 60)));
    const glm::dvec3 p = glm::dvec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>()) * scale + translate;
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw InputError(inputMessage(path, "vertices[" + std::to_string(i) + "]", "not finite once transformed"));
    out.push_back(p);
  }
  return out;
}

}  // namespace

CityJsonBuildings parseCityJson(std::string_view text, const std::string& path, Diagnostics& diag) {
  const json doc = parseJsonInput(std::string(text), path, diag);
  if (!doc.is_object() || !doc.contains("type") || doc["type"] != "CityJSON")
    throw InputError(inputMessage(path, "type", "expected \"CityJSON\" (a CityJSON file)"));
  if (!doc.contains("CityObjects") || !doc["CityObjects"].is_object())
    throw InputError(inputMessage(path, "CityObjects", "expected an object of city objects"));
  if (!doc.contains("vertices") || !doc["vertices"].is_array())
    throw InputError(inputMessage(path, "vertices", "expected an array of [x, y, z]"));
  CityJsonBuildings out;
  out.crs = crsOf(doc);
  Reader reader(path, readVertices(doc, path));
  const json& objects = doc["CityObjects"];

  // Buildings first (their index is the tag), then the parts, tagged with their parent's.
  std::map<std::string, std::uint32_t> buildingIndex;
  for (const auto& [id, o] : objects.items())
    if (o.is_object() && o.value("type", "") == "Building") {
      buildingIndex.emplace(id, std::uint32_t(out.ids.size()));
      out.ids.push_back(id);
      out.lods.push_back(-1);
    }
  for (const auto& [id, o] : objects.items()) {
    if (!o.is_object()) continue;
    const std::string type = o.value("type", "");
    if (type != "Building" && type != "BuildingPart") continue;
    std::optional<std::uint32_t> tag;
    if (type == "Building") {
      tag = buildingIndex.at(id);
    } else if (o.contains("parents") && o["parents"].is_array()) {
      for (const json& p : o["parents"])
        if (p.is_string() && buildingIndex.count(p.get<std::string>())) tag = buildingIndex.at(p.get<std::string>());
    }
    if (!tag) {  // a part without a known building is a building of its own
      tag = std::uint32_t(out.ids.size());
      out.ids.push_back(id);
      out.lods.push_back(-1);
    }
    const std::string field = "CityObjects." + id + ".geometry";
    if (!o.contains("geometry")) continue;  // a building made only of parts
    const json& geoms = o["geometry"];
    try {
      if (!geoms.is_array()) reader.fail(field, "expected an array of geometries");
      int best = -1;
      for (size_t g = 0; g < geoms.size(); ++g) {
        if (!geoms[g].is_object()) reader.fail(field + "[" + std::to_string(g) + "]", "expected an object");
        const std::string gt = geoms[g].value("type", "");
        if (gt == "GeometryInstance") continue;  // templates: not read
        if (best < 0 || lodOf(geoms[g]) > lodOf(geoms[size_t(best)])) best = int(g);
      }
      if (best < 0) continue;
      Mesh mesh;
      reader.geometry(geoms[size_t(best)], field + "[" + std::to_string(best) + "]", *tag, mesh);
      out.mesh.append(mesh);
      out.lods[*tag] = std::max(out.lods[*tag], lodOf(geoms[size_t(best)]));
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (" + type + " '" + id + "' left out)");
    }
  }
  if (out.ids.empty()) diag.warn(inputMessage(path, "CityObjects", "no Building or BuildingPart"));
  return out;
}

CityJsonBuildings readCityJson(const std::string& path, Diagnostics& diag) {
  return parseCityJson(readTextFile(path, kMaxJsonBytes, "CityJSON buildings"), path, diag);
}

bool isCityJsonFile(const std::string& path) {
  std::string lower = path;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  auto ends = [&](const std::string& s) {
    return lower.size() >= s.size() && lower.compare(lower.size() - s.size(), s.size(), s) == 0;
  };
  if (ends(".city.json") || ends(".cityjson")) return true;
  if (!ends(".json")) return false;
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(in.gcount()));
  return head.find("\"CityJSON\"") != std::string::npos;
}

}  // namespace hv
