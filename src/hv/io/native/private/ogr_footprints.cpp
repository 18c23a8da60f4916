#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_set>

#include "hv/io/native/footprints.h"
#include "hv/io/native/private/gdal_init.h"
#include "hv/io/native/private/service_fetch.h"

namespace hv {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(GDALDataset::ToHandle(ds)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

// What an attribute holds, as far as a numeric reading goes.
struct NumericField {
  enum class State { Missing, NotNumeric, Ok } state = State::Missing;
  double value = 0.0;
  std::string raw;  // the text as stored, for messages
};

// Integer, real or a numeric string ("12.5", " 7 "); anything else is NotNumeric.
NumericField readNumber(const OGRFeature& feature, const std::optional<std::string>& name) {
  NumericField out;
  if (!name) return out;
  const int index = feature.GetFieldIndex(name->c_str());
  if (index < 0 || !feature.IsFieldSetAndNotNull(index)) return out;
  out.raw = feature.GetFieldAsString(index);
  switch (feature.GetFieldDefnRef(index)->GetType()) {
    case OFTInteger:
    case OFTInteger64:
    case OFTReal:
      out.value = feature.GetFieldAsDouble(index);
      out.state = std::isfinite(out.value) ? NumericField::State::Ok : NumericField::State::NotNumeric;
      return out;
    case OFTString: {
      const char* begin = out.raw.c_str();
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(begin, &end);
      while (end && (*end == ' ' || *end == '\t')) ++end;
      const bool ok = end != begin && end && *end == '\0' && errno == 0 && std::isfinite(v);
      out.state = ok ? NumericField::State::Ok : NumericField::State::NotNumeric;
      out.value = ok ? v : 0.0;
      return out;
    }
    default:
      out.state = NumericField::State::NotNumeric;
      return out;
  }
}

std::optional<std::string> readString(const OGRFeature& feature, const std::optional<std::string>& name) {
  if (!name) return std::nullopt;
  const int index = feature.GetFieldIndex(name->c_str());
  if (index < 0 || !feature.IsFieldSetAndNotNull(index)) return std::nullopt;
  const OGRFieldType type = feature.GetFieldDefnRef(index)->GetType();
  if (type == OFTDate || type == OFTDateTime) {
    // OGR recognises dates in GeoJSON and would print them as "1920/01/01"; keep them ISO 8601.
    int y = 0, mo = 0, d = 0, h = 0, mi = 0, tz = 0;
    float s = 0.0f;
    if (!feature.GetFieldAsDateTime(index, &y, &mo, &d, &h, &mi, &s, &tz)) return std::nullopt;
    char text[40];
    if (type == OFTDate)
      std::snprintf(text, sizeof(text), "%04d-%02d-%02d", y, mo, d);
    else
      std::snprintf(text, sizeof(text), "%04d-%02d-%02dT%02d:%02d:%02d", y, mo, d, h, mi, int(s));
    return std::string(text);
  }
  return std::string(feature.GetFieldAsString(index));
}

// Ring in x, y (z of Polygon Z ignored), without GDAL's repeated closing point.
std::vector<glm::dvec2> readRing(const OGRLinearRing* ring) {
  std::vector<glm::dvec2> out;
  if (!ring) return out;
  const int n = ring->getNumPoints();
  out.reserve(size_t(std::max(n, 0)));
  for (int k = 0; k < n; ++k) out.emplace_back(ring->getX(k), ring->getY(k));
  if (out.size() > 1 && out.front() == out.back()) out.pop_back();
  return out;
}

size_t distinctPoints(const std::vector<glm::dvec2>& ring) {
  size_t n = 0;
  for (size_t k = 0; k < ring.size(); ++k) {
    bool seen = false;
    for (size_t m = 0; m < k && !seen; ++m) seen = ring[m] == ring[k];
    n += seen ? 0 : 1;
  }
  return n;
}

// Whether the layer's coordinates can be in `crs` when that is geographic: longitudes within
// ±360 degrees, latitudes within ±90. GeoJSON files written before RFC 7946 often hold projected
// coordinates without a `crs` member, which GDAL then reports as WGS 84.
bool degreesFit(OGRLayer* layer, const std::string& crs) {
  if (crs.empty()) return true;
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(crs.c_str(), OGRSpatialReference::SET_FROM_USER_INPUT_LIMITATIONS_get()) != OGRERR_NONE ||
      !srs.IsGeographic())
    return true;
  OGREnvelope extent;
  if (layer->GetExtent(&extent, TRUE) != OGRERR_NONE) return true;
  return std::abs(extent.MinX) <= 360.0 && std::abs(extent.MaxX) <= 360.0 && std::abs(extent.MinY) <= 90.0 &&
         std::abs(extent.MaxY) <= 90.0;
}

// A layer's footprints (in its CRS) into the scene frame; see footprints.h. Footprints PROJ cannot
// transform are dropped with a warning. Returns whether absolute levels were only converted to
// metres (warnLevelsAsTheyAre says so, once per layer).
bool georeferenceLayer(std::vector<Footprint>& footprints, size_t first, const GeoTransform& t, const std::string& path,
                       Diagnostics& diag) {
  if (t.isIdentity()) return false;
  const double heightUnit = t.source().heightToMetre();
  const bool throughProj = t.transformsHeights() && !t.sameCrs();
  bool levelsAsTheyAre = false;
  size_t kept = first;
  for (size_t k = first; k < footprints.size(); ++k) {
    Footprint& fp = footprints[k];
    try {
      const glm::dvec2 anchor = fp.rings.at(0).at(0);  // source coordinates, for absolute heights
      for (auto& ring : fp.rings)
        for (glm::dvec2& p : ring) p = glm::dvec2(t.point({p.x, p.y, 0.0}));
      if (fp.height) *fp.height *= heightUnit;
      for (std::optional<double>* level : {&fp.base, &fp.top}) {
        if (!*level) continue;
        if (throughProj) {
          **level = t.point({anchor.x, anchor.y, **level}).z;
        } else {
          **level *= heightUnit;
          levelsAsTheyAre = levelsAsTheyAre || !t.sameCrs();
        }
      }
    } catch (const InputError& e) {
      diag.warn(inputMessage(path, "feature " + fp.id + ": geometry", std::string(e.what()) + "; skipped"));
      continue;
    }
    if (kept != k) footprints[kept] = std::move(fp);
    ++kept;
  }
  footprints.resize(kept);
  return levelsAsTheyAre;
}

void warnLevelsAsTheyAre(const GeoTransform& t, const std::string& path, Diagnostics& diag) {
  diag.warn(inputMessage(path, "base/top",
                         "absolute elevations taken as they are, only converted to metres: " + t.source().summary() +
                             " and the scene's " + t.scene().summary() +
                             " do not both have a vertical axis; declare compound CRSs (e.g. EPSG:2154+5720) to "
                             "transform heights between vertical datums"));
}

// One layer's CRS and transform into the scene frame, and the prefix of its feature ids.
struct LayerFrame {
  std::optional<GeoTransform> transform;
  std::string prefix;
};

LayerFrame layerFrame(OGRLayer* layer, int layerCount, const SourceGeoref& georef, const std::string& path,
                      std::string& sourceCrs, Diagnostics& diag) {
  LayerFrame f;
  // The CRS first, so that a bad one is reported before any feature.
  std::string declared = georef.crs.empty() ? gdal::crsDefinition(layer->GetSpatialRef()) : georef.crs;
  if (georef.crs.empty() && !degreesFit(layer, declared)) {
    if (!georef.sceneCrs.empty())
      diag.warn(inputMessage(path, "CRS",
                             "the source says (or, GeoJSON without `crs`, RFC 7946 implies) a geographic CRS, but "
                             "its coordinates are not longitudes and latitudes: taken in the scene CRS; give "
                             "buildings.crs if that is wrong"));
    declared.clear();  // no CRS, then
  }
  const std::string crs = sourceCrsOf(georef, declared);
  if (sourceCrs.empty()) sourceCrs = crs.empty() ? declared : crs;
  if (!crs.empty()) {
    f.transform.emplace(sourceTransform(georef, crs, path, diag));
    if (f.transform->scene().geocentric || f.transform->source().geocentric)
      throw InputError(inputMessage(path, "CRS",
                                    "LOD1 footprints and the scene need a CRS with a vertical z (projected or "
                                    "compound), not a geocentric one"));
  }
  // With several layers, feature ids are only unique within their layer.
  f.prefix = layerCount > 1 ? std::string(layer->GetName()) + ":" : std::string();
  return f;
}

// One feature's footprints (in the layer's CRS) appended to `out`; a feature that cannot give
// any is warned about, naming its id.
void readFeature(const OGRFeature& feature, const std::string& fid, const FootprintFields& fields,
                 const std::string& path, std::vector<Footprint>& out, Diagnostics& diag) {
  auto warn = [&](const std::string& id, const std::string& field, const std::string& message) {
    diag.warn(inputMessage(path, "feature " + id + (field.empty() ? "" : ": " + field), message + "; skipped"));
  };

  const NumericField height = readNumber(feature, fields.height);
  const NumericField base = readNumber(feature, fields.base);
  const NumericField top = readNumber(feature, fields.top);
  if (base.state == NumericField::State::NotNumeric) {
    warn(fid, *fields.base, "expected a number, got '" + base.raw + "'");
    return;
  }
  if (top.state == NumericField::State::NotNumeric) {
    warn(fid, *fields.top, "expected a number, got '" + top.raw + "'");
    return;
  }
  const bool heightOk = height.state == NumericField::State::Ok && height.value > 0.0;
  // Without a usable height, only an absolute roof elevation can place the roof.
  if (!heightOk && top.state != NumericField::State::Ok) {
    const std::string why = height.state == NumericField::State::Missing ? "missing or null"
                            : height.state == NumericField::State::NotNumeric
                                ? "expected a number, got '" + height.raw + "'"
                                : "expected a height > 0, got " + height.raw;
    warn(fid, fields.height, why + " (and no roof elevation)");
    return;
  }

  const OGRGeometry* geometry = feature.GetGeometryRef();
  if (!geometry || geometry->IsEmpty()) {
    warn(fid, "geometry", "missing or empty");
    return;
  }
  std::vector<std::pair<std::string, const OGRPolygon*>> parts;
  switch (wkbFlatten(geometry->getGeometryType())) {
    case wkbPolygon:
      parts.emplace_back(fid, geometry->toPolygon());
      break;
    case wkbMultiPolygon: {
      const OGRMultiPolygon* multi = geometry->toMultiPolygon();
      for (int p = 0; p < multi->getNumGeometries(); ++p)
        parts.emplace_back(fid + "." + std::to_string(p), multi->getGeometryRef(p));
      break;
    }
    default:
      warn(fid, "geometry", std::string("expected a Polygon or MultiPolygon, got ") + geometry->getGeometryName());
      return;
  }

  for (const auto& [id, polygon] : parts) {
    Footprint fp;
    fp.id = id;
    bool ok = polygon && !polygon->IsEmpty();
    if (ok) {
      fp.rings.push_back(readRing(polygon->getExteriorRing()));
      for (int h = 0; h < polygon->getNumInteriorRings(); ++h)
        fp.rings.push_back(readRing(polygon->getInteriorRing(h)));
      for (const auto& ring : fp.rings) ok = ok && distinctPoints(ring) >= 3;
    }
    if (!ok) {
      warn(id, "geometry", "a ring has fewer than 3 distinct points");
      continue;
    }
    if (heightOk) fp.height = height.value;
    if (base.state == NumericField::State::Ok) fp.base = base.value;
    if (top.state == NumericField::State::Ok) fp.top = top.value;
    fp.validFrom = readString(feature, fields.validFrom);
    fp.validTo = readString(feature, fields.validTo);
    out.push_back(std::move(fp));
  }
}

// The point that places a feature in its tile: the first point of the outer ring of its first
// non-empty polygon (on the geometry, so a spatial filter holding it returns the feature). None
// for other geometry types and empty ones.
std::optional<glm::dvec2> firstVertex(const OGRGeometry* geometry) {
  if (!geometry || geometry->IsEmpty()) return std::nullopt;
  auto ofPolygon = [](const OGRPolygon* polygon) -> std::optional<glm::dvec2> {
    const OGRLinearRing* ring = polygon ? polygon->getExteriorRing() : nullptr;
    if (!ring || ring->getNumPoints() == 0) return std::nullopt;
    return glm::dvec2(ring->getX(0), ring->getY(0));
  };
  switch (wkbFlatten(geometry->getGeometryType())) {
    case wkbPolygon:
      return ofPolygon(geometry->toPolygon());
    case wkbMultiPolygon: {
      const OGRMultiPolygon* multi = geometry->toMultiPolygon();
      for (int p = 0; p < multi->getNumGeometries(); ++p)
        if (auto v = ofPolygon(multi->getGeometryRef(p))) return v;
      return std::nullopt;
    }
    default:
      return std::nullopt;
  }
}

// A layer's regular grid of tiles (layer CRS).
struct LayerGrid {
  glm::dvec2 origin{0.0};
  double size = 1.0;
  int nx = 1, ny = 1;
  bool extentKnown = false;  // false: one tile of unknown bounds (the layer gave no extent)
  int cellOf(glm::dvec2 p) const {
    const double fx = (p.x - origin.x) / size, fy = (p.y - origin.y) / size;
    const int ix = std::isfinite(fx) ? int(std::clamp(std::floor(fx), 0.0, double(nx - 1))) : 0;
    const int iy = std::isfinite(fy) ? int(std::clamp(std::floor(fy), 0.0, double(ny - 1))) : 0;
    return iy * nx + ix;
  }
  glm::dvec2 lo(int cell) const { return origin + size * glm::dvec2(cell % nx, cell / nx); }
  glm::dvec2 hi(int cell) const { return lo(cell) + glm::dvec2(size); }
};

// The extent is forced, for services too: OGR's WFS driver knows none from MapServer's
// capabilities and then reads the layer once, by pages, to find it (docs/services.md, "What OGR
// asks"); unforced, the layer would be a single tile of unknown bounds.
LayerGrid layerGrid(OGRLayer* layer, const FootprintTileOptions& options) {
  LayerGrid g;
  OGREnvelope e;
  if (layer->GetExtent(&e, TRUE) != OGRERR_NONE || !std::isfinite(e.MinX) || !std::isfinite(e.MaxX) ||
      !std::isfinite(e.MinY) || !std::isfinite(e.MaxY) || e.MaxX < e.MinX || e.MaxY < e.MinY)
    return g;  // one tile
  const double w = e.MaxX - e.MinX, h = e.MaxY - e.MinY;
  double size = options.tileSize;
  if (!(size > 0.0)) {
    const GIntBig count = layer->GetFeatureCount(TRUE);
    const double perTile = double(std::max<std::size_t>(options.perTile, 1));
    size = count > 0 ? std::sqrt(std::max(w * h, 1e-18) * perTile / double(count)) : std::max(w, h);
  }
  size = std::max({size, w / 256.0, h / 256.0, 1e-9 * std::max({std::abs(e.MinX), std::abs(e.MinY), 1.0})});
  g.origin = {e.MinX, e.MinY};
  g.size = size;
  g.extentKnown = true;
  g.nx = std::clamp(int(std::ceil(w / size)), 1, 256);
  g.ny = std::clamp(int(std::ceil(h / size)), 1, 256);
  return g;
}

// A tile's box in the scene frame: its corners and edge midpoints transformed (a point PROJ
// cannot transform leaves the box as wide as the others make it; none: infinite).
std::pair<glm::dvec2, glm::dvec2> sceneBox(const LayerGrid& g, int cell, const std::optional<GeoTransform>& t) {
  const glm::dvec2 lo = g.lo(cell), hi = g.hi(cell);
  if (!t || t->isIdentity()) return {lo, hi};
  glm::dvec2 a(INFINITY), b(-INFINITY);
  for (int i = 0; i <= 2; ++i)
    for (int j = 0; j <= 2; ++j) {
      const glm::dvec2 p = lo + (hi - lo) * glm::dvec2(0.5 * i, 0.5 * j);
      try {
        const glm::dvec2 q(t->point({p.x, p.y, 0.0}));
        a = glm::min(a, q);
        b = glm::max(b, q);
      } catch (const InputError&) {
      }
    }
  if (a.x > b.x) return {glm::dvec2(-INFINITY), glm::dvec2(INFINITY)};
  return {a, b};
}


// One tile of a layer with a fast spatial filter (a local index or a service): the features whose
// first vertex lies in `cell`, read into `footprints` (layer CRS). The rectangle is padded so that
// a first vertex on a tile border is always returned to its owner, and the border tiles reach past
// the layer's extent (which a GeoPackage may give stale). False when the reading failed part-way
// (said in `diag`).
bool readFastCell(OGRLayer* layer, const LayerGrid& grid, const std::string& prefix, int c, bool server,
                  const FootprintFields& fields, const std::string& path, std::vector<Footprint>& footprints,
                  std::unordered_set<GIntBig>& seenWithoutVertex, std::size_t& owned, Diagnostics& diag) {
  const double pad = 1e-6 * grid.size;
  const int ix = c % grid.nx, iy = c / grid.nx;
  // A server is asked for a box of sensible coordinates (one extent further, and within the
  // world for longitudes and latitudes), a local index for everything.
  const double far = (server ? 1.0 : 1e6) * grid.size * std::max(grid.nx, grid.ny);
  const glm::dvec2 lo = grid.lo(c), hi = grid.hi(c);
  double x0 = ix == 0 ? lo.x - far : lo.x - pad, y0 = iy == 0 ? lo.y - far : lo.y - pad;
  double x1 = ix == grid.nx - 1 ? hi.x + far : hi.x + pad, y1 = iy == grid.ny - 1 ? hi.y + far : hi.y + pad;
  const OGRSpatialReference* srs = layer->GetSpatialRef();
  if (server && srs && srs->IsGeographic()) {
    // OGR hands WFS and OAPIF layers over in longitude, latitude order.
    x0 = std::max(x0, -180.0), x1 = std::min(x1, 180.0), y0 = std::max(y0, -90.0), y1 = std::min(y1, 90.0);
  }
  if (grid.extentKnown || !server) layer->SetSpatialFilterRect(x0, y0, x1, y1);
  CPLErrorReset();
  layer->ResetReading();
  for (auto& feature : *layer) {
    const std::optional<glm::dvec2> v = firstVertex(feature->GetGeometryRef());
    if (v ? grid.cellOf(*v) != c : !seenWithoutVertex.insert(feature->GetFID()).second) continue;
    ++owned;
    if (gdal::ServiceProgress* progress = gdal::ServiceProgress::current()) progress->feature();
    readFeature(*feature, prefix + std::to_string(feature->GetFID()), fields, path, footprints, diag);
  }
  // A service that fails mid-way (a WFS page answered 500, a truncated response) ends the
  // iteration as if the layer had no more features: said, not silent.
  if (CPLGetLastErrorType() >= CE_Failure) {
    diag.error(inputMessage(path, prefix + "tile " + std::to_string(ix) + "," + std::to_string(iy),
                            "read failed after " + std::to_string(footprints.size()) + " footprint(s): " +
                                gdal::lastError("I/O error") + " (the rest of the tile left out)"));
    return false;
  }
  return true;
}

}  // namespace

