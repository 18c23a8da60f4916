#include "hv/io/native/camera_catalog.h"

#include <cpl_conv.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include "hv/io/camera_properties.h"
#include "hv/io/native/private/gdal_init.h"
#include "hv/io/native/remote.h"
#include "hv/util/dates.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <regex>
#include <sstream>
#include <string_view>

namespace hv {

namespace fs = std::filesystem;

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(GDALDataset::ToHandle(ds)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

// A layer ExecuteSQL returned, released by its dataset.
struct ResultSet {
  GDALDataset* ds = nullptr;
  OGRLayer* layer = nullptr;
  ResultSet(GDALDataset* d, OGRLayer* l) : ds(d), layer(l) {}
  ~ResultSet() {
    if (layer) ds->ReleaseResultSet(layer);
  }
  ResultSet(const ResultSet&) = delete;
  ResultSet& operator=(const ResultSet&) = delete;
};

// The columns besides `fid` and `centre` (docs/catalog.md, "Table layout"). Lens distortion as its
// model and the twelve numbers of hv::LensDistortion, so that every model round-trips as it is.
constexpr const char* kColumns =
    "fid, id, image, mask, width, height, focal_x, focal_y, principal_x, principal_y, skew, cam_from_world, "
    "distortion_model, distortion, date, colour_gain, colour_offset";

std::string where(const std::string& connection, const std::string& table) {
  return redactConnection(connection) + ": table " + table;
}

// "schema"."name": the table name is checked (checkCatalogTableName), quoted to keep its case.
std::string quotedTable(const std::string& table) {
  const std::size_t dot = table.find('.');
  if (dot == std::string::npos) return "\"" + table + "\"";
  return "\"" + table.substr(0, dot) + "\".\"" + table.substr(dot + 1) + "\"";
}

DatasetPtr openDatabase(const std::string& connection, bool update, const std::string& table) {
  gdal::ensureRegistered();
  const std::string conn = catalogConnection(connection);
  const char* const drivers[] = {"PostgreSQL", nullptr};
  // Only the catalog's table: the driver would otherwise list every table of the database.
  const std::string tables = "TABLES=" + table;
  const char* const options[] = {tables.c_str(), nullptr};
  DatasetPtr ds(GDALDataset::Open(conn.c_str(), GDAL_OF_VECTOR | (update ? GDAL_OF_UPDATE : 0), drivers,
                                  update ? nullptr : options, nullptr));
  if (!ds) {
    // libpq's message spans lines: one line here, as every message.
    std::string why = gdal::lastError("GDAL's PostgreSQL driver could not open it");
    why = std::regex_replace(why, std::regex(R"(\s*\n\s*)"), " ");
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    throw InputError(redactConnection(connection) + ": cannot connect: " + why);
  }
  return ds;
}

void execute(GDALDataset& ds, const std::string& sql, const std::string& what) {
  CPLErrorReset();
  OGRLayer* result = ds.ExecuteSQL(sql.c_str(), nullptr, nullptr);
  if (result) ds.ReleaseResultSet(result);
  if (CPLGetLastErrorType() >= CE_Failure)
    throw InputError(what + ": " + gdal::lastError("SQL failed") + " (" + sql + ")");
}

// A field's value as text, empty when missing or NULL.
std::string stringField(const OGRFeature& f, int index) {
  if (index < 0 || !f.IsFieldSetAndNotNull(index)) return {};
  return f.GetFieldAsString(index);
}

// An OGR field as the portable camera decoder takes it (hv/io/camera_properties.h): text, a
// list field, or any other field as the number OGR reads of it.
CameraProperty fieldValue(const OGRFeature& f, int index) {
  CameraProperty v;
  if (index < 0 || !f.IsFieldSetAndNotNull(index)) return v;
  const OGRFieldType type = f.GetFieldDefnRef(index)->GetType();
  v.type = OGRFieldDefn::GetFieldTypeName(type);
  if (type == OFTString) {
    v.kind = CameraProperty::Kind::Text;
    v.text = f.GetFieldAsString(index);
  } else if (type == OFTRealList || type == OFTIntegerList || type == OFTInteger64List) {
    v.kind = CameraProperty::Kind::NumberList;
    int n = 0;
    if (type == OFTRealList) {
      const double* w = f.GetFieldAsDoubleList(index, &n);
      v.list.assign(w, w + n);
    } else if (type == OFTIntegerList) {
      const int* w = f.GetFieldAsIntegerList(index, &n);
      for (int i = 0; i < n; ++i) v.list.push_back(w[i]);
    } else {
      const GIntBig* w = f.GetFieldAsInteger64List(index, &n);
      for (int i = 0; i < n; ++i) v.list.push_back(double(w[i]));
    }
  } else if (type == OFTInteger || type == OFTInteger64 || type == OFTReal) {
    v.kind = CameraProperty::Kind::Number;
    v.number = f.GetFieldAsDouble(index);
    v.text = f.GetFieldAsString(index);
  } else {
    v.kind = CameraProperty::Kind::Other;
    v.text = f.GetFieldAsString(index);
  }
  return v;
}

// Doubles are written as text with 17 significant digits, which PostgreSQL parses back to the
// same double (OGR's own formatting keeps 15 digits), into text columns made float8 afterwards.
std::string exactText(double v) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

void setReal(OGRFeature& f, const char* name, double v) { f.SetField(name, exactText(v).c_str()); }

void setRealList(OGRFeature& f, const char* name, const std::vector<double>& v) {
  CPLStringList list;
  for (double d : v) list.AddString(exactText(d).c_str());
  f.SetField(name, list.List());
}

std::vector<double> distortionNumbers(const LensDistortion& d) {
  return {d.center.x, d.center.y, d.scale.x, d.scale.y, d.c3, d.c5, d.c7, d.p1, d.p2, d.l1, d.l2, d.r2max};
}

// The columns every camera writer fills alike (docs/catalog.md, "Table layout"); how a number
// travels is the writer's: `real` for a number column, `list` for an array column.
using RealWriter = void (*)(OGRFeature&, const char*, double);
using RealListWriter = void (*)(OGRFeature&, const char*, const std::vector<double>&);
void fillCameraFeature(OGRFeature& feature, const Photo& p, std::int64_t fid, RealWriter real, RealListWriter list) {
  const Camera& c = p.camera;
  feature.SetFID(fid);
  feature.SetField("id", c.id.c_str());
  if (!p.imagePath.empty()) feature.SetField("image", p.imagePath.c_str());
  if (!p.maskPath.empty()) feature.SetField("mask", p.maskPath.c_str());
  feature.SetField("width", c.width);
  feature.SetField("height", c.height);
  real(feature, "focal_x", c.focal.x);
  real(feature, "focal_y", c.focal.y);
  real(feature, "principal_x", c.principal.x);
  real(feature, "principal_y", c.principal.y);
  real(feature, "skew", c.skew);
  std::vector<double> rowMajor(9);
  mat3ToRowMajor(c.camFromWorld, rowMajor.data());
  list(feature, "cam_from_world", rowMajor);
  if (c.distortion) {
    feature.SetField("distortion_model", c.distortion->model == LensDistortion::Model::Fisheye ? "fisheye" : "polynomial");
    list(feature, "distortion", distortionNumbers(*c.distortion));
  }
  if (!p.date.empty()) feature.SetField("date", p.date.c_str());
  list(feature, "colour_gain", {p.colour.gain.x, p.colour.gain.y, p.colour.gain.z});
  list(feature, "colour_offset", {p.colour.offset.x, p.colour.offset.y, p.colour.offset.z});
  feature.SetGeometryDirectly(new OGRPoint(c.center.x, c.center.y, c.center.z));
}

// The columns of docs/catalog.md's layout in one OGR layer definition (-1: absent). The centre is
// the columns centre_x/y/z when the layer has them (the catalog's SQL), else the feature's point.
struct CameraFields {
  int fid, id, image, mask, width, height, fx, fy, cx, cy, skew, rot, model, dist, date, gain, offset, x, y, z;
  explicit CameraFields(OGRFeatureDefn* defn) {
    auto column = [&](const char* name) { return defn->GetFieldIndex(name); };
    fid = column("fid"), id = column("id"), image = column("image"), mask = column("mask"), width = column("width"),
    height = column("height"), fx = column("focal_x"), fy = column("focal_y"), cx = column("principal_x"),
    cy = column("principal_y"), skew = column("skew"), rot = column("cam_from_world"),
    model = column("distortion_model"), dist = column("distortion"), date = column("date"),
    gain = column("colour_gain"), offset = column("colour_offset"), x = column("centre_x"), y = column("centre_y"),
    z = column("centre_z");
  }
  // The index of the column `name` (hv/io/camera_properties.h's names), -1 when absent.
  int index(const char* name) const {
    const std::pair<const char*, int> columns[] = {
        {"id", id},         {"image", image},     {"mask", mask},           {"width", width},
        {"height", height}, {"focal_x", fx},      {"focal_y", fy},          {"principal_x", cx},
        {"principal_y", cy}, {"skew", skew},      {"cam_from_world", rot},  {"distortion_model", model},
        {"distortion", dist}, {"date", date},     {"colour_gain", gain},    {"colour_offset", offset},
        {"centre_x", x},    {"centre_y", y},      {"centre_z", z}};
    for (const auto& [n, i] : columns)
      if (std::strcmp(n, name) == 0) return i;
    return -1;
  }
};

// One feature's camera, every field checked (the per-feature decoder of both the PostGIS catalog
// and any OGR point layer): hv::decodeCameraProperties, the browser's decoder too. Throws
// InputError naming the field; validateCamera's own checks included.
Photo decodeCamera(const OGRFeature& f, const CameraFields& i) {
  const auto property = [&](const char* name) { return fieldValue(f, i.index(name)); };
  const auto point = [&] {
    const OGRGeometry* g = f.GetGeometryRef();
    if (!g || g->IsEmpty() || wkbFlatten(g->getGeometryType()) != wkbPoint)
      throw InputError("centre: expected a point geometry");
    const OGRPoint* pt = g->toPoint();
    if (!pt->Is3D()) throw InputError("centre: expected a 3D point (x, y, z), got a 2D one");
    return glm::dvec3(pt->getX(), pt->getY(), pt->getZ());
  };
  return decodeCameraProperties(property, point);
}

// Every feature of `layer` decoded into `out`; a feature that cannot be is named (`at`, its fid,
// its camera, the field) and left out.
void decodeLayer(OGRLayer& layer, const std::string& at, std::vector<Photo>& out, Diagnostics& diag) {
  const CameraFields fields(layer.GetLayerDefn());
  for (std::unique_ptr<OGRFeature> f(layer.GetNextFeature()); f; f.reset(layer.GetNextFeature())) {
    const std::string fid = fields.fid >= 0 ? stringField(*f, fields.fid) : std::to_string(f->GetFID());
    const std::string id = stringField(*f, fields.id);
    try {
      out.push_back(decodeCamera(*f, fields));
    } catch (const InputError& e) {
      std::string what = e.what();
      const std::string named = "camera '" + id + "': ";  // validateCamera's own prefix
      if (what.rfind(named, 0) == 0) what = what.substr(named.size());
      diag.error(at + ": fid " + fid + " (camera '" + id + "'): " + what + " (camera skipped)");
    }
  }
}

}  // namespace

std::string catalogConnection(const std::string& connection) {
  if (connection.find('\0') != std::string::npos) throw InputError("catalog connection: contains a NUL byte");
  if (connection.rfind("postgresql://", 0) == 0 || connection.rfind("postgres://", 0) == 0) {
    // GDAL's driver knows the "postgresql://" scheme only.
    return connection.rfind("postgres://", 0) == 0 ? "postgresql://" + connection.substr(11) : connection;
  }
  if (connection.rfind("PG:", 0) == 0) return connection;
  throw InputError("catalog connection '" + redactConnection(connection) +
                   "': expected a PostgreSQL connection, \"postgresql://user@host:port/database\" or "
                   "\"PG:host=... dbname=...\"");
}

std::string redactConnection(const std::string& connection) {
  static const std::regex uriPassword(R"(^(postgres(ql)?://[^:/@]*):[^@]*@)");
  static const std::regex keywordPassword(R"(password\s*=\s*('[^']*'|\S+))", std::regex::icase);
  std::string out = std::regex_replace(connection, uriPassword, "$1:***@");
  return std::regex_replace(out, keywordPassword, "password=***");
}

void checkCatalogTableName(const std::string& table, const std::string& field) {
  static const std::regex name(R"(^([A-Za-z_][A-Za-z0-9_]*\.)?[A-Za-z_][A-Za-z0-9_]*$)");
  if (table.size() > 127 || !std::regex_match(table, name))
    throw InputError(field +
                     ": expected a table name, letters, digits and underscores (optionally schema.name), got \"" +
                     table + "\"");
}

CatalogWriteResult writeCameraCatalog(const std::vector<Photo>& photos, const std::string& crs,
                                      const std::string& connection, const std::string& table) {
  checkCatalogTableName(table, "table");
  gdal::QuietErrors quiet;
  const std::string at = where(connection, table);
  // COPY rather than one INSERT a row: the 10^6-camera benchmark loads in seconds.
  CPLConfigOptionSetter copy("PG_USE_COPY", "YES", false);
  DatasetPtr ds = openDatabase(connection, true, table);

  OGRSpatialReference srs;
  if (!crs.empty()) {
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE)
      throw InputError(at + ": crs '" + crs + "': GDAL cannot read it as a CRS");
  }
  if (ds->StartTransaction(FALSE) != OGRERR_NONE)
    throw InputError(at + ": cannot start a transaction: " + gdal::lastError("no reason given"));
  bool committed = false;
  struct Rollback {
    GDALDataset& ds;
    bool& committed;
    ~Rollback() {
      if (!committed) ds.RollbackTransaction();
    }
  } rollback{*ds, committed};

