// Cameras of the demo city (photographs and held-out views), their moving cars, and the ray-cast
// rendering of a shot.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <thread>

#include "hv/demo/demo_internal.h"

namespace hv::demo {

using detail::Rng;

namespace {

constexpr double kDeg = 3.141592653589793 / 180.0;

// Rows of R (world -> camera): x right, y down, z forward (camera.h). Heading `yaw` counter-clockwise
// from +x, `pitch` up from the horizon, `roll` about the viewing direction. Built from unit vectors
// and cross products, so R is orthonormal to rounding.
glm::dmat3 camFromWorldOf(double yaw, double pitch, double roll) {
  const glm::dvec3 fwd(std::cos(pitch) * std::cos(yaw), std::cos(pitch) * std::sin(yaw), std::sin(pitch));
  const glm::dvec3 right0 = glm::normalize(glm::cross(fwd, glm::dvec3(0, 0, 1)));
  const glm::dvec3 down0 = glm::cross(fwd, right0);
  const glm::dvec3 right = std::cos(roll) * right0 + std::sin(roll) * down0;
  const glm::dvec3 down = glm::cross(fwd, right);
  glm::dmat3 r;
  for (int c = 0; c < 3; ++c) {
    r[c][0] = right[c];
    r[c][1] = down[c];
    r[c][2] = fwd[c];
  }
  return r;
}

bool isBuildingMaterial(Material m) { return m >= Material::Plaster && m <= Material::RoofTiles; }

struct Size {
  int w, h;
};
constexpr Size kPhotoSizes[] = {{320, 240}, {400, 300}, {360, 270}, {300, 300}};

class Planner {
 public:
  Planner(const World& w, const RayCaster& caster)
      : w_(w), s_(w.options.city), caster_(caster), rng_(0xca3e7a5ULL ^ (std::uint64_t(w.options.seed) << 20)) {}

  ShotPlan plan() {
    const DemoOptions& o = w_.options;
    ShotPlan out;
    std::vector<int> streetPhotos;
    for (int i = 0; i < o.photos; ++i) {
      Shot shot;
      shot.elevated = i % 6 == 3;
      out.photos.push_back(shot);
      if (!shot.elevated) streetPhotos.push_back(i);
    }
    // Street-level walks; each walk with a held-out view in its middle, so views lie between
    // photographs that look the same way.
    const int nViews = std::max(0, o.views);
    const int nWalks = std::max({nViews, int((streetPhotos.size() + 3) / 4), 1});
    size_t nextPhoto = 0;
    for (int k = 0; k < nWalks; ++k) {
      const int nPhotos = int(streetPhotos.size() / size_t(nWalks)) + (k < int(streetPhotos.size() % size_t(nWalks)));
      const bool hasView = k < nViews;
      const int poses = nPhotos + (hasView ? 1 : 0);
      if (poses == 0) continue;
      const std::vector<Camera> cams = walk(poses);
      for (int j = 0; j < poses; ++j) {
        if (hasView && j == poses / 2) {
          Shot view;
          view.camera = cams[size_t(j)];
          finishIntrinsics(view.camera, {320, 240}, rng_.uniform(55.0, 70.0));
          out.views.push_back(view);
        } else {
          out.photos[size_t(streetPhotos[nextPhoto++])].camera = cams[size_t(j)];
        }
      }
    }
    int carDebt = 0, maskDebt = 0;
    for (int i = 0; i < o.photos; ++i) {
      Shot& shot = out.photos[size_t(i)];
      if (shot.elevated) shot.camera = elevated();
      const Size size = kPhotoSizes[rng_.integer(0, 3)];
      finishIntrinsics(shot.camera, size, shot.elevated ? rng_.uniform(45.0, 65.0) : rng_.uniform(50.0, 75.0));
      if (i % 6 == 2) addDistortion(shot.camera);
      // Cars go to every third photograph, masked in every other one of those. A camera that sees
      // no carriageway passes its role on to the next plain street-level photograph.
      const bool plain = i % 6 == 0;
      if (i % 3 == 1 || (plain && carDebt > 0)) {
        const bool owed = i % 3 != 1;
        const bool wantMask = owed ? maskDebt > 0 : i % 6 == 1;
        addCars(shot);
        if (shot.cars.mesh.empty()) {
          carDebt += owed ? 0 : 1;
          maskDebt += !owed && wantMask ? 1 : 0;
        } else {
          shot.masked = wantMask;
          carDebt -= owed ? 1 : 0;
          maskDebt -= owed && wantMask ? 1 : 0;
        }
      }
      if (i % 6 == 5) {
        static constexpr EraCast casts[] = {EraCast::Sepia, EraCast::Faded, EraCast::Cyanotype};
        shot.cast = casts[(i / 6) % 3];
      }
      const int year = shot.cast != EraCast::None ? rng_.integer(1890, 1915) : rng_.integer(1890, 1960);
      char date[16];
      std::snprintf(date, sizeof date, "%04d-%02d-%02d", year, rng_.integer(1, 12), rng_.integer(1, 28));
      shot.date = date;
      char id[16];
      std::snprintf(id, sizeof id, "p%04d", i + 1);
      shot.camera.id = id;
    }
    for (size_t k = 0; k < out.views.size(); ++k) {
      char id[16];
      std::snprintf(id, sizeof id, "v%03d", int(k + 1));
      out.views[k].camera.id = id;
    }
    return out;
  }

