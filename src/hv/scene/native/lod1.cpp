#include "hv/scene/native/lod1.h"

#include <geos_c.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <utility>

namespace hv {

namespace {

// A reentrant GEOS context per call: footprints may be extruded from several threads, and the
// context is where GEOS leaves its last error message.
class GeosContext {
 public:
  GeosContext() : handle_(GEOS_init_r()) {
    GEOSContext_setErrorMessageHandler_r(handle_, &GeosContext::onError, &lastError_);
  }
  ~GeosContext() { GEOS_finish_r(handle_); }
  GeosContext(const GeosContext&) = delete;
  GeosContext& operator=(const GeosContext&) = delete;

  GEOSContextHandle_t get() const { return handle_; }
  const std::string& lastError() const { return lastError_; }

 private:
  static void onError(const char* message, void* userdata) { *static_cast<std::string*>(userdata) = message; }
  GEOSContextHandle_t handle_;
  std::string lastError_;
};

struct GeomDeleter {
  GEOSContextHandle_t handle;
  void operator()(GEOSGeometry* g) const { GEOSGeom_destroy_r(handle, g); }
};
using GeomPtr = std::unique_ptr<GEOSGeometry, GeomDeleter>;

GEOSGeometry* makeLinearRing(const GeosContext& ctx, const std::vector<glm::dvec2>& ring) {
  GEOSCoordSequence* seq = GEOSCoordSeq_create_r(ctx.get(), unsigned(ring.size() + 1), 2);
  if (!seq) return nullptr;
  for (size_t k = 0; k <= ring.size(); ++k) {
    const glm::dvec2& p = ring[k % ring.size()];  // GEOS rings are explicitly closed
    GEOSCoordSeq_setXY_r(ctx.get(), seq, unsigned(k), p.x, p.y);
  }
  return GEOSGeom_createLinearRing_r(ctx.get(), seq);  // takes ownership of seq, even on failure
}

GeomPtr makePolygon(const GeosContext& ctx, const std::vector<std::vector<glm::dvec2>>& rings) {
  GEOSGeometry* shell = makeLinearRing(ctx, rings[0]);
  std::vector<GEOSGeometry*> holes;
  bool ok = shell != nullptr;
  for (size_t r = 1; r < rings.size() && ok; ++r) {
    GEOSGeometry* hole = makeLinearRing(ctx, rings[r]);
    if (hole)
      holes.push_back(hole);
    else
      ok = false;
  }
  if (!ok) {
    if (shell) GEOSGeom_destroy_r(ctx.get(), shell);
    for (GEOSGeometry* h : holes) GEOSGeom_destroy_r(ctx.get(), h);
    return GeomPtr(nullptr, GeomDeleter{ctx.get()});
  }
  // Takes ownership of the shell and the holes.
  return GeomPtr(GEOSGeom_createPolygon_r(ctx.get(), shell, holes.data(), unsigned(holes.size())),
                 GeomDeleter{ctx.get()});
}

}  // namespace

// GEOS's constrained Delaunay triangulation of `polygon` (GEOS >= 3.10, after JTS's
// ConstrainedDelaunayTriangulator), which only uses the polygon's own vertices: each triangle's
// corners as indices of `index` (the rings' vertices by position), counter-clockwise in the plane.
// `fail(what)` makes the exception for a failure.
namespace {

std::vector<glm::uvec3> constrainedDelaunay(const GeosContext& ctx, const GEOSGeometry* polygon,
                                            const std::map<std::pair<double, double>, std::uint32_t>& index,
                                            const std::function<InputError(const std::string&)>& fail) {
  const GeomPtr triangles(GEOSConstrainedDelaunayTriangulation_r(ctx.get(), polygon), GeomDeleter{ctx.get()});
  if (!triangles) throw fail("triangulation failed: " + ctx.lastError());
  std::vector<glm::uvec3> out;
  const int count = GEOSGetNumGeometries_r(ctx.get(), triangles.get());
  for (int t = 0; t < count; ++t) {
    const GEOSGeometry* tri = GEOSGetGeometryN_r(ctx.get(), triangles.get(), t);
    const GEOSGeometry* shell = GEOSGetExteriorRing_r(ctx.get(), tri);
    const GEOSCoordSequence* seq = shell ? GEOSGeom_getCoordSeq_r(ctx.get(), shell) : nullptr;
    unsigned size = 0;
    if (!seq || !GEOSCoordSeq_getSize_r(ctx.get(), seq, &size) || size < 3)
      throw fail("triangulation returned a malformed triangle");
    glm::uvec3 corner;
    glm::dvec2 xy[3];
    for (unsigned c = 0; c < 3; ++c) {
      GEOSCoordSeq_getXY_r(ctx.get(), seq, c, &xy[c].x, &xy[c].y);
      const auto it = index.find({xy[c].x, xy[c].y});
      if (it == index.end()) throw fail("triangulation introduced a vertex not on the polygon");
      corner[int(c)] = it->second;
    }
    if (twiceSignedArea({xy[0], xy[1], xy[2]}) < 0.0) std::swap(corner[1], corner[2]);
    out.push_back(corner);
  }
  return out;
}

}  // namespace

Mesh extrudeLod1(const Footprint& footprint, double baseZ, double topZ) {
  if (!std::isfinite(baseZ) || !std::isfinite(topZ) || !(topZ > baseZ))
    throw InputError(footprintMessage(footprint, "roof elevation " + std::to_string(topZ) +
                                                     " is not above the base elevation " +
                                                     std::to_string(baseZ)));
  std::vector<std::vector<glm::dvec2>> rings = cleanFootprintRings(footprint);

  const GeosContext ctx;
  const GeomPtr polygon = makePolygon(ctx, rings);
  if (!polygon) throw InputError(footprintMessage(footprint, "not a polygon: " + ctx.lastError()));
  const char valid = GEOSisValid_r(ctx.get(), polygon.get());
  if (valid != 1) {
    char* reason = GEOSisValidReason_r(ctx.get(), polygon.get());
    const std::string why = reason ? reason : ctx.lastError();
    if (reason) GEOSFree_r(ctx.get(), reason);
    throw InputError(footprintMessage(footprint, "invalid polygon: " + why));
  }
  // Oriented after GEOS so that a bow-tie (whose signed area may cancel) is reported as such.
  orientFootprintRings(footprint, rings);

  // The roof's corners as ring vertices (k of the concatenated rings): the roof's border edges are
  // exactly the ring edges.
  std::map<std::pair<double, double>, std::uint32_t> ringVertex;
  std::uint32_t k = 0;
  for (const auto& ring : rings)
    for (const auto& p : ring) ringVertex.emplace(std::make_pair(p.x, p.y), k++);
  const auto roofFail = [&](const std::string& why) { return InputError(footprintMessage(footprint, "roof " + why)); };
  return extrudePrism(rings, constrainedDelaunay(ctx, polygon.get(), ringVertex, roofFail), baseZ, topZ);
}

std::vector<glm::uvec3> triangulatePolygon(const std::vector<std::vector<glm::dvec2>>& rings, const std::string& what) {
  if (rings.empty() || rings[0].size() < 3) throw InputError(what + ": fewer than 3 points");
  std::map<std::pair<double, double>, std::uint32_t> index;
  std::uint32_t k = 0;
  for (const auto& ring : rings)
    for (const glm::dvec2& p : ring) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw InputError(what + ": a non-finite coordinate");
      index.emplace(std::make_pair(p.x, p.y), k++);
    }
  if (rings.size() == 1 && rings[0].size() == 3) {  // a triangle already (most CityJSON surfaces)
    if (twiceSignedArea(rings[0]) == 0.0) throw InputError(what + ": zero area");
    return {twiceSignedArea(rings[0]) > 0.0 ? glm::uvec3(0, 1, 2) : glm::uvec3(0, 2, 1)};
  }
  const GeosContext ctx;
  const GeomPtr polygon = makePolygon(ctx, rings);
  if (!polygon) throw InputError(what + ": not a polygon: " + ctx.lastError());
  if (GEOSisValid_r(ctx.get(), polygon.get()) != 1) {
    char* reason = GEOSisValidReason_r(ctx.get(), polygon.get());
    const std::string why = reason ? reason : ctx.lastError();
    if (reason) GEOSFree_r(ctx.get(), reason);
    throw InputError(what + ": invalid polygon: " + why);
  }
  const std::vector<glm::uvec3> out =
      constrainedDelaunay(ctx, polygon.get(), index, [&](const std::string& why) { return InputError(what + ": " + why); });
  if (out.empty()) throw InputError(what + ": zero area");
  return out;
}

Mesh buildLod1(const std::vector<Footprint>& footprints, const Heightfield* terrain, Diagnostics& diag) {
  return buildLod1With(footprints, terrain, diag, extrudeLod1);
}

}  // namespace hv