  if (const std::size_t dot = table.find('.'); dot != std::string::npos)
    execute(*ds, "CREATE SCHEMA IF NOT EXISTS \"" + table.substr(0, dot) + "\"", at);
  const char* const layerOptions[] = {"GEOMETRY_NAME=centre",
                                      "FID=fid",
                                      "DIM=XYZ",
                                      "SPATIAL_INDEX=GIST",
                                      "OVERWRITE=YES",
                                      "LAUNDER=NO",
                                      "DESCRIPTION=histoview camera catalog (docs/catalog.md)",
                                      nullptr};
  CPLErrorReset();
  OGRLayer* layer =
      ds->CreateLayer(table.c_str(), crs.empty() ? nullptr : &srs, wkbPoint25D, const_cast<char**>(layerOptions));
  if (!layer) throw InputError(at + ": cannot create the table: " + gdal::lastError("no reason given"));
  struct Field {
    const char* name;
    OGRFieldType type;
  };
  const Field fields[] = {{"id", OFTString},
                          {"image", OFTString},
                          {"mask", OFTString},
                          {"width", OFTInteger},
                          {"height", OFTInteger},
                          {"focal_x", OFTString},
                          {"focal_y", OFTString},
                          {"principal_x", OFTString},
                          {"principal_y", OFTString},
                          {"skew", OFTString},
                          {"cam_from_world", OFTStringList},
                          {"distortion_model", OFTString},
                          {"distortion", OFTStringList},
                          {"date", OFTString},
                          {"date_from", OFTDate},
                          {"date_to", OFTDate},
                          {"colour_gain", OFTStringList},
                          {"colour_offset", OFTStringList}};
  for (const Field& f : fields) {
    OGRFieldDefn defn(f.name, f.type);
    if (std::string(f.name) == "id" || std::string(f.name) == "width" || std::string(f.name) == "height")
      defn.SetNullable(FALSE);
    if (layer->CreateField(&defn) != OGRERR_NONE)
      throw InputError(at + ": cannot create column " + f.name + ": " + gdal::lastError("no reason given"));
  }

