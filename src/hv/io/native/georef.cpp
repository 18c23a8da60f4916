#include "hv/io/native/georef.h"
#include "hv/io/native/crs_proj_string.h"

#include <proj.h>
#include <proj_experimental.h>  // proj_crs_demote_to_2D

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

namespace hv {
namespace {

// Owning handles for PROJ objects.
struct CtxDeleter {
  void operator()(PJ_CONTEXT* c) const { proj_context_destroy(c); }
};
struct PjDeleter {
  void operator()(PJ* p) const { proj_destroy(p); }
};
using CtxPtr = std::unique_ptr<PJ_CONTEXT, CtxDeleter>;
using PjPtr = std::unique_ptr<PJ, PjDeleter>;

CtxPtr newContext() {
  CtxPtr ctx(proj_context_create());
  proj_log_level(ctx.get(), PJ_LOG_NONE);  // failures are reported through InputError instead
  return ctx;
}

std::string str(const char* s) { return s ? std::string(s) : std::string(); }

bool isCrsType(PJ_TYPE t) {
  switch (t) {
    case PJ_TYPE_GEODETIC_CRS:
    case PJ_TYPE_GEOCENTRIC_CRS:
    case PJ_TYPE_GEOGRAPHIC_CRS:
    case PJ_TYPE_GEOGRAPHIC_2D_CRS:
    case PJ_TYPE_GEOGRAPHIC_3D_CRS:
    case PJ_TYPE_VERTICAL_CRS:
    case PJ_TYPE_PROJECTED_CRS:
    case PJ_TYPE_COMPOUND_CRS:
    case PJ_TYPE_TEMPORAL_CRS:
    case PJ_TYPE_ENGINEERING_CRS:
    case PJ_TYPE_BOUND_CRS:
    case PJ_TYPE_OTHER_CRS:
      return true;
    default:
      return false;
  }
}

PjPtr createCrs(PJ_CONTEXT* ctx, const std::string& definition) {
  PjPtr pj(proj_create(ctx, definition.c_str()));
  if (!pj || !isCrsType(proj_get_type(pj.get())))
    throw InputError("CRS '" + definition + "': PROJ cannot read it as a coordinate reference system" +
                     (pj ? "" : std::string(" (") + proj_context_errno_string(ctx, proj_context_errno(ctx)) + ")") +
                     "; expected e.g. \"EPSG:2154\", \"EPSG:2154+5720\", WKT or a PROJ string");
  return pj;
}

// The horizontal part of a CRS: a bound CRS's source, a compound CRS's first component, a 3D
// geographic or projected CRS taken as 2D. Others (geocentric, engineering) are returned as they are.
PjPtr horizontalPart(PJ_CONTEXT* ctx, const PJ* crs) {
  PjPtr out(proj_clone(ctx, crs));
  for (int depth = 0; out && depth < 3; ++depth) {
    const PJ_TYPE t = proj_get_type(out.get());
    if (t == PJ_TYPE_BOUND_CRS)
      out.reset(proj_get_source_crs(ctx, out.get()));
    else if (t == PJ_TYPE_COMPOUND_CRS)
      out.reset(proj_crs_get_sub_crs(ctx, out.get(), 0));
    else
      break;
  }
  if (!out) return out;
  const PJ_TYPE t = proj_get_type(out.get());
  PjPtr cs(proj_crs_get_coordinate_system(ctx, out.get()));
  const bool threeAxes = cs && proj_cs_get_axis_count(ctx, cs.get()) == 3;
  if (t == PJ_TYPE_GEOGRAPHIC_3D_CRS || (t == PJ_TYPE_PROJECTED_CRS && threeAxes)) {
    PjPtr flat(proj_crs_demote_to_2D(ctx, nullptr, out.get()));
    if (flat) out = std::move(flat);
  }
  return out;
}

bool equivalent(PJ_CONTEXT* ctx, const PJ* a, const PJ* b) {
  return a && b && proj_is_equivalent_to_with_ctx(ctx, a, b, PJ_COMP_EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS);
}

struct Axis {
  std::string unit;
  double toMetre = 0.0;  // unit conversion factor (to metres, or to radians for angles)
  std::string direction;
};

std::vector<Axis> axes(PJ_CONTEXT* ctx, const PJ* crs) {
  std::vector<Axis> out;
  PjPtr cs(proj_crs_get_coordinate_system(ctx, crs));
  if (!cs) return out;
  const int n = proj_cs_get_axis_count(ctx, cs.get());
  for (int i = 0; i < n; ++i) {
    const char *name = nullptr, *abbrev = nullptr, *dir = nullptr, *unit = nullptr, *auth = nullptr, *code = nullptr;
    double factor = 0.0;
    if (proj_cs_get_axis_info(ctx, cs.get(), i, &name, &abbrev, &dir, &factor, &unit, &auth, &code))
      out.push_back({str(unit), factor, str(dir)});
  }
  return out;
}

CrsDescription describe(PJ_CONTEXT* ctx, PJ* pjIn, const std::string& definition) {
  CrsDescription d;
  d.definition = definition;
  PjPtr bound;
  PJ* pj = pjIn;
  if (proj_get_type(pj) == PJ_TYPE_BOUND_CRS) {  // +towgs84 and the like: describe the CRS itself
    bound.reset(proj_get_source_crs(ctx, pj));
    if (bound) pj = bound.get();
  }
  d.name = str(proj_get_name(pj));
  if (str(proj_get_id_auth_name(pj, 0)) == "EPSG") {
    d.epsg = std::atoi(proj_get_id_code(pj, 0));
  } else {
    int* confidence = nullptr;
    if (PJ_OBJ_LIST* list = proj_identify(ctx, pj, "EPSG", nullptr, &confidence)) {
      if (proj_list_get_count(list) > 0 && confidence && confidence[0] >= 90) {
        PjPtr best(proj_list_get(ctx, list, 0));
        if (best && proj_get_id_code(best.get(), 0)) d.epsg = std::atoi(proj_get_id_code(best.get(), 0));
      }
      proj_int_list_destroy(confidence);
      proj_list_destroy(list);
    }
  }
  const PJ_TYPE type = proj_get_type(pj);
  auto setHorizontal = [&](const Axis& a, bool angular) {
    d.horizontalUnit = a.unit;
    d.horizontalToMetre = angular ? 0.0 : a.toMetre;
  };
  auto setVertical = [&](const Axis& a) {
    d.verticalUnit = a.unit;
    d.verticalToMetre = a.toMetre;
  };
  if (type == PJ_TYPE_COMPOUND_CRS) {
    d.type = "compound";
    PjPtr h(proj_crs_get_sub_crs(ctx, pj, 0)), v(proj_crs_get_sub_crs(ctx, pj, 1));
    if (h) {
      const auto ha = axes(ctx, h.get());
      const PJ_TYPE ht = proj_get_type(h.get());
      const bool angular = ht == PJ_TYPE_GEOGRAPHIC_2D_CRS || ht == PJ_TYPE_GEOGRAPHIC_3D_CRS;
      d.geographic = angular;
      if (!ha.empty()) setHorizontal(ha[0], angular);
    }
    if (v) {
      const auto va = axes(ctx, v.get());
      if (!va.empty()) setVertical(va[0]);
    }
    return d;
  }
  const auto a = axes(ctx, pj);
  switch (type) {
    case PJ_TYPE_GEOCENTRIC_CRS:
      d.type = "geocentric";
      d.geocentric = true;
      if (!a.empty()) {
        setHorizontal(a[0], false);
        setVertical(a[0]);
      }
      break;
    case PJ_TYPE_GEOGRAPHIC_2D_CRS:
    case PJ_TYPE_GEOGRAPHIC_3D_CRS:
      d.type = type == PJ_TYPE_GEOGRAPHIC_2D_CRS ? "geographic 2D" : "geographic 3D";
      d.geographic = true;
      if (!a.empty()) setHorizontal(a[0], true);
      if (a.size() >= 3) setVertical(a[2]);
      break;
    case PJ_TYPE_PROJECTED_CRS:
      d.type = "projected";
      if (!a.empty()) setHorizontal(a[0], false);
      if (a.size() >= 3) setVertical(a[2]);
      break;
    case PJ_TYPE_VERTICAL_CRS:
      d.type = "vertical";
      if (!a.empty()) setVertical(a[0]);
      break;
    default:
      d.type = "engineering or other";
      if (!a.empty()) setHorizontal(a[0], false);
      if (a.size() >= 3) setVertical(a[2]);
      break;
  }
  return d;
}

std::string unitText(const std::string& unit, double toMetre) {
  std::ostringstream s;
  s << (unit.empty() ? "unknown unit" : unit);
  if (toMetre > 0.0 && toMetre != 1.0) s << " (" << toMetre << " m)";
  return s.str();
}

}  // namespace

std::string CrsDescription::summary() const {
  std::ostringstream s;
  s << (name.empty() ? definition : name);
  if (epsg) s << " (EPSG:" << *epsg << ")";
  s << ", " << type;
  if (geographic)
    s << ", " << (horizontalUnit.empty() ? "degree" : horizontalUnit);
  else
    s << ", " << unitText(horizontalUnit, horizontalToMetre);
  if (hasVerticalAxis() && !geocentric) s << ", heights in " << unitText(verticalUnit, verticalToMetre);
  return s.str();
}

double CrsDescription::heightToMetre() const {
  if (hasVerticalAxis()) return verticalToMetre;
  return horizontalToMetre > 0.0 ? horizontalToMetre : 1.0;
}

CrsDescription describeCrs(const std::string& definition) {
  CtxPtr ctx = newContext();
  PjPtr pj = createCrs(ctx.get(), definition);
  return describe(ctx.get(), pj.get(), definition);
}

std::string crsProjString(const std::string& definition) {
  CtxPtr ctx = newContext();
  PjPtr pj = createCrs(ctx.get(), definition);
  const char* const options[] = {"MULTILINE=NO", nullptr};
  return str(proj_as_proj_string(ctx.get(), pj.get(), PJ_PROJ_4, options));
}

bool equivalentCrs(const std::string& a, const std::string& b) {
  if (a == b) return true;
  CtxPtr ctx = newContext();
  try {
    const PjPtr pa = createCrs(ctx.get(), a), pb = createCrs(ctx.get(), b);
    return equivalent(ctx.get(), pa.get(), pb.get());
  } catch (const InputError&) {
    return false;
  }
}

glm::dvec3 ecefUp(const glm::dvec3& p) {
  const double a = 6378137.0, f = 1.0 / 298.257222101, b = a * (1.0 - f);  // GRS80
  return glm::normalize(glm::dvec3(p.x / (a * a), p.y / (a * a), p.z / (b * b)));
}

struct GeoTransform::Impl {
  CtxPtr ctx;
  PjPtr op;
  CrsDescription source, scene;
  double xyToMetre = 1.0, zToMetre = 1.0;
  bool sameCrs = false, sameHorizontal = false;
  glm::dvec3 step{1.0};  // finite-difference steps, source units
};

GeoTransform::GeoTransform(const std::string& sourceCrs, const std::string& sceneCrs, Diagnostics& diag)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.ctx = newContext();
  PJ_CONTEXT* ctx = m.ctx.get();
  PjPtr src = createCrs(ctx, sourceCrs), dst = createCrs(ctx, sceneCrs);
  m.source = describe(ctx, src.get(), sourceCrs);
  m.scene = describe(ctx, dst.get(), sceneCrs);
  const std::string pair = "from " + m.source.summary() + " to " + m.scene.summary();
  m.sameCrs = equivalent(ctx, src.get(), dst.get());
  m.sameHorizontal =
      m.sameCrs || equivalent(ctx, horizontalPart(ctx, src.get()).get(), horizontalPart(ctx, dst.get()).get());
  if (m.scene.geographic)
    throw InputError("scene CRS '" + sceneCrs + "' is geographic (" + m.scene.horizontalUnit +
                     "): expected a projected, geocentric or local CRS with linear units");

