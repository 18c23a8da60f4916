// Internals shared by the demo city's translation units: a portable PRNG, hashing and value noise,
// and mesh-building helpers. Not part of the public API.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <string>
#include <vector>

#include "hv/demo/demo_city.h"
#include "hv/demo/footprint_shapes.h"
#include "hv/scene/orthophoto.h"

namespace hv::demo::detail {

// SplitMix64 (Steele, Lea & Flood 2014, "Fast splittable pseudorandom number generators"): tiny,
// well mixed, and its output is fixed by its definition, unlike std:: distributions.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() { return double(next() >> 11) * (1.0 / 9007199254740992.0); }
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
  // Uniform integer in [lo, hi] (modulo bias is negligible for the small ranges used here).
  int integer(int lo, int hi) { return lo + int(next() % std::uint64_t(hi - lo + 1)); }
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t state_;
};

// Stateless hash of integer coordinates (SplitMix64 finaliser), for per-brick or per-slab colours.
inline std::uint64_t hash(std::int64_t a, std::int64_t b = 0, std::int64_t c = 0, std::uint64_t salt = 0) {
  std::uint64_t z = salt ^ 0x2545f4914f6cdd1dULL;
  for (std::int64_t v : {a, b, c}) {
    z += std::uint64_t(v) + 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
  }
  return z;
}
inline double hash01(std::int64_t a, std::int64_t b = 0, std::int64_t c = 0, std::uint64_t salt = 0) {
  return double(hash(a, b, c, salt) >> 11) * (1.0 / 9007199254740992.0);
}

// Value noise in [0, 1]: trilinear interpolation (smoothstep-weighted) of hashed lattice values.
inline double valueNoise(glm::dvec3 p, std::uint64_t salt) {
  const glm::dvec3 f = glm::floor(p);
  const glm::dvec3 t = p - f;
  const glm::dvec3 s = t * t * (3.0 - 2.0 * t);
  const auto ix = std::int64_t(f.x), iy = std::int64_t(f.y), iz = std::int64_t(f.z);
  double v[2][2][2];
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b)
      for (int c = 0; c < 2; ++c) v[a][b][c] = hash01(ix + a, iy + b, iz + c, salt);
  auto lerp = [](double x, double y, double k) { return x + (y - x) * k; };
  const double x00 = lerp(v[0][0][0], v[1][0][0], s.x), x10 = lerp(v[0][1][0], v[1][1][0], s.x);
  const double x01 = lerp(v[0][0][1], v[1][0][1], s.x), x11 = lerp(v[0][1][1], v[1][1][1], s.x);
  return lerp(lerp(x00, x10, s.y), lerp(x01, x11, s.y), s.z);
}

// Appends a planar quad (a, b, c, d in order around it) whose normal is made to point along
// `outward`, so the mesh follows hv/scene/mesh.h's counter-clockwise-from-outside rule.
void addQuad(Layer& layer, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 d, glm::dvec3 outward,
             std::uint32_t surface);
void addTriangle(Layer& layer, glm::dvec3 a, glm::dvec3 b, glm::dvec3 c, glm::dvec3 outward, std::uint32_t surface);
// An oriented box: centre, three orthonormal axes and half-extents along them; faces outward.
void addBox(Layer& layer, glm::dvec3 centre, glm::dvec3 ax, glm::dvec3 ay, glm::dvec3 az, glm::dvec3 half,
            std::uint32_t surface);
std::uint32_t addSurface(Layer& layer, const Surface& s);

// A lot of a block: its street corner, along-street and into-block unit axes, size, and whether a
// neighbouring lot (rather than a cross street) lies on either side.
struct Lot {
  glm::dvec2 origin, u, v;
  double width, depth;
  bool gapLeft, gapRight;
};

// The lots of the block whose south-west corner is b0 (two rows of lotsPerRow, row 0 on the south
// street): the cut positions along the block are drawn from `rng`.
std::vector<Lot> blockLots(const CitySettings& s, glm::dvec2 b0, double blockW, double blockD, Rng& rng);

// A building's footprint on its lot: the shape (cells of the 3 x 3 lot grid), the grid lines in
// the lot frame, the world rings (outer counter-clockwise first, holes clockwise) and the LOD1
// height. Draws from `rng` in a fixed order (shape unless courtyard, grid lines, height).
struct DrawnFootprint {
  Shape shape = Shape::Rect;
  CellSet cells{};
  std::array<double, 4> us{}, vs{};
  std::vector<std::vector<glm::dvec2>> rings;
  double height = 0.0;
};
DrawnFootprint drawFootprint(const CitySettings& s, const Lot& lot, bool courtyard, Rng& rng);

// Large cities: each block and each lot draws from its own generator, seeded from the seed and the
// block's lattice position, so a block is the same whatever the city's size.
Rng blockRng(std::uint32_t seed, int i, int j);
struct LotDraw {
  bool built = false, courtyard = false;
  Rng rng{0};  // continues with drawFootprint, then the ground-truth details
};
LotDraw lotDraw(const CitySettings& s, std::uint32_t seed, int i, int j, int lot);
std::string largeBuildingId(int i, int j, int lot);

// A car (body, cabin, glass band, wheels) standing on the ground at `base`, heading along `dir`.
void addCar(Layer& layer, glm::dvec3 base, glm::dvec2 dir, glm::dvec3 color);

// The city seen straight from above over the DTM's extent (its first to last sample centres, the
// terrain mesh's extent): one vertical ray per pixel through its centre onto world.truth, shade()d,
// `maxSide` pixels on the longer side; alpha 0 where the ray hits nothing. The demo's
// orthophoto.tif (scene.json "orthophoto").
Orthophoto orthophotoFromAbove(const World& world, const RayCaster& truthCaster, int maxSide);

}  // namespace hv::demo::detail