  std::int64_t fid = 0;
  for (const Photo& p : photos) {
    const Camera& c = p.camera;
    OGRFeature feature(layer->GetLayerDefn());
    fillCameraFeature(feature, p, ++fid, setReal, setRealList);
    // The interval the date names, for SQL (the `dates` range); PostgreSQL has no year 0.
    if (const auto interval = p.date.empty() ? std::nullopt : parseDate(p.date)) {
      const CivilDate a = civilFromDays(interval->first), b = civilFromDays(interval->last);
      if (a.year >= 1) {
        feature.SetField("date_from", int(a.year), int(a.month), int(a.day));
        feature.SetField("date_to", int(b.year), int(b.month), int(b.day));
      }
    }
    CPLErrorReset();
    if (layer->CreateFeature(&feature) != OGRERR_NONE)
      throw InputError(at + ": camera '" + c.id + "': cannot write: " + gdal::lastError("no reason given"));
  }
  // The numbers written as text become float8 (setReal); the dates as a range. OGR made the 2D
  // GiST index on `centre` (SPATIAL_INDEX=GIST), which the nearest-camera query runs on.
  const std::string t = quotedTable(table);
  std::string types;
  for (const Field& f : fields) {
    if (f.type != OFTString && f.type != OFTStringList) continue;
    const std::string n = f.name;
    if (n == "id" || n == "image" || n == "mask" || n == "distortion_model" || n == "date") continue;
    const char* type = f.type == OFTStringList ? "float8[]" : "float8";
    types += (types.empty() ? " ALTER COLUMN " : ", ALTER COLUMN ") + n + " TYPE " + type + " USING " + n + "::" + type;
  }
  execute(*ds, "ALTER TABLE " + t + types, at);
  execute(*ds,
          "ALTER TABLE " + t +
              " ADD COLUMN dates daterange GENERATED ALWAYS AS (daterange(date_from, date_to, '[]')) STORED",
          at);
  if (ds->CommitTransaction() != OGRERR_NONE)
    throw InputError(at + ": cannot commit: " + gdal::lastError("no reason given"));
  committed = true;
  execute(*ds, "ANALYZE " + t, at);