 private:
  const World& w_;
  const CitySettings& s_;
  const RayCaster& caster_;
  Rng rng_;

  void finishIntrinsics(Camera& c, Size size, double hfovDeg) {
    c.width = size.w;
    c.height = size.h;
    const double f = 0.5 * size.w / std::tan(0.5 * hfovDeg * kDeg);
    c.focal = {f, f};
    c.principal = {0.5 * size.w + rng_.uniform(-4.0, 4.0), 0.5 * size.h + rng_.uniform(-4.0, 4.0)};
    c.skew = 0.0;
  }

  // Radial distortion (Brédif 2013, fig. 2) with a displacement of `corner` pixels at the farthest
  // image corner, split over c3, c5, c7; r2max at 1.5 x that radius, where the polynomial is still
  // monotonic (derivative >= 1 - 3.5 corner / R > 0 at the corner for corner/R <= 0.06, and about
  // 0.2 at 1.5 R for barrel distortion), so undistort() inverts every pixel of the image.
  void addDistortion(Camera& c) {
    LensDistortion d;
    d.center = c.principal + glm::dvec2(rng_.uniform(-3.0, 3.0), rng_.uniform(-3.0, 3.0));
    double radius = 0.0;
    for (glm::dvec2 corner :
         {glm::dvec2(0, 0), glm::dvec2(c.width, 0), glm::dvec2(0, c.height), glm::dvec2(c.width, c.height)})
      radius = std::max(radius, glm::length(corner - d.center));
    const double disp = rng_.uniform(s_.distortionCornerMin, s_.distortionCornerMax) * (rng_.chance(0.6) ? -1.0 : 1.0);
    d.c3 = 0.8 * disp / std::pow(radius, 3);
    d.c5 = 0.15 * disp / std::pow(radius, 5);
    d.c7 = 0.05 * disp / std::pow(radius, 7);
    d.r2max = 2.25 * radius * radius;
    c.distortion = d;
    for (glm::dvec2 corner :
         {glm::dvec2(0, 0), glm::dvec2(c.width, 0), glm::dvec2(0, c.height), glm::dvec2(c.width, c.height)})
      if (!c.undistort(corner)) throw std::logic_error("demo city: distortion not invertible at an image corner");
  }

