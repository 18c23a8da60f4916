#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "hv/io/native/footprints.h"
#include "hv/io/native/private/gdal_init.h"

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
// transform are dropped with a warning.
void georeferenceLayer(std::vector<Footprint>& footprints, size_t first, const GeoTransform& t,
                       const std::string& path, Diagnostics& diag) {
  if (t.isIdentity()) return;
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
  if (levelsAsTheyAre)
    diag.warn(inputMessage(path, "base/top",
                           "absolute elevations taken as they are, only converted to metres: " + t.source().summary() +
                               " and the scene's " + t.scene().summary() +
                               " do not both have a vertical axis; declare compound CRSs (e.g. EPSG:2154+5720) to "
                               "transform heights between vertical datums"));
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
  DatasetPtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY));
  if (!ds)
    throw InputError(
        inputMessage(path, "", "cannot open as a vector source: " + gdal::lastError("unknown format")));

  GeoreferencedFootprints result;
  std::vector<Footprint>& out = result.footprints;
  const int layerCount = ds->GetLayerCount();
  for (int l = 0; l < layerCount; ++l) {
    OGRLayer* layer = ds->GetLayer(l);
    const size_t first = out.size();
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
    if (result.sourceCrs.empty()) result.sourceCrs = crs.empty() ? declared : crs;
    std::optional<GeoTransform> transform;
    if (!crs.empty()) {
      transform.emplace(sourceTransform(georef, crs, path, diag));
      if (transform->scene().geocentric || transform->source().geocentric)
        throw InputError(inputMessage(path, "CRS",
                                      "LOD1 footprints and the scene need a CRS with a vertical z (projected or "
                                      "compound), not a geocentric one"));
    }
    // With several layers, feature ids are only unique within their layer.
    const std::string prefix = layerCount > 1 ? std::string(layer->GetName()) + ":" : std::string();
    layer->ResetReading();
    for (auto& feature : *layer) {
      const std::string fid = prefix + std::to_string(feature->GetFID());
      auto warn = [&](const std::string& id, const std::string& field, const std::string& message) {
        diag.warn(
            inputMessage(path, "feature " + id + (field.empty() ? "" : ": " + field), message + "; skipped"));
      };

      const NumericField height = readNumber(*feature, fields.height);
      const NumericField base = readNumber(*feature, fields.base);
      const NumericField top = readNumber(*feature, fields.top);
      if (base.state == NumericField::State::NotNumeric) {
        warn(fid, *fields.base, "expected a number, got '" + base.raw + "'");
        continue;
      }
      if (top.state == NumericField::State::NotNumeric) {
        warn(fid, *fields.top, "expected a number, got '" + top.raw + "'");
        continue;
      }
      const bool heightOk = height.state == NumericField::State::Ok && height.value > 0.0;
      // Without a usable height, only an absolute roof elevation can place the roof.
      if (!heightOk && top.state != NumericField::State::Ok) {
        const std::string why = height.state == NumericField::State::Missing ? "missing or null"
                                : height.state == NumericField::State::NotNumeric
                                    ? "expected a number, got '" + height.raw + "'"
                                    : "expected a height > 0, got " + height.raw;
        warn(fid, fields.height, why + " (and no roof elevation)");
        continue;
      }

      const OGRGeometry* geometry = feature->GetGeometryRef();
      if (!geometry || geometry->IsEmpty()) {
        warn(fid, "geometry", "missing or empty");
        continue;
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
          warn(fid, "geometry",
               std::string("expected a Polygon or MultiPolygon, got ") + geometry->getGeometryName());
          continue;
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
        fp.validFrom = readString(*feature, fields.validFrom);
        fp.validTo = readString(*feature, fields.validTo);
        out.push_back(std::move(fp));
      }
    }
    if (transform) georeferenceLayer(out, first, *transform, path, diag);
  }
  return result;
}

}  // namespace hv
