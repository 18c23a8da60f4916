#include "hv/io/tiles3d.h"

#include "hv/io/tiles3d_json.h"
#include "hv/util/diagnostics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <sstream>
#include <utility>

namespace hv {

namespace tiles3d_json {

using nlohmann::json;

bool finiteNumber(const json& v) { return v.is_number() && std::isfinite(v.get<double>()); }

// A JSON value, shortened for messages.
std::string shown(const json& v) {
  std::string s = v.dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > 60) s = s.substr(0, 57) + "...";
  return s;
}

std::vector<double> numbers(const json& v, std::size_t n, const std::string& url, const std::string& field,
                            const std::string& what) {
  if (!v.is_array() || v.size() != n)
    throw InputError(inputMessage(url, field, "expected " + what + ", got " + shown(v)));
  std::vector<double> out;
  for (const json& x : v) {
    if (!finiteNumber(x)) throw InputError(inputMessage(url, field, "expected " + what + ", got " + shown(v)));
    out.push_back(x.get<double>());
  }
  return out;
}

}  // namespace tiles3d_json

namespace {

using nlohmann::json;
using tiles3d_json::finiteNumber;
using tiles3d_json::numbers;
using tiles3d_json::shown;

std::string num(double v) {
  std::ostringstream o;
  o.precision(12);
  o << v;
  return o.str();
}

TileSphere sphereOf(const json& bv, const glm::dmat4& t, const std::string& url, const std::string& field) {
  if (!bv.is_object())
    throw InputError(inputMessage(url, field, "expected an object with box, region or sphere, got " + shown(bv)));
  TileSphere s;
  if (bv.contains("box")) {
    const std::vector<double> b = numbers(bv["box"], 12, url, field + ".box", "12 numbers (centre, three half-axes)");
    s.centre = glm::dvec3(t * glm::dvec4(b[0], b[1], b[2], 1.0));
    const glm::dmat3 r(t);
    const glm::dvec3 a = r * glm::dvec3(b[3], b[4], b[5]), c = r * glm::dvec3(b[6], b[7], b[8]),
                     d = r * glm::dvec3(b[9], b[10], b[11]);
    for (int k = 0; k < 8; ++k)
      s.radius = std::max(s.radius, glm::length((k & 1 ? a : -a) + (k & 2 ? c : -c) + (k & 4 ? d : -d)));
  } else if (bv.contains("region")) {
    const std::vector<double> g = numbers(bv["region"], 6, url, field + ".region",
                                          "6 numbers (west, south, east, north in radians, min and max height)");
    const double pi = 3.14159265358979323846;
    if (g[0] < -pi || g[0] > pi || g[2] < -pi || g[2] > pi || g[1] < -pi / 2 || g[3] > pi / 2 || g[1] > g[3] ||
        g[4] > g[5])
      throw InputError(inputMessage(url, field + ".region",
                                    "expected west, south, east, north in radians (south <= north, within +-pi, "
                                    "+-pi/2) and min height <= max height, got " +
                                        shown(bv["region"])));
    const double east = g[2] < g[0] ? g[2] + 2 * pi : g[2];  // across the antimeridian
    std::vector<glm::dvec3> pts;
    for (int i = 0; i <= 2; ++i)
      for (int j = 0; j <= 2; ++j)
        for (double h : {g[4], g[5]})
          pts.push_back(wgs84ToEcef(g[0] + (east - g[0]) * i / 2, g[1] + (g[3] - g[1]) * j / 2, h));
    glm::dvec3 lo(std::numeric_limits<double>::max()), hi(-std::numeric_limits<double>::max());
    for (const glm::dvec3& p : pts) lo = glm::min(lo, p), hi = glm::max(hi, p);
    s.centre = 0.5 * (lo + hi);
    for (const glm::dvec3& p : pts) s.radius = std::max(s.radius, glm::length(p - s.centre));
  } else if (bv.contains("sphere")) {
    const std::vector<double> g = numbers(bv["sphere"], 4, url, field + ".sphere", "4 numbers (centre, radius)");
    if (g[3] < 0) throw InputError(inputMessage(url, field + ".sphere", "expected a radius >= 0, got " + num(g[3])));
    s.centre = glm::dvec3(t * glm::dvec4(g[0], g[1], g[2], 1.0));
    const glm::dmat3 r(t);
    s.radius = g[3] * std::max({glm::length(r[0]), glm::length(r[1]), glm::length(r[2])});
  } else {
    throw InputError(inputMessage(url, field, "expected box (12 numbers), region (6) or sphere (4), got " + shown(bv)));
  }
  return s;
}

glm::dmat4 transformOf(const json& v, const std::string& url, const std::string& field) {
  const std::vector<double> m = numbers(v, 16, url, field, "16 numbers (a column-major 4x4 matrix)");
  if (m[3] != 0.0 || m[7] != 0.0 || m[11] != 0.0 || m[15] != 1.0)
    throw InputError(inputMessage(
        url, field, "expected an affine matrix (elements 4, 8, 12 zero and 16 one, column-major), got " + shown(v)));
  glm::dmat4 t;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) t[c][r] = m[std::size_t(c * 4 + r)];
  return t;
}