  // On a coarse ray grid: enough building, not too much sky, and not a wall filling the frame.
  bool seesCity(const Camera& c, double closeDistance) {
    int building = 0, sky = 0, close = 0, total = 0;
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 12; ++i) {
        const glm::dvec2 px((i + 0.5) * c.width / 12.0, (j + 0.5) * c.height / 9.0);
        const glm::dvec3 dir = glm::normalize(c.rayDirection(px));
        const auto hit = caster_.intersect(c.center, dir);
        ++total;
        if (!hit) {
          ++sky;
          continue;
        }
        if (isBuildingMaterial(Material(w_.truth.mesh.triangleTags[hit->triangle]))) ++building;
        if (hit->t < closeDistance) ++close;
      }
    return building >= s_.minBuildingFraction * total && sky <= s_.maxSkyFraction * total &&
           close <= s_.maxCloseFraction * total;
  }

  bool placeable(glm::dvec3 centre) const {
    if (w_.insideBuilding(centre.x, centre.y)) return false;
    // Nothing (a balcony, a wall) within half a metre around the camera.
    for (glm::dvec3 d :
         {glm::dvec3(1, 0, 0), glm::dvec3(-1, 0, 0), glm::dvec3(0, 1, 0), glm::dvec3(0, -1, 0), glm::dvec3(0, 0, 1)})
      if (caster_.occluded(centre, d, 0.0, 0.5)) return false;
    return true;
  }

  std::vector<Camera> walk(int poses) {
    for (int attempt = 0;; ++attempt) {
      if (attempt > 200) throw std::logic_error("demo city: no street-level camera sees the buildings");
      const Street& st = w_.surveyStreets[size_t(rng_.integer(0, int(w_.surveyStreets.size()) - 1))];
      const double sgn = rng_.chance(0.5) ? 1.0 : -1.0;
      const double length = (poses - 1) * s_.walkStep;
      const double lo = st.from + w_.streetWidth, hi = st.to - w_.streetWidth - length;
      if (hi <= lo) continue;
      const double start = sgn > 0 ? rng_.uniform(lo, hi) : rng_.uniform(lo + length, hi + length);
      const double side = rng_.chance(0.5) ? 1.0 : -1.0;
      const double lateral = side * rng_.uniform(2.5, 0.5 * w_.streetWidth - 1.5);
      const double heading = st.alongX ? (sgn > 0 ? 0.0 : 180.0) : (sgn > 0 ? 90.0 : 270.0);
      std::vector<Camera> cams;
      for (int j = 0; j < poses; ++j) {
        const double along = start + sgn * j * s_.walkStep + rng_.uniform(-1.0, 1.0);
        const double across = st.centre + lateral + rng_.uniform(-0.5, 0.5);
        const glm::dvec2 xy = st.alongX ? glm::dvec2(along, across) : glm::dvec2(across, along);
        Camera c;
        c.width = 320;
        c.height = 240;
        c.focal = {220.0, 220.0};
        c.principal = {160.0, 120.0};
        c.center = glm::dvec3(xy, w_.groundZ(xy.x, xy.y) + rng_.uniform(s_.streetEyeMin, s_.streetEyeMax));
        if (!placeable(c.center)) break;
        bool ok = false;
        for (int look = 0; look < 30 && !ok; ++look) {
          // Along the street, or turned towards the façades of either side.
          const double mode = rng_.uniform();
          double yaw = heading +
                       (mode < 0.3 ? rng_.uniform(-12.0, 12.0) : (mode < 0.65 ? 1.0 : -1.0) * rng_.uniform(20.0, 60.0));
          c.camFromWorld = camFromWorldOf(yaw * kDeg, rng_.uniform(2.0, 10.0) * kDeg, rng_.uniform(-1.5, 1.5) * kDeg);
          ok = seesCity(c, s_.streetCloseDistance);
        }
        if (!ok) break;
        cams.push_back(c);
      }
      if (int(cams.size()) == poses) return cams;
    }
  }