std::vector<Footprint> readFootprints(const std::string& path, const FootprintFields& fields, Diagnostics& diag) {
  return readFootprints(path, fields, SourceGeoref{}, diag).footprints;  // no scene CRS: as they are
}

GeoreferencedFootprints readFootprints(const std::string& path, const FootprintFields& fields,
                                       const SourceGeoref& georef, Diagnostics& diag) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  gdal::requireOpenable(path, "footprints", true);
  DatasetPtr ds(gdal::openVector(path));
  if (!ds)
    throw InputError(inputMessage(path, "", "cannot open as a vector source: " + gdal::lastError("unknown format")));

  GeoreferencedFootprints result;
  std::vector<Footprint>& out = result.footprints;
  const int layerCount = ds->GetLayerCount();
  for (int l = 0; l < layerCount; ++l) {
    OGRLayer* layer = ds->GetLayer(l);
    const size_t first = out.size();
    const LayerFrame frame = layerFrame(layer, layerCount, georef, path, result.sourceCrs, diag);
    layer->ResetReading();
    for (auto& feature : *layer)
      readFeature(*feature, frame.prefix + std::to_string(feature->GetFID()), fields, path, out, diag);
    if (frame.transform && georeferenceLayer(out, first, *frame.transform, path, diag))
      warnLevelsAsTheyAre(*frame.transform, path, diag);
  }
  return result;
}

