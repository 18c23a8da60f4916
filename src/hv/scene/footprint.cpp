#include "hv/scene/footprint.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <list>

namespace hv {

double twiceSignedArea(const std::vector<glm::dvec2>& ring) {
  double a = 0.0;
  for (size_t k = 0, n = ring.size(); k < n; ++k) {
    const glm::dvec2& p = ring[k];
    const glm::dvec2& q = ring[(k + 1) % n];
    a += p.x * q.y - q.x * p.y;
  }
  return a;
}

namespace {

double cross(const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Whether p lies in the closed triangle abc (counter-clockwise).
bool inTriangle(const glm::dvec2& p, const glm::dvec2& a, const glm::dvec2& b, const glm::dvec2& c) {
  return cross(a, b, p) >= 0.0 && cross(b, c, p) >= 0.0 && cross(c, a, p) >= 0.0;
}

// Whether segments pq and rs cross at a point inside both (touching at an end point does not count).
bool properlyCross(const glm::dvec2& p, const glm::dvec2& q, const glm::dvec2& r, const glm::dvec2& s) {
  const double d1 = cross(p, q, r), d2 = cross(p, q, s), d3 = cross(r, s, p), d4 = cross(r, s, q);
  return ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0));
}

}  // namespace

std::string footprintMessage(const Footprint& fp, const std::string& message) {
  return inputMessage("footprint " + (fp.id.empty() ? std::string("<no id>") : fp.id), "", message);
}

std::vector<std::vector<glm::dvec2>> cleanFootprintRings(const Footprint& footprint) {
  if (footprint.rings.empty()) throw InputError(footprintMessage(footprint, "no outer ring"));
  std::vector<std::vector<glm::dvec2>> rings;
  for (size_t r = 0; r < footprint.rings.size(); ++r) {
    std::vector<glm::dvec2> ring;
    ring.reserve(footprint.rings[r].size());
    for (const auto& p : footprint.rings[r])
      if (ring.empty() || p != ring.back()) ring.push_back(p);
    while (ring.size() > 1 && ring.front() == ring.back()) ring.pop_back();
    for (const auto& p : ring)
      if (!std::isfinite(p.x) || !std::isfinite(p.y))
        throw InputError(footprintMessage(footprint, "ring " + std::to_string(r) + " has a non-finite coordinate"));
    if (ring.size() < 3)
      throw InputError(footprintMessage(footprint, "ring " + std::to_string(r) + " has " + std::to_string(ring.size()) +
                                                       " distinct points, expected at least 3"));
    rings.push_back(std::move(ring));
  }
  return rings;
}

void orientFootprintRings(const Footprint& footprint, std::vector<std::vector<glm::dvec2>>& rings) {
  for (size_t r = 0; r < rings.size(); ++r) {
    auto& ring = rings[r];
    const double area2 = twiceSignedArea(ring);
    if (area2 == 0.0) throw InputError(footprintMessage(footprint, "ring " + std::to_string(r) + " has zero area"));
    // Outer ring counter-clockwise, holes clockwise seen from above: the solid is then always on
    // the left of each directed edge, so every wall faces right (outwards) by the same rule.
    if ((area2 > 0.0) != (r == 0)) std::reverse(ring.begin(), ring.end());
  }
}

Mesh extrudePrism(const std::vector<std::vector<glm::dvec2>>& rings, const std::vector<glm::uvec3>& roof, double baseZ,
                  double topZ) {
  Mesh mesh;
  for (const auto& ring : rings)
    for (const auto& p : ring) {
      mesh.positions.emplace_back(p.x, p.y, baseZ);
      mesh.positions.emplace_back(p.x, p.y, topZ);
    }
  // Roof counter-clockwise from above (up-facing), floor the other way (down-facing).
  for (const glm::uvec3& c : roof) {
    mesh.triangles.emplace_back(2 * c[0] + 1, 2 * c[1] + 1, 2 * c[2] + 1);
    mesh.triangles.emplace_back(2 * c[0], 2 * c[2], 2 * c[1]);
  }
  // Walls: one quad per ring edge p -> q. The solid lies left of the edge, so the quad
  // (p base, q base, q roof, p roof) is counter-clockwise seen from the right, i.e. from outside.
  std::uint32_t first = 0;
  for (const auto& ring : rings) {
    const auto n = std::uint32_t(ring.size());
    for (std::uint32_t k = 0; k < n; ++k) {
      const std::uint32_t p = first + k, q = first + (k + 1) % n;
      mesh.triangles.emplace_back(2 * p, 2 * q, 2 * q + 1);
      mesh.triangles.emplace_back(2 * p, 2 * q + 1, 2 * p + 1);
    }
    first += n;
  }
  return mesh;
}