  Camera elevated() {
    for (int attempt = 0; attempt < 500; ++attempt) {
      const Street& st = w_.surveyStreets[size_t(rng_.integer(0, int(w_.surveyStreets.size()) - 1))];
      const double along = rng_.uniform(st.from + 0.5 * w_.streetWidth, st.to - 0.5 * w_.streetWidth);
      const double across = st.centre + rng_.uniform(-3.0, 3.0);
      const glm::dvec2 xy = st.alongX ? glm::dvec2(along, across) : glm::dvec2(across, along);
      const Building& target = w_.buildings[size_t(rng_.integer(0, int(w_.buildings.size()) - 1))];
      glm::dvec2 tc(0.0);
      for (glm::dvec2 p : target.rings[0]) tc += p / double(target.rings[0].size());
      const double dist = glm::length(tc - xy);
      if (dist < 20.0 || dist > 90.0) continue;
      Camera c;
      c.width = 320;
      c.height = 240;
      c.focal = {260.0, 260.0};
      c.principal = {160.0, 120.0};
      c.center = glm::dvec3(xy, w_.groundZ(xy.x, xy.y) + rng_.uniform(s_.elevatedMin, s_.elevatedMax));
      const double targetZ = 0.5 * (target.groundFloorZ + target.topZ);
      const double pitch = std::clamp(std::atan2(targetZ - c.center.z, dist), -55.0 * kDeg, -15.0 * kDeg);
      const double yaw = std::atan2(tc.y - xy.y, tc.x - xy.x) + rng_.uniform(-8.0, 8.0) * kDeg;
      c.camFromWorld = camFromWorldOf(yaw, pitch, rng_.uniform(-2.0, 2.0) * kDeg);
      if (placeable(c.center) && seesCity(c, s_.elevatedCloseDistance)) return c;
    }
    throw std::logic_error("demo city: no elevated camera sees the buildings");
  }

  // One to three cars on the carriageway in front of the camera, visible from it: aim through a
  // random pixel of the lower part of the image and keep road points at a sensible distance, then
  // put the car in the lane on that side of the centre line.
  void addCars(Shot& shot) {
    const Camera& c = shot.camera;
    const int want = rng_.integer(1, 3);
    std::vector<glm::dvec2> placed;
    for (int attempt = 0; attempt < 600 && int(placed.size()) < want; ++attempt) {
      const glm::dvec2 pd(rng_.uniform(0.1, 0.9) * c.width, rng_.uniform(0.4, 0.95) * c.height);
      const auto dir = sampleRay(c, pd);
      if (!dir) continue;
      const auto hit = caster_.intersect(c.center, *dir);
      if (!hit || !w_.onRoad(hit->position.x, hit->position.y)) continue;
      const Street* st = nullptr;
      int bands = 0;  // 2 on a crossing: no car there
      for (const Street& s : w_.streets) {
        const double across = s.alongX ? hit->position.y : hit->position.x;
        if (std::abs(across - s.centre) <= 0.5 * w_.roadWidth) {
          st = &s;
          ++bands;
        }
      }
      if (bands != 1) continue;
      const double acrossHit = (st->alongX ? hit->position.y : hit->position.x) - st->centre;
      const double lane = acrossHit >= 0.0 ? 1.0 : -1.0;
      const double along = st->alongX ? hit->position.x : hit->position.y;
      const double across = st->centre + lane * rng_.uniform(1.2, 2.2);
      const glm::dvec2 xy = st->alongX ? glm::dvec2(along, across) : glm::dvec2(across, along);
      const glm::dvec2 alongDir = st->alongX ? glm::dvec2(1.0, 0.0) : glm::dvec2(0.0, 1.0);
      if (!w_.onRoad(xy.x + 2.6 * alongDir.x, xy.y + 2.6 * alongDir.y) ||
          !w_.onRoad(xy.x - 2.6 * alongDir.x, xy.y - 2.6 * alongDir.y))
        continue;
      const double dist = glm::length(xy - glm::dvec2(c.center));
      if (dist < 6.0 || dist > (shot.elevated ? 80.0 : 35.0)) continue;
      bool apart = true;
      for (glm::dvec2 p : placed) apart = apart && glm::length(p - xy) > 6.5;
      if (!apart) continue;
      const glm::dvec3 mid(xy, w_.groundZ(xy.x, xy.y) + 0.8);
      const Projection pr = c.project(mid);
      if (!pr.inImage) continue;
      const glm::dvec3 toCar = mid - c.center;
      if (caster_.occluded(c.center, toCar, 0.0, glm::length(toCar) - 2.5)) continue;
      // Driving on the right: the lane side sets the heading.
      const glm::dvec2 dir2 = st->alongX ? glm::dvec2(-lane, 0.0) : glm::dvec2(0.0, lane);
      const glm::dvec3 color(rng_.uniform(0.05, 0.9), rng_.uniform(0.05, 0.9), rng_.uniform(0.05, 0.9));
      detail::addCar(shot.cars, glm::dvec3(xy, w_.groundZ(xy.x, xy.y)), dir2, color);
      placed.push_back(xy);
    }
  }
};

}  // namespace