FootprintTileSource readFootprintTiles(const std::string& path, const FootprintFields& fields,
                                       const SourceGeoref& georef, const FootprintTileOptions& options,
                                       const std::function<void(FootprintTile&)>& consume, Diagnostics& diag) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  gdal::ServiceProgress progress("buildings", path);  // a line per service request (service_fetch.h)
  gdal::requireOpenable(path, "footprints", true);
  DatasetPtr ds(gdal::openVector(path));
  if (!ds)
    throw InputError(inputMessage(path, "", "cannot open as a vector source: " + gdal::lastError("unknown format")));

  FootprintTileSource source;
  source.path = path;
  const std::string driver = ds->GetDriverName() ? ds->GetDriverName() : "";
  const bool server = driver == "WFS" || driver == "OAPIF";
  const int layerCount = ds->GetLayerCount();
  // A WFS whose TYPENAME names no feature type opens with no layer: said, not an empty city.
  if (layerCount == 0)
    throw InputError(inputMessage(path, "",
                                  std::string("no layer in this ") + ds->GetDriverName() +
                                      " source (a WFS TYPENAME or an OGC API collection that the "
                                      "service does not offer? MapServer prefixes its type names: ms:...)"));
  std::size_t layerBase = 0;  // the index of the layer's first tile
  for (int l = 0; l < layerCount; ++l) {
    OGRLayer* layer = ds->GetLayer(l);
    CPLErrorReset();
    const LayerFrame frame = layerFrame(layer, layerCount, georef, path, source.sourceCrs, diag);
    const LayerGrid grid = layerGrid(layer, options);
    // A service that fails on its first requests (the schema, the count) gives an empty layer
    // from then on: the failure is the message, not an empty city.
    if (server && CPLGetLastErrorType() >= CE_Failure)
      throw InputError(inputMessage(path, frame.prefix, "the service failed: " + gdal::lastError("I/O error")));
    if (l == 0) source.tileSize = grid.size;
    const int cells = grid.nx * grid.ny;
    source.tilesTotal += std::size_t(cells);
    if (!server) source.features += std::size_t(std::max<GIntBig>(0, layer->GetFeatureCount(TRUE)));
    std::vector<char> wanted(static_cast<std::size_t>(cells), 1);
    FootprintTile tile;
    for (int c = 0; c < cells; ++c) {
      if (!options.wanted) continue;
      std::tie(tile.lo, tile.hi) = sceneBox(grid, c, frame.transform);
      wanted[std::size_t(c)] = options.wanted(tile.lo, tile.hi) ? 1 : 0;
    }
    source.tilesRead += std::size_t(std::count(wanted.begin(), wanted.end(), char(1)));
    bool levelsAsTheyAre = false;
    auto deliver = [&](int cell, std::vector<Footprint>& footprints) {
      if (frame.transform)
        levelsAsTheyAre = georeferenceLayer(footprints, 0, *frame.transform, path, diag) || levelsAsTheyAre;
      if (footprints.empty()) return;
      tile.index = layerBase + std::size_t(cell);
      std::tie(tile.lo, tile.hi) = sceneBox(grid, cell, frame.transform);
      tile.footprints = std::move(footprints);
      consume(tile);
      tile.footprints.clear();
    };

    // A WFS or OGC API - Features layer says it has no fast spatial filter, yet the server does
    // the filtering: each tile is one request with its bounding box (BBOX=, bbox=), paged
    // (STARTINDEX/COUNT, the "next" links), which is what reading by tile is for (docs/services.md).
    const bool fast = server || layer->TestCapability(OLCFastSpatialFilter) != 0;
    if (fast) {
      // Each wanted tile through the layer's spatial index (readFastCell).
      std::unordered_set<GIntBig> seenWithoutVertex;
      std::size_t owned = 0, k = 0;
      const auto n = std::size_t(std::count(wanted.begin(), wanted.end(), char(1)));
      for (int c = 0; c < cells; ++c) {
        if (!wanted[std::size_t(c)]) continue;
        progress.tile(++k, n);
        std::vector<Footprint> footprints;
        if (!readFastCell(layer, grid, frame.prefix, c, server, fields, path, footprints, seenWithoutVertex, owned,
                          diag))
          ++source.tilesFailed;
        deliver(c, footprints);
      }
      progress.tile(0, 0);
      layer->SetSpatialFilter(nullptr);
      if (std::all_of(wanted.begin(), wanted.end(), [](char w) { return w != 0; })) {
        const GIntBig count = layer->GetFeatureCount(TRUE);
        if (count > GIntBig(owned))
          diag.warn(inputMessage(path, frame.prefix + "features",
                                 std::to_string(count - GIntBig(owned)) +
                                     " feature(s) without geometry, which a spatial filter never returns; skipped"));
      }
    } else {
      // No spatial index: the layer is read once, each feature sorted into its tile.
      source.spatialFilter = false;
      if (source.note.empty())
        source.note = std::string(layer->GetName()) + " (" + ds->GetDriverName() +
                      ") has no fast spatial filter (no spatial index: a Shapefile without .qix, GeoJSON, ...): "
                      "read once and indexed in memory";
      std::vector<std::vector<Footprint>> byCell(static_cast<std::size_t>(cells));
      std::vector<Footprint> unplaced;  // features without a polygon: only their warnings
      CPLErrorReset();
      layer->ResetReading();
      std::size_t readCount = 0;
      for (auto& feature : *layer) {
        ++readCount;
        const std::optional<glm::dvec2> v = firstVertex(feature->GetGeometryRef());
        const int c = v ? grid.cellOf(*v) : -1;
        if (c >= 0 && !wanted[std::size_t(c)]) continue;
        readFeature(*feature, frame.prefix + std::to_string(feature->GetFID()), fields, path,
                    c >= 0 ? byCell[std::size_t(c)] : unplaced, diag);
      }
      if (CPLGetLastErrorType() >= CE_Failure) {
        ++source.tilesFailed;
        diag.error(inputMessage(path, frame.prefix + "features",
                                "read failed after " + std::to_string(readCount) +
                                    " feature(s): " + gdal::lastError("I/O error") + " (the rest left out)"));
      }
      for (int c = 0; c < cells; ++c) deliver(c, byCell[std::size_t(c)]);
    }
    if (levelsAsTheyAre) warnLevelsAsTheyAre(*frame.transform, path, diag);
    layerBase += std::size_t(cells);
  }
  return source;
}