  CatalogWriteResult out;
  out.rows = photos.size();
  ResultSet srid(ds.get(), ds->ExecuteSQL(("SELECT max(ST_SRID(centre)) FROM " + t).c_str(), nullptr, nullptr));
  if (srid.layer)
    if (std::unique_ptr<OGRFeature> f(srid.layer->GetNextFeature()); f) out.srid = f->GetFieldAsInteger(0);
  return out;
}

CatalogCameras readCameraCatalog(const std::string& connection, const std::string& table, Diagnostics& diag) {
  checkCatalogTableName(table, "table");
  gdal::QuietErrors quiet;
  const std::string at = where(connection, table);
  DatasetPtr ds = openDatabase(connection, false, table);
  OGRLayer* layer = ds->GetLayerByName(table.c_str());
  if (!layer) throw InputError(at + ": no such table with a geometry column (histoview catalog load writes one)");
  CatalogCameras out;
  out.crs = gdal::crsDefinition(layer->GetSpatialRef());

  const std::string sql = std::string("SELECT ") + kColumns +
                          ", ST_X(centre) AS centre_x, ST_Y(centre) AS centre_y, ST_Z(centre) AS centre_z FROM " +
                          quotedTable(table) + " ORDER BY fid";
  CPLErrorReset();
  ResultSet rows(ds.get(), ds->ExecuteSQL(sql.c_str(), nullptr, nullptr));
  if (!rows.layer)
    throw InputError(at + ": cannot read: " + gdal::lastError("no result") +
                     " (expected the columns of docs/catalog.md, as histoview catalog load writes them)");
  decodeLayer(*rows.layer, at, out.photos, diag);
  if (CPLGetLastErrorType() >= CE_Failure)
    throw InputError(at + ": reading stopped: " + gdal::lastError("no reason given"));
  return out;
}

