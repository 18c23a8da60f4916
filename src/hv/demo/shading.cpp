// Ground-truth appearance of the demo city: procedural albedo per material (patterns with detail at
// 1-20 cm, so that a misregistered texture visibly loses PSNR) under a fixed, view-independent
// lighting (Lambert with a fixed sun plus a sky ambient term): what multi-view blending can
// reproduce exactly, since every photograph sees the same colour at a surface point.
#include <cmath>

#include "hv/demo/demo_internal.h"

namespace hv::demo {

using detail::hash01;
using detail::valueNoise;

namespace {

double fract(double x) { return x - std::floor(x); }

// Noise at a feature size of `scale` metres, in [0, 1].
double noise(glm::dvec3 q, double scale, std::uint64_t salt) { return valueNoise(q / scale, salt); }

glm::dvec3 grass(glm::dvec3 q) {
  const double f = 0.6 * noise(q, 0.06, 11) + 0.4 * noise(q, 0.7, 12);
  glm::dvec3 c = glm::dvec3(0.30, 0.48, 0.18) * (0.7 + 0.6 * f);
  // Sparse flowers on a 5 cm lattice.
  if (hash01(std::int64_t(std::floor(q.x / 0.05)), std::int64_t(std::floor(q.y / 0.05)), 0, 13) > 0.985)
    c = {0.88, 0.82, 0.35};
  return c;
}

glm::dvec3 asphalt(const World& w, glm::dvec3 p, glm::dvec3 q) {
  const double f = 0.7 * noise(q, 0.04, 21) + 0.3 * noise(q, 1.5, 22);
  glm::dvec3 c = glm::dvec3(0.24, 0.24, 0.25) * (0.75 + 0.5 * f);
  // Dashed centre line (3 m dash, 3 m gap), not across crossings.
  int bands = 0;
  const Street* in = nullptr;
  for (const Street& st : w.streets) {
    const double across = st.alongX ? p.y : p.x;
    if (std::abs(across - st.centre) <= 0.5 * w.roadWidth) {
      ++bands;
      in = &st;
    }
  }
  if (bands == 1) {
    const double across = (in->alongX ? p.y : p.x) - in->centre, along = in->alongX ? q.x : q.y;
    if (std::abs(across) < 0.07 && fract(along / 6.0) < 0.5) c = {0.86, 0.86, 0.82};
  }
  return c;
}

glm::dvec3 paving(glm::dvec3 q) {
  const double slab = 0.4, joint = 0.012;
  const double i = std::floor(q.x / slab), j = std::floor(q.y / slab);
  const double fx = q.x - i * slab, fy = q.y - j * slab;
  if (fx < joint || fy < joint) return {0.33, 0.32, 0.30};
  return glm::dvec3(0.63, 0.61, 0.57) * (0.85 + 0.22 * hash01(std::int64_t(i), std::int64_t(j), 0, 31)) *
         (0.92 + 0.16 * noise(q, 0.03, 32));
}

glm::dvec3 plaster(const World& w, const Surface& s, glm::dvec3 p, glm::dvec3 q) {
  const double h = p.z - s.origin.z;  // above the ground floor
  glm::dvec3 c = s.tint * (0.86 + 0.14 * noise(q, 0.05, 41) + 0.08 * noise(q, 0.5, 42));
  if (h < 0.6) return c * glm::dvec3(0.72, 0.72, 0.74);  // plinth
  // String course: a darker band under each floor line.
  const double fh = w.options.city.floorHeight;
  if (fract(h / fh) * fh < 0.18 && h > 1.0) c *= 0.8;
  return c;
}

glm::dvec3 masonry(const Surface& s, glm::dvec3 p, glm::dvec3 q, double unitW, double unitH, double joint,
                   glm::dvec3 mortar, double variation) {
  const double a = glm::dot(p - s.origin, s.u), h = p.z - s.origin.z;
  const double row = std::floor(h / unitH);
  const double shifted = a + (std::fmod(std::abs(row), 2.0) == 1.0 ? 0.5 * unitW : 0.0);
  const double col = std::floor(shifted / unitW);
  if (h - row * unitH < joint || shifted - col * unitW < joint) return mortar;
  const double v = hash01(std::int64_t(col), std::int64_t(row), s.building, 51);
  return s.tint * (1.0 - 0.5 * variation + variation * v) * (0.93 + 0.12 * noise(q, 0.02, 52));
}

glm::dvec3 glass(const Surface& s, glm::dvec3 p) {
  const double a = glm::dot(p - s.origin, s.u), h = p.z - s.origin.z;
  const double fw = 0.07, sx = s.size.x, sy = s.size.y;
  if (a < fw || a > sx - fw || h < fw || h > sy - fw || std::abs(a - 0.5 * sx) < 0.5 * fw ||
      std::abs(h - 0.7 * sy) < 0.5 * fw)
    return s.tint;
  const double v =
      hash01(std::int64_t(std::floor(s.origin.x * 10.0)), std::int64_t(std::floor(s.origin.y * 10.0)),
             std::int64_t(std::floor(s.origin.z * 10.0)), 61);
  // Some windows have a pale curtain drawn on their upper part.
  if (v > 0.6 && h > 0.45 * sy) return glm::dvec3(0.70, 0.64, 0.55) * (0.9 + 0.1 * fract(a / 0.08));
  return glm::dvec3(0.10, 0.13, 0.18) + (h / sy) * glm::dvec3(0.10, 0.12, 0.14);
}

glm::dvec3 door(const Surface& s, glm::dvec3 p) {
  const double a = glm::dot(p - s.origin, s.u), h = p.z - s.origin.z;
  const double sx = s.size.x, sy = s.size.y;
  if (a < 0.08 || a > sx - 0.08 || h > sy - 0.08) return s.tint * 0.6;  // frame
  if (h > 0.72 * sy) return {0.12, 0.14, 0.18};                         // transom light
  const double plank = 0.12, col = std::floor(a / plank);
  if (a - col * plank < 0.01) return s.tint * 0.45;
  return s.tint * (0.85 + 0.3 * hash01(std::int64_t(col), s.building, 0, 71));
}

glm::dvec3 balcony(const Surface& s, glm::dvec3 p, glm::dvec3 q) {
  const double a = glm::dot(p - s.origin, s.u), h = p.z - s.origin.z;
  if (h < 0.0) return s.tint * 0.85 * (0.9 + 0.2 * noise(q, 0.05, 81));  // slab edge and underside
  // Wrought-iron look painted on the parapet: top rail and balusters every 12 cm.
  if (h > s.size.y - 0.07 || h < 0.06 || fract(a / 0.12) < 0.3) return {0.12, 0.12, 0.13};
  return s.tint * 0.95;
}

glm::dvec3 roofTiles(const Surface& s, glm::dvec3 p) {
  const double a = glm::dot(p - s.origin, s.u), b = glm::dot(p - s.origin, s.w);
  const double row = std::floor(b / 0.2);
  const double shifted = a + (std::fmod(std::abs(row), 2.0) == 1.0 ? 0.15 : 0.0);
  const double col = std::floor(shifted / 0.3);
  if (b - row * 0.2 < 0.02 || shifted - col * 0.3 < 0.015) return {0.28, 0.14, 0.10};
  return glm::dvec3(0.64, 0.32, 0.21) *
         (0.8 + 0.3 * hash01(std::int64_t(col), std::int64_t(row), s.building, 91));
}

glm::dvec3 albedo(const World& w, const Surface& s, glm::dvec3 p) {
  const glm::dvec3 q = p - w.origin;
  switch (s.material) {
    case Material::Grass:
      return grass(q);
    case Material::Asphalt:
      return asphalt(w, p, q);
    case Material::Paving:
      return paving(q);
    case Material::Kerb:
      return glm::dvec3(0.70, 0.70, 0.68) * (0.8 + 0.3 * noise(q, 0.03, 101));
    case Material::Plaster:
      return plaster(w, s, p, q);
    // Mortar close to the brick's tone: the 7.5 cm courses stay visible up close without
    // turning into moiré at 30 m (about 10 cm per pixel).
    case Material::Brick:
      return masonry(s, p, q, 0.24, 0.075, 0.012, s.tint * 1.35 + 0.05, 0.3);
    case Material::Stone:
      return masonry(s, p, q, 0.6, 0.3, 0.015, {0.55, 0.53, 0.50}, 0.18);
    case Material::Glass:
      return glass(s, p);
    case Material::Reveal:
      return s.tint * 0.8 * (0.92 + 0.12 * noise(q, 0.04, 111));
    case Material::Door:
      return door(s, p);
    case Material::Balcony:
      return balcony(s, p, q);
    case Material::RoofGravel:
      return glm::dvec3(0.52, 0.50, 0.47) * (0.65 + 0.55 * noise(q, 0.03, 121)) *
             (0.9 + 0.2 * noise(q, 0.8, 122));
    case Material::RoofTiles:
      return roofTiles(s, p);
    case Material::TreeTrunk:
      return glm::dvec3(0.36, 0.26, 0.17) * (0.75 + 0.4 * noise(q, 0.04, 131));
    case Material::TreeCrown:
      return s.tint * (0.6 + 0.7 * noise(q, 0.15, 141));
    case Material::CarBody:
      return s.tint * (0.92 + 0.08 * noise(q, 0.2, 151));
    case Material::CarGlass:
      return {0.14, 0.17, 0.21};
    case Material::CarWheel:
      return {0.06, 0.06, 0.06};
    case Material::Count:
      break;
  }
  return {1.0, 0.0, 1.0};
}

}  // namespace

glm::dvec3 shade(const World& world, const Layer& layer, const RayHit& hit) {
  const Surface& s = layer.surfaces[layer.surfaceOf[hit.triangle]];
  const CitySettings& cs = world.options.city;
  // Lambert with a fixed sun; the ambient (sky) term is a little brighter on up-facing surfaces.
  const double sun = std::max(0.0, glm::dot(hit.normal, world.sunDirection));
  const double light = cs.ambient * (0.85 + 0.15 * hit.normal.z) + cs.diffuse * sun;
  return glm::clamp(albedo(world, s, hit.position) * light, 0.0, 1.0);
}

glm::dvec3 shade(const World& world, const RayHit& hit) { return shade(world, world.truth, hit); }

glm::dvec3 applyCast(EraCast cast, glm::dvec3 c) {
  const double y = 0.299 * c.r + 0.587 * c.g + 0.114 * c.b;  // Rec. 601 luma
  switch (cast) {
    case EraCast::None:
      return c;
    case EraCast::Sepia:
      return glm::clamp(glm::dvec3(0.08 + 0.98 * y, 0.05 + 0.84 * y, 0.02 + 0.62 * y), 0.0, 1.0);
    case EraCast::Faded:
      return glm::clamp(0.62 * c + glm::dvec3(0.27, 0.25, 0.19), 0.0, 1.0);
    case EraCast::Cyanotype:
      return glm::clamp(glm::dvec3(0.10 + 0.55 * y, 0.22 + 0.62 * y, 0.42 + 0.55 * y), 0.0, 1.0);
  }
  return c;
}

}  // namespace hv::demo