struct FootprintTileReader::Impl {
  std::string path;
  FootprintFields fields;
  DatasetPtr ds;
  bool server = false;
  struct Layer {
    OGRLayer* layer = nullptr;
    LayerFrame frame;
    LayerGrid grid;
    std::size_t base = 0;  // the index of its first tile
  };
  std::vector<Layer> layers;
  std::size_t tiles = 0;
  std::vector<std::string> openWarnings;  // the layers' frames' (each read repeats them)
};

FootprintTileReader::FootprintTileReader(const std::string& path, const FootprintFields& fields,
                                         const SourceGeoref& georef, const FootprintTileOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.path = path;
  m.fields = fields;
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  gdal::requireOpenable(path, "footprints", true);
  m.ds.reset(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!m.ds)
    throw InputError(inputMessage(path, "", "cannot open as a vector source: " + gdal::lastError("unknown format")));
  const std::string driver = m.ds->GetDriverName() ? m.ds->GetDriverName() : "";
  m.server = driver == "WFS" || driver == "OAPIF";
  const int layerCount = m.ds->GetLayerCount();
  if (layerCount == 0) throw InputError(inputMessage(path, "", "no layer in this " + driver + " source"));
  Diagnostics diag;
  std::string sourceCrs;
  for (int l = 0; l < layerCount; ++l) {
    Impl::Layer layer;
    layer.layer = m.ds->GetLayer(l);
    CPLErrorReset();
    layer.frame = layerFrame(layer.layer, layerCount, georef, path, sourceCrs, diag);
    layer.grid = layerGrid(layer.layer, options);
    if (m.server && CPLGetLastErrorType() >= CE_Failure)
      throw InputError(inputMessage(path, layer.frame.prefix, "the service failed: " + gdal::lastError("I/O error")));
    if (!m.server && layer.layer->TestCapability(OLCFastSpatialFilter) == 0)
      throw InputError(inputMessage(path, layer.frame.prefix, "no fast spatial filter: cannot be read by tile"));
    layer.base = m.tiles;
    m.tiles += std::size_t(layer.grid.nx * layer.grid.ny);
    m.layers.push_back(std::move(layer));
  }
  if (!diag.errors.empty()) throw InputError(diag.errors.front());
  m.openWarnings = std::move(diag.warnings);
}