struct CameraCatalog::Impl {
  DatasetPtr ds;
  std::string table, at;
  std::size_t rows = 0;
  int srid = 0;
};

CameraCatalog::CameraCatalog(const std::string& connection, const std::string& table)
    : impl_(std::make_unique<Impl>()) {
  checkCatalogTableName(table, "table");
  gdal::QuietErrors quiet;
  impl_->table = table;
  impl_->at = where(connection, table);
  impl_->ds = openDatabase(connection, false, table);
  CPLErrorReset();
  ResultSet r(impl_->ds.get(),
              impl_->ds->ExecuteSQL(("SELECT count(*), max(ST_SRID(centre)) FROM " + quotedTable(table)).c_str(),
                                    nullptr, nullptr));
  if (!r.layer) throw InputError(impl_->at + ": cannot read: " + gdal::lastError("no result"));
  std::unique_ptr<OGRFeature> f(r.layer->GetNextFeature());
  if (!f) throw InputError(impl_->at + ": cannot read: " + gdal::lastError("no row"));
  impl_->rows = std::size_t(f->GetFieldAsInteger64(0));
  impl_->srid = f->GetFieldAsInteger(1);
}

CameraCatalog::~CameraCatalog() = default;
CameraCatalog::CameraCatalog(CameraCatalog&&) noexcept = default;
CameraCatalog& CameraCatalog::operator=(CameraCatalog&&) noexcept = default;