std::vector<glm::uvec3> earClipPolygon(const std::vector<std::vector<glm::dvec2>>& rings, const std::string& what) {
  if (rings.empty() || rings[0].size() < 3) throw InputError(what + ": fewer than 3 points");
  std::vector<glm::dvec2> pts;
  std::vector<std::vector<std::uint32_t>> loops;  // each ring's indices, outer CCW, holes CW
  double area2 = 0.0;
  for (size_t r = 0; r < rings.size(); ++r) {
    std::vector<std::uint32_t> loop;
    for (const glm::dvec2& p : rings[r]) {
      if (!std::isfinite(p.x) || !std::isfinite(p.y)) throw InputError(what + ": a non-finite coordinate");
      loop.push_back(std::uint32_t(pts.size()));
      pts.push_back(p);
    }
    const double a = twiceSignedArea(rings[r]);
    if ((a > 0.0) != (r == 0)) std::reverse(loop.begin(), loop.end());
    area2 += r == 0 ? std::abs(a) : -std::abs(a);
    if (r > 0 && loop.size() < 3) loops.pop_back();  // a degenerate hole is no hole
    loops.push_back(std::move(loop));
  }
  if (!(area2 > 0.0)) throw InputError(what + ": zero area");

  // The holes bridged to the outer ring, rightmost hole first: from the hole's rightmost vertex to
  // the nearest vertex of the polygon so far that the bridge reaches without crossing an edge.
  std::vector<std::uint32_t> poly = loops[0];
  std::vector<size_t> holes;
  for (size_t h = 1; h < loops.size(); ++h) holes.push_back(h);
  auto maxX = [&](size_t h) {
    double m = -std::numeric_limits<double>::infinity();
    for (std::uint32_t i : loops[h]) m = std::max(m, pts[i].x);
    return m;
  };
  std::sort(holes.begin(), holes.end(), [&](size_t a, size_t b) { return maxX(a) > maxX(b); });
  for (size_t hi = 0; hi < holes.size(); ++hi) {
    const auto& hole = loops[holes[hi]];
    size_t m = 0;
    for (size_t k = 1; k < hole.size(); ++k)
      if (pts[hole[k]].x > pts[hole[m]].x) m = k;
    const glm::dvec2 M = pts[hole[m]];
    auto blocked = [&](const glm::dvec2& V) {
      auto crossesLoop = [&](const std::vector<std::uint32_t>& loop) {
        for (size_t k = 0; k < loop.size(); ++k)
          if (properlyCross(M, V, pts[loop[k]], pts[loop[(k + 1) % loop.size()]])) return true;
        return false;
      };
      if (crossesLoop(poly)) return true;
      for (size_t o = hi; o < holes.size(); ++o)
        if (crossesLoop(loops[holes[o]])) return true;
      return false;
    };
    size_t best = poly.size(), nearest = 0;
    double bestD = std::numeric_limits<double>::infinity(), nearestD = bestD;
    for (size_t k = 0; k < poly.size(); ++k) {
      const double d = glm::length(pts[poly[k]] - M);
      if (d < nearestD) nearestD = d, nearest = k;
      if (d < bestD && !blocked(pts[poly[k]])) bestD = d, best = k;
    }
    if (best == poly.size()) best = nearest;  // an invalid polygon: the nearest vertex
    // poly[..best], hole from m around to m, back to poly[best], poly[best + 1..].
    std::vector<std::uint32_t> merged(poly.begin(), poly.begin() + std::ptrdiff_t(best) + 1);
    for (size_t k = 0; k <= hole.size(); ++k) merged.push_back(hole[(m + k) % hole.size()]);
    merged.insert(merged.end(), poly.begin() + std::ptrdiff_t(best), poly.end());
    poly = std::move(merged);
  }

  // Ear clipping of the one loop: a convex corner is an ear when no other vertex (apart from
  // copies of its own corners, the bridges' ends) lies in its triangle.
  std::list<std::uint32_t> loop(poly.begin(), poly.end());
  std::vector<glm::uvec3> out;
  auto prevOf = [&](std::list<std::uint32_t>::iterator it) {
    return it == loop.begin() ? std::prev(loop.end()) : std::prev(it);
  };
  auto nextOf = [&](std::list<std::uint32_t>::iterator it) {
    return std::next(it) == loop.end() ? loop.begin() : std::next(it);
  };
  while (loop.size() > 3) {
    bool clipped = false;
    for (auto it = loop.begin(); it != loop.end(); ++it) {
      const auto ip = prevOf(it), in = nextOf(it);
      const glm::dvec2 &a = pts[*ip], &b = pts[*it], &c = pts[*in];
      if (cross(a, b, c) <= 0.0) continue;
      bool ear = true;
      for (std::uint32_t v : loop) {
        const glm::dvec2& p = pts[v];
        if (p == a || p == b || p == c) continue;
        if (inTriangle(p, a, b, c)) {
          ear = false;
          break;
        }
      }
      if (!ear) continue;
      out.emplace_back(*ip, *it, *in);
      loop.erase(it);
      clipped = true;
      break;
    }
    if (clipped) continue;
    // No ear: a collinear or reflex corner left by degenerate input. Drop the flattest corner
    // without a triangle, so the loop always shrinks.
    auto flattest = loop.begin();
    double best = std::numeric_limits<double>::infinity();
    for (auto it = loop.begin(); it != loop.end(); ++it) {
      const double c = std::abs(cross(pts[*prevOf(it)], pts[*it], pts[*nextOf(it)]));
      if (c < best) best = c, flattest = it;
    }
    loop.erase(flattest);
  }
  if (loop.size() == 3) {
    auto it = loop.begin();
    const std::uint32_t a = *it++, b = *it++, c = *it;
    if (cross(pts[a], pts[b], pts[c]) > 0.0) out.emplace_back(a, b, c);
  }
  if (out.empty()) throw InputError(what + ": zero area");
  return out;
}