FootprintTileReader::~FootprintTileReader() = default;

std::size_t FootprintTileReader::tiles() const { return impl_->tiles; }

std::vector<Footprint> FootprintTileReader::read(std::size_t tile, Diagnostics& diag) {
  Impl& m = *impl_;
  if (tile >= m.tiles)
    throw std::out_of_range(m.path + ": building tile " + std::to_string(tile) + " of " + std::to_string(m.tiles));
  const gdal::QuietErrors quiet;
  for (const std::string& w : m.openWarnings) diag.warn(w);
  std::size_t l = 0;
  while (l + 1 < m.layers.size() && m.layers[l + 1].base <= tile) ++l;
  const Impl::Layer& layer = m.layers[l];
  std::vector<Footprint> footprints;
  std::unordered_set<GIntBig> seenWithoutVertex;
  std::size_t owned = 0;
  readFastCell(layer.layer, layer.grid, layer.frame.prefix, int(tile - layer.base), m.server, m.fields, m.path,
               footprints, seenWithoutVertex, owned, diag);
  layer.layer->SetSpatialFilter(nullptr);
  if (layer.frame.transform && georeferenceLayer(footprints, 0, *layer.frame.transform, m.path, diag))
    warnLevelsAsTheyAre(*layer.frame.transform, m.path, diag);
  return footprints;
}

}  // namespace hv
