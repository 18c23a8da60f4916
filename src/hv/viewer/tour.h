// Camera paths made from a scene, for `histoview path` and `fly --camera`: a tour that visits the
// photographs in street order (focus + context at each), and an orbit around a point. The keys are
// those of hv/camera/camera_path.h (times in seconds; every key at one image size), written by
// hv/io/camera_path_json.h as the PATH.json that `fly` reads.
#pragma once

#include "hv/camera/camera_path.h"
#include "hv/viewer/navigation.h"

#include <glm/glm.hpp>

#include <vector>

namespace hv::viewer {

// The length of the open path through `centres` in `order`.
double pathLength(const std::vector<glm::dvec3>& centres, const std::vector<int>& order);

// A short open path through every centre: streetOrder's nearest-neighbour chain, then 2-opt
// (Croes 1958: reverse a stretch of the path whenever that shortens it, until no reversal does;
// the ends may move too). Quadratic per pass; passes are capped (maxPasses), so thousands of
// photographs still finish. Never longer than the nearest-neighbour chain.
std::vector<int> tourOrder(const std::vector<glm::dvec3>& centres, int maxPasses = 50);

struct TourSettings {
  FocusContextSettings focus;  // step back, zoom out, hold and back times, horizon levelling
  double speed = 5.0;          // scene units per second between photographs (travel takes at
                               // least focus.travelSeconds)
};

// Key cameras for a walk through `photos` (visited in the given order) at width x height: for
// each, travel to its focus view (photoInWindow, horizon levelled as FocusContextPath does),
// hold, step back along its axis to the context view; then on to the next. Times increase strictly.
// Throws std::invalid_argument when `photos` is empty or the size is not positive.
std::vector<PathKey> focusContextKeys(const std::vector<Camera>& photos, int width, int height, const TourSettings& s);

struct OrbitSettings {
  double radius = 50.0;        // horizontal distance from the point, scene units
  double elevationDeg = 30.0;  // the eye above the point's horizontal plane, seen from the point
  double seconds = 24.0;       // one turn
  int keys = 12;               // key cameras per turn (the path closes on the first one)
  double fovDeg = 60.0;        // horizontal field of view
};

// One turn around `around` (counter-clockwise seen from above `up`), every key looking at it with
// no roll, the first key on the `east` side of upFrame(up). Throws std::invalid_argument for a
// radius, time or key count that makes no path.
std::vector<PathKey> orbitKeys(const glm::dvec3& around, const glm::dvec3& up, int width, int height,
                               const OrbitSettings& s);

}  // namespace hv::viewer