bool endsWith(const std::string& s, const std::string& end) {
  return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

bool isJsonUri(const std::string& uri) {
  std::string u = uri.substr(0, uri.find_first_of("?#"));
  std::transform(u.begin(), u.end(), u.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return endsWith(u, ".json");
}

}  // namespace

glm::dvec3 wgs84ToEcef(double lon, double lat, double height) {
  const double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
  const double n = a / std::sqrt(1.0 - e2 * std::sin(lat) * std::sin(lat));
  return {(n + height) * std::cos(lat) * std::cos(lon), (n + height) * std::cos(lat) * std::sin(lon),
          (n * (1.0 - e2) + height) * std::sin(lat)};
}

std::string resolveTileUri(const std::string& base, const std::string& uri) {
  const bool absolute = uri.find("://") != std::string::npos || uri.rfind("/vsi", 0) == 0 || uri.rfind("data:", 0) == 0;
  if (absolute) return uri;
  const std::size_t scheme = base.find("://");
  std::string prefix, path;
  std::string b = base;
  if (scheme != std::string::npos) {
    b = b.substr(0, b.find_first_of("?#", scheme + 3));
    const std::size_t slash = b.find('/', scheme + 3);
    prefix = slash == std::string::npos ? b : b.substr(0, slash);
    path = slash == std::string::npos ? "/" : b.substr(slash);
  } else {
    path = b;
  }
  if (!uri.empty() && uri[0] == '/') {
    if (scheme == std::string::npos) return uri;
    path = uri;
  } else {
    const std::size_t slash = path.rfind('/');
    path = (slash == std::string::npos ? std::string() : path.substr(0, slash + 1)) + uri;
  }
  // "./" and "../" segments (the query of `uri`, if any, kept as it is).
  const std::size_t q = path.find_first_of("?#");
  const std::string tail = q == std::string::npos ? "" : path.substr(q);
  if (q != std::string::npos) path = path.substr(0, q);
  const bool rooted = !path.empty() && path[0] == '/';
  std::vector<std::string> parts;
  std::size_t start = rooted ? 1 : 0;
  int leadingUp = 0;
  while (start <= path.size()) {
    std::size_t end = path.find('/', start);
    if (end == std::string::npos) end = path.size();
    const std::string part = path.substr(start, end - start);
    if (part == "..") {
      if (!parts.empty())
        parts.pop_back();
      else if (!rooted)
        ++leadingUp;
    } else if (part != "." && !(part.empty() && end != path.size())) {
      parts.push_back(part);
    }
    start = end + 1;
  }
  std::string out = rooted ? "/" : "";
  for (int i = 0; i < leadingUp; ++i) out += "../";
  for (std::size_t i = 0; i < parts.size(); ++i) out += (i ? "/" : "") + parts[i];
  return prefix + out + tail;
}

Tiles3dTileset parseTileset(std::string_view text, const std::string& url, const glm::dmat4& parentTransform,
                            TileRefine inheritedRefine, int depth) {
  json doc;
  try {
    doc = json::parse(text);
  } catch (const json::exception& e) {
    throw InputError(inputMessage(url, "", std::string("expected a 3D Tiles tileset (JSON): ") + e.what()));
  }
  if (!doc.is_object()) throw InputError(inputMessage(url, "", "expected a 3D Tiles tileset (a JSON object)"));
  Tiles3dTileset ts;
  ts.url = url;
  if (!doc.contains("asset") || !doc["asset"].is_object())
    throw InputError(inputMessage(url, "asset", "expected an object with the version (\"1.0\")"));
  const json& asset = doc["asset"];
  if (!asset.contains("version") || !asset["version"].is_string())
    throw InputError(inputMessage(url, "asset.version", "expected a string (\"1.0\")"));
  ts.version = asset["version"].get<std::string>();
  if (ts.version == "1.1")
    ts.notes.push_back(
        inputMessage(url, "asset.version", "1.1 read as 1.0: implicit tiling, glTF content and metadata are not read"));
  else if (ts.version != "1.0" && ts.version != "0.0")
    throw InputError(
        inputMessage(url, "asset.version", "expected \"1.0\" (or \"0.0\", \"1.1\"), got \"" + ts.version + "\""));
  if (!doc.contains("geometricError") || !finiteNumber(doc["geometricError"]) ||
      doc["geometricError"].get<double>() < 0)
    throw InputError(inputMessage(url, "geometricError",
                                  "expected a number >= 0 (metres), got " +
                                      (doc.contains("geometricError") ? shown(doc["geometricError"]) : "nothing")));
  ts.geometricError = doc["geometricError"].get<double>();
  if (!doc.contains("root") || !doc["root"].is_object())
    throw InputError(inputMessage(url, "root", "expected the root tile (an object)"));
  if (doc.contains("extensionsRequired") && doc["extensionsRequired"].is_array() && !doc["extensionsRequired"].empty())
    throw InputError(
        inputMessage(url, "extensionsRequired",
                     "expected none (no 3D Tiles extension is read), got " + shown(doc["extensionsRequired"])));

  // Depth first with an explicit stack (a deep tree must not exhaust the call stack).
  struct Pending {
    const json* tile;
    int parent;
    std::string path;
  };
  std::vector<Pending> pending{{&doc["root"], -1, "root"}};
  while (!pending.empty()) {
    const Pending item = pending.back();
    pending.pop_back();
    const json& j = *item.tile;
    const std::string& f = item.path;
    if (!j.is_object()) throw InputError(inputMessage(url, f, "expected a tile (an object), got " + shown(j)));
    if (ts.tiles.size() >= kMaxTiles3dTiles)
      throw InputError(
          inputMessage(url, f, "more than " + std::to_string(kMaxTiles3dTiles) + " tiles (expected fewer)"));
    Tiles3dTile t;
    t.parent = item.parent;
    t.path = f;
    const Tiles3dTile* parent = item.parent >= 0 ? &ts.tiles[std::size_t(item.parent)] : nullptr;
    t.depth = parent ? parent->depth + 1 : depth;
    if (t.depth > kMaxTiles3dDepth)
      throw InputError(
          inputMessage(url, f, "deeper than " + std::to_string(kMaxTiles3dDepth) + " levels (expected fewer)"));
    t.transform = parent ? parent->transform : parentTransform;
    if (j.contains("transform")) t.transform = t.transform * transformOf(j["transform"], url, f + ".transform");
    if (!j.contains("boundingVolume"))
      throw InputError(inputMessage(url, f + ".boundingVolume", "expected box, region or sphere, got nothing"));
    t.bounds = sphereOf(j["boundingVolume"], t.transform, url, f + ".boundingVolume");
    if (!j.contains("geometricError") || !finiteNumber(j["geometricError"]) || j["geometricError"].get<double>() < 0)
      throw InputError(inputMessage(url, f + ".geometricError",
                                    "expected a number >= 0 (metres), got " +
                                        (j.contains("geometricError") ? shown(j["geometricError"]) : "nothing")));
    t.geometricError = j["geometricError"].get<double>();
    t.refine = parent ? parent->refine : inheritedRefine;
    if (j.contains("refine")) {
      const json& r = j["refine"];
      // Upper case in the specification; lower case is common enough to read too.
      std::string s = r.is_string() ? r.get<std::string>() : "";
      std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::toupper(c)); });
      if (s == "ADD")
        t.refine = TileRefine::Add;
      else if (s == "REPLACE")
        t.refine = TileRefine::Replace;
      else
        throw InputError(inputMessage(url, f + ".refine", "expected \"ADD\" or \"REPLACE\", got " + shown(r)));
    } else if (!parent && depth == 0) {
      ts.notes.push_back(inputMessage(url, "root.refine", "missing (required for the root): REPLACE assumed"));
    }
    if (j.contains("content") && !j["content"].is_null()) {
      const json& c = j["content"];
      const char* key = c.is_object() && c.contains("uri") ? "uri" : "url";  // "url": the 1.0 pre-release spelling
      if (!c.is_object() || !c.contains(key) || !c[key].is_string() || c[key].get<std::string>().empty())
        throw InputError(inputMessage(url, f + ".content.uri", "expected a URI (string), got " + shown(c)));
      t.content = resolveTileUri(url, c[key].get<std::string>());
      t.external = isJsonUri(c[key].get<std::string>());
    }
    if (j.contains("viewerRequestVolume")) ts.notes.push_back(inputMessage(url, f + ".viewerRequestVolume", "ignored"));
    const int index = int(ts.tiles.size());
    if (parent) ts.tiles[std::size_t(item.parent)].children.push_back(index);
    ts.tiles.push_back(std::move(t));
    if (j.contains("children")) {
      const json& kids = j["children"];
      if (!kids.is_array()) throw InputError(inputMessage(url, f + ".children", "expected an array of tiles"));
      for (std::size_t k = kids.size(); k-- > 0;)
        pending.push_back({&kids[k], index, f + ".children[" + std::to_string(k) + "]"});
    }
  }
  // Children were pushed in reverse so that they are visited in order; parents precede children.
  return ts;
}