  // What PROJ would prefer with every grid at hand: if that needs a grid that is not installed,
  // the operation actually used is a poorer one (typically heights left on another datum).
  {
    PJ_OPERATION_FACTORY_CONTEXT* fctx = proj_create_operation_factory_context(ctx, nullptr);
    proj_operation_factory_context_set_grid_availability_use(ctx, fctx, PROJ_GRID_AVAILABILITY_IGNORED);
    proj_operation_factory_context_set_spatial_criterion(ctx, fctx, PROJ_SPATIAL_CRITERION_PARTIAL_INTERSECTION);
    PJ_OBJ_LIST* ops = proj_create_operations(ctx, src.get(), dst.get(), fctx);
    const int count = ops ? proj_list_get_count(ops) : 0;
    if (count > 0) {
      PjPtr best(proj_list_get(ctx, ops, 0));
      const int grids = proj_coordoperation_get_grid_used_count(ctx, best.get());
      for (int i = 0; i < grids; ++i) {
        const char *shortName = nullptr, *fullName = nullptr, *package = nullptr, *url = nullptr;
        int direct = 0, open = 0, available = 0;
        if (proj_coordoperation_get_grid_used(ctx, best.get(), i, &shortName, &fullName, &package, &url, &direct,
                                              &open, &available) &&
            !available)
          diag.warn("georeferencing " + pair + ": PROJ's preferred operation (" + str(proj_get_name(best.get())) +
                    ") needs the grid " + str(shortName) +
                    ", which is not installed; the transformation falls back to one without it, so heights (or "
                    "positions) may stay on another datum" + (str(url).empty() ? "" : " (grid: " + str(url) + ")"));
      }
    }
    if (ops) proj_list_destroy(ops);
    proj_operation_factory_context_destroy(fctx);
  }