std::size_t CameraCatalog::size() const { return impl_->rows; }
int CameraCatalog::srid() const { return impl_->srid; }

namespace {

// The query point as an EWKT constant, exactly as given (%.17g).
std::string pointLiteral(const glm::dvec3& p, int srid, const std::string& at) {
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
    throw InputError(at + ": nearest cameras: the position is not finite");
  char text[160];
  std::snprintf(text, sizeof(text), "'SRID=%d;POINT Z (%.17g %.17g %.17g)'::geometry", srid, p.x, p.y, p.z);
  return text;
}

// The k cameras nearest to the point `q` in 3D, ascending distance, ties broken by fid as in
// hv::ibr::CameraIndex (docs/catalog.md, "Nearest cameras"). The 2016 paper's `<->` (2D distance,
// on the 2D GiST index) finds the k nearest in plan; the largest 3D distance r among them bounds
// the 3D k-th nearest, and every camera within r in 3D is within r in plan: the box of half-width
// r around q (`&&`, the same index) holds the exact 3D answer, ranked here. PostGIS' n-D `<<->>`
// would give it in one scan, but on a 10^6-row table its n-D index scan read 6 times the pages.
std::string nearestSql(const std::string& table, const std::string& q, std::size_t k) {
  const std::string limit = std::to_string(k);
  return "SELECT fid, id, ST_3DDistance(centre, " + q + ") AS d FROM " + table + " WHERE centre && ST_Expand(" + q +
         ", (SELECT max(ST_3DDistance(s.centre, " + q + ")) FROM (SELECT centre FROM " + table +
         " ORDER BY centre <-> " + q + " LIMIT " + limit + ") AS s)) ORDER BY d, fid LIMIT " + limit;
}

// Ties broken by fid as in hv::ibr::CameraIndex, then the k nearest.
void keepNearest(std::vector<CameraCatalog::Neighbour>& n, std::size_t k) {
  std::sort(n.begin(), n.end(), [](const CameraCatalog::Neighbour& a, const CameraCatalog::Neighbour& b) {
    return a.distance != b.distance ? a.distance < b.distance : a.fid < b.fid;
  });
  if (n.size() > k) n.resize(k);
}

}  // namespace

std::vector<CameraCatalog::Neighbour> CameraCatalog::nearestCameras(const glm::dvec3& position, std::size_t k) const {
  std::vector<Neighbour> out;
  if (k == 0) return out;
  const std::string point = pointLiteral(position, impl_->srid, impl_->at);
  gdal::QuietErrors quiet;
  const std::string sql = "SELECT fid, id, d FROM (" + nearestSql(quotedTable(impl_->table), point, k) + ") AS n";
  CPLErrorReset();
  ResultSet r(impl_->ds.get(), impl_->ds->ExecuteSQL(sql.c_str(), nullptr, nullptr));
  if (!r.layer) throw InputError(impl_->at + ": nearest cameras: " + gdal::lastError("no result") + " (" + sql + ")");
  for (std::unique_ptr<OGRFeature> f(r.layer->GetNextFeature()); f; f.reset(r.layer->GetNextFeature()))
    out.push_back({f->GetFieldAsInteger64(0), f->GetFieldAsString(1), f->GetFieldAsDouble(2)});
  keepNearest(out, k);
  return out;
}