Mesh extrudeLod1EarClip(const Footprint& footprint, double baseZ, double topZ) {
  if (!std::isfinite(baseZ) || !std::isfinite(topZ) || !(topZ > baseZ))
    throw InputError(footprintMessage(footprint, "roof elevation " + std::to_string(topZ) +
                                                     " is not above the base elevation " + std::to_string(baseZ)));
  std::vector<std::vector<glm::dvec2>> rings = cleanFootprintRings(footprint);
  orientFootprintRings(footprint, rings);
  const std::vector<glm::uvec3> roof = earClipPolygon(rings, footprintMessage(footprint, "roof"));
  return extrudePrism(rings, roof, baseZ, topZ);
}

Mesh buildLod1With(const std::vector<Footprint>& footprints, const Heightfield* terrain, Diagnostics& diag,
                   const Lod1Extruder& extrude) {
  Mesh all;
  for (size_t index = 0; index < footprints.size(); ++index) {
    const Footprint& fp = footprints[index];
    double baseZ = 0.0;
    if (fp.base) {
      baseZ = *fp.base;
    } else if (terrain && !terrain->empty() && !fp.rings.empty()) {
      if (const auto ground = terrain->minUnder(fp.rings[0]))
        baseZ = *ground;
      else
        diag.warn(footprintMessage(fp, "no terrain elevation under the footprint; base set to 0"));
    } else {
      diag.warn(footprintMessage(fp, "no base elevation and no terrain; base set to 0"));
    }

    double topZ = 0.0;
    if (fp.top) {
      topZ = *fp.top;
    } else if (fp.height) {
      topZ = baseZ + *fp.height;
    } else {
      diag.warn(footprintMessage(fp, "neither a height nor a roof elevation; skipped"));
      continue;
    }

    try {
      Mesh building = extrude(fp, baseZ, topZ);
      building.triangleTags.assign(building.triangles.size(), std::uint32_t(index));
      all.append(building);
    } catch (const InputError& e) {
      diag.warn(std::string(e.what()) + "; skipped");
    }
  }
  return all;
}

std::vector<DateInterval> footprintValidity(const std::vector<Footprint>& footprints, const std::string& fromField,
                                            const std::string& toField, const std::string& path, Diagnostics& diag) {
  std::vector<DateInterval> out;
  out.reserve(footprints.size());
  for (const Footprint& f : footprints) {
    DateInterval valid;  // open-ended unless the attributes say otherwise
    auto bound = [&](const std::optional<std::string>& text, const std::string& field, bool from) {
      if (!text || text->empty()) return;
      if (const auto d = parseDate(*text)) {
        (from ? valid.first : valid.last) = from ? d->first : d->last;
      } else {
        diag.warn(path + ": footprint " + f.id + ": " + field + ": expected an ISO 8601 date, got '" + *text +
                  "' (ignored)");
      }
    };
    bound(f.validFrom, fromField, true);
    bound(f.validTo, toField, false);
    out.push_back(valid);
  }
  return out;
}

}  // namespace hv