  PjPtr op(proj_create_crs_to_crs_from_pj(ctx, src.get(), dst.get(), nullptr, nullptr));
  if (!op) throw InputError("georeferencing " + pair + ": PROJ finds no operation");
  m.op.reset(proj_normalize_for_visualization(ctx, op.get()));
  if (!m.op) throw InputError("georeferencing " + pair + ": PROJ cannot normalise the axis order");
  if (proj_get_type(m.op.get()) != PJ_TYPE_UNKNOWN && proj_coordoperation_has_ballpark_transformation(ctx, m.op.get()))
    diag.warn("georeferencing " + pair + ": PROJ uses a ballpark transformation (datum shift ignored; errors up to "
              "metres)");
  if (!m.scene.hasVerticalAxis() && (m.source.geocentric || (m.source.geographic && m.source.hasVerticalAxis())))
    diag.warn("georeferencing " + pair + ": the scene CRS declares no vertical datum, so heights stay ellipsoidal "
              "heights; declare a compound CRS (e.g. EPSG:2154+5720) for altitudes");

  m.xyToMetre = m.scene.geocentric ? 1.0 : (m.scene.horizontalToMetre > 0.0 ? m.scene.horizontalToMetre : 1.0);
  if (m.scene.hasVerticalAxis())
    m.zToMetre = m.scene.verticalToMetre;
  else if (m.source.hasVerticalAxis())
    m.zToMetre = m.source.verticalToMetre;
  else if (m.source.horizontalToMetre > 0.0)
    m.zToMetre = m.source.horizontalToMetre;
  // Steps of about a metre: 1e-5 degree is 1.1 m of latitude.
  const double hUnit = m.source.geographic ? 1e-5 : 1.0 / (m.source.horizontalToMetre > 0 ? m.source.horizontalToMetre : 1.0);
  const double vUnit = 1.0 / (m.source.hasVerticalAxis() ? m.source.verticalToMetre
                                                         : (m.source.horizontalToMetre > 0 ? m.source.horizontalToMetre : 1.0));
  m.step = {hUnit, hUnit, vUnit};
}