std::vector<std::vector<CameraCatalog::Neighbour>> CameraCatalog::nearestCameras(
    const std::vector<glm::dvec3>& positions, std::size_t k) const {
  std::vector<std::vector<Neighbour>> out(positions.size());
  if (k == 0 || positions.empty()) return out;
  std::string values;
  for (std::size_t i = 0; i < positions.size(); ++i)
    values += (i ? ", (" : "(") + std::to_string(i) + ", " + pointLiteral(positions[i], impl_->srid, impl_->at) + ")";
  gdal::QuietErrors quiet;
  // nearestSql per position, as a lateral subquery (the point is a parameter of it, which the
  // 2D index searches by as it does a constant).
  const std::string sql = "SELECT v.i, n.fid, n.id, n.d FROM (VALUES " + values + ") AS v(i, q), LATERAL (" +
                          nearestSql(quotedTable(impl_->table), "v.q", k) + ") AS n";
  CPLErrorReset();
  ResultSet r(impl_->ds.get(), impl_->ds->ExecuteSQL(sql.c_str(), nullptr, nullptr));
  if (!r.layer)
    throw InputError(impl_->at + ": nearest cameras (" + std::to_string(positions.size()) +
                     " positions): " + gdal::lastError("no result"));
  for (std::unique_ptr<OGRFeature> f(r.layer->GetNextFeature()); f; f.reset(r.layer->GetNextFeature())) {
    const std::int64_t i = f->GetFieldAsInteger64(0);
    if (i >= 0 && std::size_t(i) < out.size())
      out[std::size_t(i)].push_back({f->GetFieldAsInteger64(1), f->GetFieldAsString(2), f->GetFieldAsDouble(3)});
  }
  for (std::vector<Neighbour>& n : out) keepNearest(n, k);
  return out;
}

namespace {

std::string jsonNumbers(const std::vector<double>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? "," : "") + exactText(v[i]);
  return out + "]";
}

// The OGR driver for a file name: GeoPackage or GeoJSON.
const char* driverFor(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char ch) { return char(std::tolower(ch)); });
  if (ext == ".gpkg") return "GPKG";
  if (ext == ".geojson" || ext == ".json") return "GeoJSON";
  return nullptr;
}

}  // namespace

std::size_t writeOgrCameras(const std::vector<Photo>& photos, const std::string& crs, const std::string& path,
                            const std::string& layerName) {
  gdal::ensureRegistered();
  gdal::QuietErrors quiet;
  const std::string at = path + ": layer " + layerName;
  const char* driverName = driverFor(path);
  if (!driverName) throw InputError(path + ": expected a .gpkg (GeoPackage) or .geojson file name");
  if (layerName.empty()) throw InputError(path + ": the layer needs a name");
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driverName);
  if (!driver) throw InputError(path + ": GDAL has no " + driverName + " driver");
  std::error_code ec;
  fs::remove(path, ec);  // replaced, as the catalog's table is
  DatasetPtr ds(driver->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!ds) throw InputError(path + ": cannot create: " + gdal::lastError("no reason given"));
  OGRSpatialReference srs;
  if (!crs.empty()) {
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE)
      throw InputError(at + ": crs '" + crs + "': GDAL cannot read it as a CRS");
  }
  const bool geojson = std::string(driverName) == "GeoJSON";
  // GeoJSON: every double with 17 significant digits (exact), the CRS named (not RFC 7946's WGS 84).
  const char* const jsonOptions[] = {"RFC7946=NO", "SIGNIFICANT_FIGURES=17", nullptr};
  const char* const gpkgOptions[] = {"GEOMETRY_NAME=centre", "FID=fid", "SPATIAL_INDEX=YES",
                                     "DESCRIPTION=histoview cameras (docs/catalog.md)", nullptr};
  OGRLayer* layer = ds->CreateLayer(layerName.c_str(), crs.empty() ? nullptr : &srs, wkbPoint25D,
                                    const_cast<char**>(geojson ? jsonOptions : gpkgOptions));
  if (!layer) throw InputError(at + ": cannot create the layer: " + gdal::lastError("no reason given"));
  struct Field {
    const char* name;
    OGRFieldType type;
  };
  // The catalog's columns; number arrays as JSON text "[a,b,...]" (17 digits), which every driver
  // and WFS server passes on as it is.
  const Field fields[] = {
      {"id", OFTString},         {"image", OFTString}, {"mask", OFTString},           {"width", OFTInteger},
      {"height", OFTInteger},    {"focal_x", OFTReal}, {"focal_y", OFTReal},          {"principal_x", OFTReal},
      {"principal_y", OFTReal},  {"skew", OFTReal},    {"cam_from_world", OFTString}, {"distortion_model", OFTString},
      {"distortion", OFTString}, {"date", OFTString},  {"colour_gain", OFTString},    {"colour_offset", OFTString}};
  for (const Field& f : fields) {
    OGRFieldDefn defn(f.name, f.type);
    if (layer->CreateField(&defn) != OGRERR_NONE)
      throw InputError(at + ": cannot create field " + f.name + ": " + gdal::lastError("no reason given"));
  }
  if (!geojson && ds->StartTransaction(FALSE) != OGRERR_NONE)
    throw InputError(at + ": cannot start a transaction: " + gdal::lastError("no reason given"));
  std::int64_t fid = 0;
  for (const Photo& p : photos) {
    const Camera& c = p.camera;
    OGRFeature feature(layer->GetLayerDefn());
    fillCameraFeature(
        feature, p, ++fid, [](OGRFeature& f, const char* name, double v) { f.SetField(name, v); },
        [](OGRFeature& f, const char* name, const std::vector<double>& v) { f.SetField(name, jsonNumbers(v).c_str()); });
    CPLErrorReset();
    if (layer->CreateFeature(&feature) != OGRERR_NONE)
      throw InputError(at + ": camera '" + c.id + "': cannot write: " + gdal::lastError("no reason given"));
  }
  if (!geojson && ds->CommitTransaction() != OGRERR_NONE)
    throw InputError(at + ": cannot commit: " + gdal::lastError("no reason given"));
  DatasetPtr closed = std::move(ds);
  closed.reset();  // flushed here: a GeoJSON file is written on close
  if (CPLGetLastErrorType() >= CE_Failure) throw InputError(at + ": cannot write: " + gdal::lastError("no reason"));
  return photos.size();
}