void graftTileset(Tiles3dTileset& host, int at, Tiles3dTileset sub) {
  const int offset = int(host.tiles.size());
  if (host.tiles.size() + sub.tiles.size() > kMaxTiles3dTiles)
    throw InputError(inputMessage(
        sub.url, "",
        "the tilesets together have more than " + std::to_string(kMaxTiles3dTiles) + " tiles (expected fewer)"));
  Tiles3dTile& host_tile = host.tiles[std::size_t(at)];
  host_tile.content.clear();
  host_tile.external = false;
  host_tile.children.push_back(offset);
  for (Tiles3dTile& t : sub.tiles) {
    t.parent = t.parent < 0 ? at : t.parent + offset;
    for (int& c : t.children) c += offset;
    host.tiles.push_back(std::move(t));
  }
  for (std::string& n : sub.notes) host.notes.push_back(std::move(n));
}

// ------------------------------------------------------------------------------------------------
// Writing a tile set

namespace {

struct Node {
  std::vector<std::uint32_t> points;  // into the cloud
  Aabb box;
};

}  // namespace

PointTilesWritten writePointTiles(const PointCloud& cloud, const glm::dmat4& rootTransform,
                                  const PointTilesOptions& options) {
  PointTilesWritten out;
  out.files.push_back({"tileset.json", ""});
  const std::size_t perTile = std::max<std::size_t>(options.pointsPerTile, 1);
  // A fixed pseudo-random order: each tile's sample is spread over its node (points of a file are
  // often in scan order).
  std::vector<std::uint32_t> order(cloud.size());
  for (std::uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  for (std::size_t i = order.size(); i > 1; --i) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    std::swap(order[i - 1], order[std::size_t((state >> 33) % i)]);
  }
  auto subset = [&](const std::vector<std::uint32_t>& idx) {
    PointCloud c;
    PointFields f = cloud.fields();
    f.intensity = false;  // pnts has no field for it
    c.resize(idx.size(), f);
    for (std::size_t i = 0; i < idx.size(); ++i) {
      c.positions[i] = cloud.positions[idx[i]];
      if (f.classification) c.classification[i] = cloud.classification[idx[i]];
      if (f.rgb) c.rgb[i] = cloud.rgb[idx[i]];
      if (f.normals) c.normals[i] = cloud.normals[idx[i]];
    }
    return c;
  };
  auto boxJson = [](const Aabb& b) {
    const glm::dvec3 c = b.center(), h = 0.5 * (b.hi - b.lo);
    return json::array(
        {c.x, c.y, c.z, std::max(h.x, 1e-3), 0, 0, 0, std::max(h.y, 1e-3), 0, 0, 0, std::max(h.z, 1e-3)});
  };
  // Recursion over the tree (depth at most options.maxDepth).
  std::function<json(Node&, const std::string&, int)> build = [&](Node& node, const std::string& name, int depth) {
    ++out.tiles;
    out.depth = std::max(out.depth, depth);
    json tile;
    tile["boundingVolume"] = {{"box", boxJson(node.box)}};
    const bool leaf = node.points.size() <= perTile || depth >= options.maxDepth;
    std::vector<std::uint32_t> keep;
    if (leaf) {
      keep = std::move(node.points);
    } else {
      keep.assign(node.points.begin(), node.points.begin() + std::ptrdiff_t(perTile));
    }
    out.files.push_back({name + ".pnts", writePnts(subset(keep))});
    tile["content"] = {{"uri", name + ".pnts"}};
    const glm::dvec3 size = node.box.hi - node.box.lo;
    const double largest = std::max({size.x, size.y, size.z});
    if (leaf) {
      tile["geometricError"] = 0.0;
      return tile;
    }
    // The spacing of the kept sample over the node's area (points of a city lie on surfaces).
    tile["geometricError"] = largest / std::sqrt(double(keep.size()));
    const glm::dvec3 mid = node.box.center();
    std::array<bool, 3> split{};
    for (int a = 0; a < 3; ++a) split[std::size_t(a)] = size[a] >= 0.5 * largest;
    std::array<Node, 8> kids;
    for (std::size_t i = perTile; i < node.points.size(); ++i) {
      const glm::dvec3& p = cloud.positions[node.points[i]];
      int k = 0;
      for (int a = 0; a < 3; ++a)
        if (split[std::size_t(a)] && p[a] >= mid[a]) k |= 1 << a;
      kids[std::size_t(k)].points.push_back(node.points[i]);
    }
    node.points.clear();
    node.points.shrink_to_fit();
    json children = json::array();
    for (int k = 0; k < 8; ++k) {
      Node& kid = kids[std::size_t(k)];
      if (kid.points.empty()) continue;
      for (std::uint32_t i : kid.points) kid.box.extend(cloud.positions[i]);
      children.push_back(build(kid, name + std::to_string(k), depth + 1));
    }
    tile["children"] = children;
    return tile;
  };
  Node root;
  root.points = order;
  root.box = cloud.bounds();
  if (root.box.empty()) root.box = Aabb{glm::dvec3(0.0), glm::dvec3(0.0)};
  json rootTile = build(root, "r", 0);
  rootTile["refine"] = "ADD";
  json m = json::array();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) m.push_back(rootTransform[c][r]);
  rootTile["transform"] = m;
  json ts;
  ts["asset"] = {{"version", "1.0"}, {"generator", "histoview points-tiles"}};
  const glm::dvec3 size = root.box.hi - root.box.lo;
  ts["geometricError"] = std::max(rootTile["geometricError"].get<double>(), glm::length(size));
  ts["root"] = rootTile;
  out.files[0].bytes = ts.dump(1) + "\n";
  return out;
}

}  // namespace hv