GeoTransform::~GeoTransform() = default;
GeoTransform::GeoTransform(GeoTransform&&) noexcept = default;
GeoTransform& GeoTransform::operator=(GeoTransform&&) noexcept = default;

const CrsDescription& GeoTransform::source() const { return impl_->source; }
const CrsDescription& GeoTransform::scene() const { return impl_->scene; }
double GeoTransform::zToMetre() const { return impl_->zToMetre; }
bool GeoTransform::sameCrs() const { return impl_->sameCrs; }
bool GeoTransform::sameHorizontalCrs() const { return impl_->sameHorizontal; }
bool GeoTransform::transformsHeights() const {
  return impl_->source.hasVerticalAxis() && impl_->scene.hasVerticalAxis();
}
bool GeoTransform::isIdentity() const {
  return impl_->sameCrs && impl_->xyToMetre == 1.0 && impl_->zToMetre == 1.0;
}

glm::dvec3 GeoTransform::point(const glm::dvec3& p) const {
  PJ* op = impl_->op.get();
  proj_errno_reset(op);
  const PJ_COORD out = proj_trans(op, PJ_FWD, proj_coord(p.x, p.y, p.z, 0.0));
  const glm::dvec3 r(out.xyz.x, out.xyz.y, out.xyz.z);
  if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z) || std::abs(r.x) >= HUGE_VAL / 2) {
    std::ostringstream s;
    s.precision(17);
    s << "georeferencing from " << impl_->source.summary() << ": PROJ cannot transform (" << p.x << ", " << p.y
      << ", " << p.z << "): " << proj_context_errno_string(impl_->ctx.get(), proj_errno(op));
    throw InputError(s.str());
  }
  return {r.x * impl_->xyToMetre, r.y * impl_->xyToMetre, r.z * impl_->zToMetre};
}