CatalogCameras readOgrCameras(const std::string& source, const std::string& layerName, Diagnostics& diag) {
  gdal::ensureRegistered();
  enableRemoteReading();
  gdal::QuietErrors quiet;
  gdal::requireOpenable(source, "cameras", false);
  DatasetPtr ds(gdal::openVector(source));
  if (!ds) throw InputError(source + ": cameras: GDAL cannot open it: " + gdal::lastError("no reason given"));
  OGRLayer* layer = nullptr;
  if (layerName.empty()) {
    if (ds->GetLayerCount() != 1)
      throw InputError(source + ": cameras.layer: expected the layer's name (the source has " +
                       std::to_string(ds->GetLayerCount()) + " layers)");
    layer = ds->GetLayer(0);
  } else {
    layer = ds->GetLayerByName(layerName.c_str());
  }
  if (!layer) {
    std::string names;
    for (int l = 0; l < ds->GetLayerCount() && l < 20; ++l)
      names += (l ? ", " : "") + std::string(ds->GetLayer(l)->GetName());
    throw InputError(source + ": cameras.layer: no layer \"" + layerName +
                     "\" (it has: " + (names.empty() ? std::string("none") : names) + ")");
  }
  const std::string at = source + ": layer " + layer->GetName();
  CatalogCameras out;
  // A GeoPackage written without a CRS names GeoPackage's "Undefined geographic SRS" (srs_id 0) or
  // "Undefined Cartesian SRS" (-1): no CRS, not degrees.
  const OGRSpatialReference* srs = layer->GetSpatialRef();
  const char* srsName = srs ? srs->GetName() : nullptr;
  if (!(srsName && std::string(srsName).rfind("Undefined ", 0) == 0)) out.crs = gdal::crsDefinition(srs);
  CPLErrorReset();
  layer->ResetReading();
  decodeLayer(*layer, at, out.photos, diag);
  // A service that fails mid-way ends the reading as if the layer had no more features: said.
  if (CPLGetLastErrorType() >= CE_Failure)
    diag.error(at + ": reading stopped: " + gdal::lastError("no reason given") + " (" +
               std::to_string(out.photos.size()) + " cameras read)");
  return out;
}

}  // namespace hv