ShotPlan planShots(const World& world, const RayCaster& caster) { return Planner(world, caster).plan(); }

std::optional<glm::dvec3> sampleRay(const Camera& camera, glm::dvec2 pxDistorted) {
  const auto ideal = camera.undistort(pxDistorted);
  if (!ideal) return std::nullopt;
  return glm::normalize(camera.rayDirection(*ideal));
}

Rendered renderShot(const World& world, const RayCaster& truthCaster, const Shot& shot, int samplesPerAxis) {
  const Camera& cam = shot.camera;
  const int n = std::max(1, samplesPerAxis);
  const int w = cam.width, h = cam.height;
  std::unique_ptr<RayCaster> carCaster;
  if (!shot.cars.mesh.empty()) carCaster = std::make_unique<RayCaster>(shot.cars.mesh);
  Rendered out;
  out.color = Image8(w, h, 3);
  out.coverage = Image8(w, h, 1);
  std::vector<std::uint8_t> carPixel(size_t(w) * h, 0);
  const glm::dvec3 sky = world.options.city.skyColor;

  std::atomic<int> nextRow{0};
  auto worker = [&]() {
    for (int y = nextRow++; y < h; y = nextRow++)
      for (int x = 0; x < w; ++x) {
        glm::dvec3 sum(0.0);
        int covered = 0;
        bool car = false;
        for (int sy = 0; sy < n; ++sy)
          for (int sx = 0; sx < n; ++sx) {
            const glm::dvec2 pd(x + (sx + 0.5) / n, y + (sy + 0.5) / n);
            const auto dir = sampleRay(cam, pd);
            if (!dir) {
              sum += sky;
              continue;
            }
            auto hit = truthCaster.intersect(cam.center, *dir);
            const Layer* layer = &world.truth;
            if (carCaster) {
              const double tMax = hit ? hit->t : 1e30;
              if (auto carHit = carCaster->intersect(cam.center, *dir, 0.0, tMax); carHit && carHit->t < tMax) {
                hit = carHit;
                layer = &shot.cars;
                car = true;
              }
            }
            if (hit) {
              sum += shade(world, *layer, *hit);
              ++covered;
            } else {
              sum += sky;
            }
          }
        const glm::dvec3 c = applyCast(shot.cast, sum / double(n * n));
        for (int k = 0; k < 3; ++k)
          out.color.at(x, y, k) = std::uint8_t(std::floor(glm::clamp(c[k], 0.0, 1.0) * 255.0 + 0.5));
        out.coverage.at(x, y, 0) = covered == n * n ? 255 : 0;
        carPixel[size_t(y) * w + x] = car ? 1 : 0;
      }
  };
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();

  if (shot.masked) {
    // 0 over car pixels dilated by a square of radius maskDilation (Chebyshev distance).
    const int r = int(std::lround(world.options.city.maskDilation));
    out.mask = Image8(w, h, 1, 255);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (!carPixel[size_t(y) * w + x]) continue;
        for (int yy = std::max(0, y - r); yy <= std::min(h - 1, y + r); ++yy)
          for (int xx = std::max(0, x - r); xx <= std::min(w - 1, x + r); ++xx) out.mask.at(xx, yy, 0) = 0;
      }
  }
  return out;
}

}  // namespace hv::demo