void GeoTransform::points(std::vector<glm::dvec3>& v) const {
  for (glm::dvec3& p : v) p = point(p);
}

glm::dmat3 GeoTransform::jacobian(const glm::dvec3& p) const {
  glm::dmat3 j(0.0);
  for (int axis = 0; axis < 3; ++axis) {
    glm::dvec3 d(0.0);
    d[axis] = impl_->step[axis];
    j[axis] = (point(p + d) - point(p - d)) / (2.0 * impl_->step[axis]);  // column = d out / d in_axis
  }
  return j;
}

Camera GeoTransform::camera(const Camera& c, double* nonOrthogonality) const {
  glm::dmat3 j = jacobian(c.center);
  if (impl_->source.geographic)
    for (int axis = 0; axis < 3; ++axis) j[axis] = glm::normalize(j[axis]);
  if (nonOrthogonality) {
    const double det = glm::determinant(j);
    const glm::dmat3 unit = j / std::cbrt(det);
    const glm::dmat3 g = glm::transpose(unit) * unit;
    double defect = 0.0;
    for (int col = 0; col < 3; ++col)
      for (int row = 0; row < 3; ++row) defect = std::max(defect, std::abs(g[col][row] - (row == col ? 1.0 : 0.0)));
    *nonOrthogonality = defect;
  }
  Camera out = c;
  out.center = point(c.center);
  out.camFromWorld = orthonormalize(c.camFromWorld * glm::inverse(j));
  return out;
}

