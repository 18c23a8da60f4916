// The demo city's simulated mobile-mapping lidar scan.
#include <atomic>
#include <cmath>
#include <numbers>
#include <thread>

#include "hv/demo/demo_city.h"

namespace hv::demo {

namespace {

// One turn of the scanner: where it is and the plane it turns in.
struct Turn {
  glm::dvec3 origin;
  glm::dvec3 across;  // unit, horizontal, across the street (to the left of travel)
  double phase;       // radians: the turn's first ray, so successive turns interleave
};

std::uint16_t to16(double c) {  // 8-bit value as LAS 16-bit colour, so LAS and PLY agree exactly
  return std::uint16_t(std::lround(glm::clamp(c, 0.0, 1.0) * 255.0) * 257);
}

}  // namespace

PointCloud simulateLidar(const World& world) {
  // The vehicle drives the survey streets: all of them in the small city, the central ones in a large one.
  const LidarSettings& ls = world.options.lidar;
  // Everything that stands in today's city, in one layer so that shade() finds each hit's surface.
  Layer scanned = world.truth;
  scanned.append(world.trees);
  scanned.append(world.parkedCars);
  const RayCaster caster(scanned.mesh);

  std::vector<Turn> turns;
  for (const Street& st : world.surveyStreets) {
    const glm::dvec2 along = st.alongX ? glm::dvec2(1, 0) : glm::dvec2(0, 1);
    const glm::dvec2 left(-along.y, along.x);
    const glm::dvec2 centre = st.alongX ? glm::dvec2(0, st.centre) : glm::dvec2(st.centre, 0);
    const int n = int(std::floor((st.to - st.from) / ls.profileSpacing));
    for (int i = 0; i <= n; ++i) {
      const double s = st.from + ls.profileSpacing * i;
      const glm::dvec2 xy = centre + along * s - left * ls.laneOffset;
      // The golden-ratio phase spreads the rays of successive turns evenly between each other.
      const double phase = std::fmod(double(turns.size()) * 0.6180339887498949, 1.0) * 2.0 * std::numbers::pi /
                           double(ls.raysPerProfile);
      turns.push_back({glm::dvec3(xy, world.groundZ(xy.x, xy.y) + ls.scannerHeight), glm::dvec3(left, 0.0), phase});
    }
  }

  struct Hit {
    glm::dvec3 position;
    glm::vec3 normal;
    glm::u16vec3 rgb;
    std::uint16_t intensity;
    std::uint8_t cls;
  };
  std::vector<std::vector<Hit>> hits(turns.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t t; (t = next.fetch_add(1)) < turns.size();) {
      const Turn& turn = turns[t];
      for (int k = 0; k < ls.raysPerProfile; ++k) {
        const double a = turn.phase + 2.0 * std::numbers::pi * k / ls.raysPerProfile;
        const glm::dvec3 dir = std::cos(a) * turn.across + std::sin(a) * glm::dvec3(0, 0, 1);
        const auto hit = caster.intersect(turn.origin, dir, ls.minRange, ls.maxRange);
        if (!hit) continue;
        const glm::dvec3 n = glm::dot(hit->normal, dir) > 0.0 ? -hit->normal : hit->normal;
        const glm::dvec3 c = shade(world, scanned, *hit);
        const double luma = 0.299 * c.r + 0.587 * c.g + 0.114 * c.b;
        const auto material = Material(scanned.mesh.triangleTags[hit->triangle]);
        hits[t].push_back({hit->position,
                           glm::vec3(n),
                           {to16(c.r), to16(c.g), to16(c.b)},
                           std::uint16_t(std::lround(65535.0 * glm::clamp(luma * -glm::dot(n, dir), 0.0, 1.0))),
                           asprsClass(material)});
      }
    }
  };
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();

  std::size_t total = 0;
  for (const auto& h : hits) total += h.size();
  PointCloud cloud;
  cloud.crs = "EPSG:2154";
  cloud.resize(total, {.intensity = true, .classification = true, .rgb = true, .normals = true});
  std::size_t i = 0;
  for (const auto& turn : hits)
    for (const Hit& h : turn) {
      cloud.positions[i] = h.position;
      cloud.normals[i] = h.normal;
      cloud.rgb[i] = h.rgb;
      cloud.intensity[i] = h.intensity;
      cloud.classification[i] = h.cls;
      ++i;
    }
  return cloud;
}

}  // namespace hv::demo
