#include "hv/io/geojson_footprints.h"

#include "hv/io/json_input.h"

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

namespace hv {

using json = nlohmann::json;

namespace {

std::optional<double> numberOf(const json& props, const std::string& key) {
  if (!props.is_object() || !props.contains(key)) return std::nullopt;
  const json& v = props[key];
  if (v.is_number()) return v.get<double>();
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    char* end = nullptr;
    const double d = std::strtod(s.c_str(), &end);
    if (end && end != s.c_str() && *end == '\0' && std::isfinite(d)) return d;
  }
  return std::nullopt;
}

std::optional<std::string> textOf(const json& props, const std::optional<std::string>& key) {
  if (!key || !props.is_object() || !props.contains(*key)) return std::nullopt;
  const json& v = props[*key];
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number()) return v.dump();
  return std::nullopt;
}

// [[x, y(, z)], ...] rings of a Polygon's coordinates.
std::vector<std::vector<glm::dvec2>> ringsOf(const json& polygon, const std::string& where) {
  if (!polygon.is_array() || polygon.empty()) throw InputError(where + ": expected an array of rings");
  std::vector<std::vector<glm::dvec2>> rings;
  for (const json& ring : polygon) {
    if (!ring.is_array()) throw InputError(where + ": expected a ring (an array of positions)");
    std::vector<glm::dvec2> r;
    for (const json& p : ring) {
      if (!p.is_array() || p.size() < 2 || !p[0].is_number() || !p[1].is_number())
        throw InputError(where + ": expected a position [x, y]");
      r.emplace_back(p[0].get<double>(), p[1].get<double>());
    }
    rings.push_back(std::move(r));
  }
  return rings;
}

}  // namespace

GeoJsonFootprintPage parseGeoJsonFootprints(const std::string& text, const GeoJsonFootprintFields& fields,
                                            const std::string& name, Diagnostics& diag) {
  GeoJsonFootprintPage page;
  const json doc = parseFeatureCollection(text, name, page.next);
  for (const json& f : doc["features"]) {
    const std::size_t index = page.features++;
    std::string id = std::to_string(index);
    if (f.is_object() && f.contains("id") && (f["id"].is_string() || f["id"].is_number()))
      id = f["id"].is_string() ? f["id"].get<std::string>() : f["id"].dump();
    const std::string where = name + ": feature " + id;
    try {
      if (!f.is_object() || !f.contains("geometry") || !f["geometry"].is_object())
        throw InputError(where + ": no geometry (skipped)");
      const json& g = f["geometry"];
      const std::string type = g.value("type", std::string());
      const json props = f.value("properties", json::object());
      Footprint base;
      base.height = numberOf(props, fields.height);
      if (fields.base) base.base = numberOf(props, *fields.base);
      if (fields.top) base.top = numberOf(props, *fields.top);
      base.validFrom = textOf(props, fields.validFrom);
      base.validTo = textOf(props, fields.validTo);
      if (!base.height && !base.top)
        throw InputError(where + ": no usable height ('" + fields.height + "' missing or not a number; skipped)");
      if (type == "Polygon") {
        Footprint fp = base;
        fp.id = id;
        fp.rings = ringsOf(g.value("coordinates", json()), where);
        page.footprints.push_back(std::move(fp));
      } else if (type == "MultiPolygon" && g.contains("coordinates") && g["coordinates"].is_array()) {
        std::size_t part = 0;
        for (const json& poly : g["coordinates"]) {
          Footprint fp = base;
          fp.id = id + "." + std::to_string(part++);
          fp.rings = ringsOf(poly, where);
          page.footprints.push_back(std::move(fp));
        }
      } else {
        throw InputError(where + ": geometry '" + type + "', expected Polygon or MultiPolygon (skipped)");
      }
    } catch (const InputError& e) {
      diag.warn(e.what());
    }
  }
  return page;
}

Heightfield parseAaiGrid(const std::string& text, const std::string& name) {
  std::istringstream in(text);
  in.imbue(std::locale::classic());
  double ncols = -1, nrows = -1, x = NAN, y = NAN, cell = NAN, dx = NAN, dy = NAN;
  bool xCenter = false, yCenter = false;
  std::optional<double> nodata;
  std::string key;
  // The header: keywords, case-insensitive, until the first number.
  for (;;) {
    const std::streampos at = in.tellg();
    if (!(in >> key)) throw InputError(name + ": header: ended before the values");
    std::string k;
    for (char c : key) k += char(std::tolower(static_cast<unsigned char>(c)));
    if (k.empty() || !std::isalpha(static_cast<unsigned char>(k[0]))) {
      in.seekg(at);
      break;
    }
    double v = NAN;
    if (!(in >> v)) throw InputError(name + ": header: " + key + ": expected a number");
    if (k == "ncols")
      ncols = v;
    else if (k == "nrows")
      nrows = v;
    else if (k == "xllcorner" || k == "xllcenter")
      x = v, xCenter = k == "xllcenter";
    else if (k == "yllcorner" || k == "yllcenter")
      y = v, yCenter = k == "yllcenter";
    else if (k == "cellsize")
      cell = v;
    else if (k == "dx")
      dx = v;
    else if (k == "dy")
      dy = v;
    else if (k == "nodata_value")
      nodata = v;
    else
      throw InputError(name + ": header: unknown keyword '" + key + "'");
  }
  if (!std::isnan(cell)) dx = dy = cell;
  if (!(ncols >= 1 && nrows >= 1 && ncols == std::floor(ncols) && nrows == std::floor(nrows) && ncols * nrows <= 1e8))
    throw InputError(name + ": ncols, nrows: expected positive whole numbers (at most 1e8 samples)");
  if (!std::isfinite(x) || !std::isfinite(y)) throw InputError(name + ": xllcorner, yllcorner: missing");
  if (!(dx > 0.0) || !(dy > 0.0)) throw InputError(name + ": cellsize: expected a positive cell size");
  Heightfield h;
  h.cols = int(ncols);
  h.rows = int(nrows);
  h.cellX = dx;
  h.cellY = -dy;
  h.originX = xCenter ? x - 0.5 * dx : x;
  h.originY = (yCenter ? y - 0.5 * dy : y) + nrows * dy;
  h.z.resize(std::size_t(h.cols) * std::size_t(h.rows));
  for (std::size_t i = 0; i < h.z.size(); ++i) {
    double v = NAN;
    if (!(in >> v))
      throw InputError(name + ": values: " + std::to_string(i) + " of " + std::to_string(h.z.size()) +
                       " read, expected a number (truncated?)");
    h.z[i] = nodata && v == *nodata ? std::numeric_limits<float>::quiet_NaN() : float(v);
  }
  if (in >> key) throw InputError(name + ": values: more than ncols x nrows (" + key + "...)");
  return h;
}

}  // namespace hv