GeodeticFrame geodeticFrameAt(const std::string& sceneCrs, const glm::dvec3& world, Diagnostics& diag) {
  if (sceneCrs.empty())
    throw InputError("the scene has no CRS (scene.json `crs`): a position on the Earth needs one, e.g. \"EPSG:2154\"");
  const CrsDescription d = describeCrs(sceneCrs);
  if (d.geographic)
    throw InputError("scene CRS '" + sceneCrs + "' is geographic: expected a projected or geocentric CRS");
  // The scene frame is the CRS in metres (header comment): back to the CRS's units.
  const double xyUnit = d.geocentric || !(d.horizontalToMetre > 0.0) ? 1.0 : d.horizontalToMetre;
  const double zUnit = d.geocentric ? 1.0 : d.heightToMetre();
  const glm::dvec3 native(world.x / xyUnit, world.y / xyUnit, world.z / zUnit);

  GeodeticFrame f;
  f.heightIsZ = !d.hasVerticalAxis() && !d.geocentric;
  {
    CtxPtr ctx = newContext();
    PjPtr src = createCrs(ctx.get(), sceneCrs), dst = createCrs(ctx.get(), "EPSG:4979");
    PjPtr op(proj_create_crs_to_crs_from_pj(ctx.get(), src.get(), dst.get(), nullptr, nullptr));
    PjPtr norm(op ? proj_normalize_for_visualization(ctx.get(), op.get()) : nullptr);
    if (!norm) throw InputError("scene CRS '" + sceneCrs + "': PROJ finds no operation to WGS 84 (EPSG:4979)");
    proj_errno_reset(norm.get());
    const PJ_COORD out = proj_trans(norm.get(), PJ_FWD, proj_coord(native.x, native.y, native.z, 0.0));
    if (!std::isfinite(out.xyz.x) || !std::isfinite(out.xyz.y) || !std::isfinite(out.xyz.z) ||
        std::abs(out.xyz.x) >= HUGE_VAL / 2) {
      std::ostringstream s;
      s.precision(17);
      s << "scene CRS '" << sceneCrs << "': PROJ cannot bring (" << world.x << ", " << world.y << ", " << world.z
        << ") to WGS 84: " << proj_context_errno_string(ctx.get(), proj_errno(norm.get()));
      throw InputError(s.str());
    }
    f.lonDeg = out.xyz.x;
    f.latDeg = out.xyz.y;
    f.heightM = out.xyz.z;
  }
  const GeoTransform toEcef(sceneCrs, "EPSG:4978", diag);
  glm::dmat3 ecefFromWorld = toEcef.jacobian(native);
  ecefFromWorld[0] /= xyUnit, ecefFromWorld[1] /= xyUnit, ecefFromWorld[2] /= zUnit;
  const double lat = f.latDeg * M_PI / 180.0, lon = f.lonDeg * M_PI / 180.0;
  const double sp = std::sin(lat), cp = std::cos(lat), sl = std::sin(lon), cl = std::cos(lon);
  const glm::dmat3 enuFromEcef = glm::transpose(
      glm::dmat3(glm::dvec3(-sl, cl, 0.0), glm::dvec3(-sp * cl, -sp * sl, cp), glm::dvec3(cp * cl, cp * sl, sp)));
  const glm::dmat3 j = enuFromEcef * ecefFromWorld;
  const glm::dmat3 unit = j / std::cbrt(glm::determinant(j));
  const glm::dmat3 g = glm::transpose(unit) * unit;
  for (int col = 0; col < 3; ++col)
    for (int row = 0; row < 3; ++row)
      f.nonOrthogonality = std::max(f.nonOrthogonality, std::abs(g[col][row] - (row == col ? 1.0 : 0.0)));
  f.enuFromWorld = orthonormalize(j);
  return f;
}

std::string sourceCrsOf(const SourceGeoref& georef, const std::string& declared) {
  if (georef.sceneCrs.empty()) return {};
  if (!georef.crs.empty()) return georef.crs;
  return declared.empty() ? georef.sceneCrs : declared;
}

GeoTransform sourceTransform(const SourceGeoref& georef, const std::string& sourceCrs, const std::string& file,
                             Diagnostics& diag) {
  try {
    return GeoTransform(sourceCrs, georef.sceneCrs, diag);
  } catch (const InputError& e) {
    // Name where the CRS came from: scene.json's field when it overrides, else the file.
    const bool fromField = !georef.crs.empty() && sourceCrs == georef.crs && !georef.field.empty();
    throw InputError((fromField ? georef.field : file + ": CRS") + ": " + e.what());
  }
}

}  // namespace hv
