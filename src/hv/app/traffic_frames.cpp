#include "hv/app/traffic_frames.h"

#include "hv/app/fly_command.h"
#include "hv/io/camera_path_json.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <optional>

namespace hv::app {

namespace fs = std::filesystem;

namespace {

// A vehicle's track as a polyline with the distance travelled at each sample.
struct Track {
  std::vector<glm::dvec2> xy;
  std::vector<double> t, s;

  explicit Track(const Trajectory& v) {
    for (const TrajectorySample& p : v.samples) {
      const double step = xy.empty() ? 0.0 : glm::length(p.xy - xy.back());
      s.push_back(s.empty() ? 0.0 : s.back() + step);
      xy.push_back(p.xy);
      t.push_back(p.t);
    }
  }
  // Distance travelled at time `time` (inside the samples' span).
  double at(double time) const {
    const size_t i = size_t(std::upper_bound(t.begin(), t.end(), time) - t.begin());
    if (i == 0) return s.front();
    if (i >= t.size()) return s.back();
    const double f = (time - t[i - 1]) / (t[i] - t[i - 1]);
    return s[i - 1] + f * (s[i] - s[i - 1]);
  }
  // The point `d` metres along the track; before its start (or past its end) straight on from its
  // first (last) moving segment.
  glm::dvec2 point(double d) const {
    const size_t n = xy.size();
    const auto direction = [&](size_t from, int step) {
      for (size_t i = from; i < n && i + step < n; i += size_t(step)) {
        const glm::dvec2 e = xy[i + size_t(step)] - xy[i];
        if (glm::length(e) > 1e-6) return e / glm::length(e);
      }
      return glm::dvec2(0.0);
    };
    if (d <= 0.0 || n == 1) return xy.front() + d * direction(0, 1);
    if (d >= s.back()) {
      glm::dvec2 last(0.0);  // the last segment that moves
      for (size_t i = n - 1; i > 0; --i)
        if (s[i] > s[i - 1]) {
          last = (xy[i] - xy[i - 1]) / (s[i] - s[i - 1]);
          break;
        }
      return xy.back() + (d - s.back()) * last;
    }
    const size_t i = size_t(std::upper_bound(s.begin(), s.end(), d) - s.begin());
    const double f = (d - s[i - 1]) / (s[i] - s[i - 1]);
    return xy[i - 1] + f * (xy[i] - xy[i - 1]);
  }
};

}  // namespace

TrafficChase trafficChase(const Trajectories& traffic, const TerrainHeight& terrain, const TrafficFramesOptions& o,
                          const std::vector<Camera>& photos) {
  std::vector<glm::dvec3> photoAxes;
  for (const Camera& c : photos) photoAxes.push_back(glm::normalize(c.rayDirection(c.principal)));
  TrafficChase best;
  if (o.frames < 1 || !(o.fps > 0.0)) return best;
  const double t0 = o.start, t1 = o.start + (o.frames - 1) / o.fps;
  const double focal = 0.5 * o.width / std::tan(0.5 * o.fovDeg * M_PI / 180.0);
  int bestScore = -1;
  for (const Trajectory& v : traffic.vehicles) {
    if (v.samples.front().t > t0 || v.samples.back().t < t1) continue;
    const Track track(v);
    if (track.at(t1) - track.at(t0) < 2.0 * (t1 - t0)) continue;  // under 2 m/s: waiting
    std::vector<PathKey> keys;
    int score = 0, others = 0;
    for (int i = 0; i < o.frames; ++i) {
      const double time = t0 + i / o.fps;
      const double d = track.at(time);
      const glm::dvec2 eye = track.point(d - o.behind), target = track.point(d + o.ahead);
      const auto he = terrain.heightAt(eye.x, eye.y), ht = terrain.heightAt(target.x, target.y);
      if (!he || !ht || glm::length(target - eye) < 1.0) {
        keys.clear();
        break;
      }
      const glm::dvec3 e(eye, *he + o.eyeHeight), c(target, *ht + o.targetHeight);
      keys.push_back({lookAtCamera(frameId(i), e, c, o.width, o.height, focal), i / o.fps});
      const glm::dvec2 forward = glm::normalize(target - eye);
      for (const Trajectory& other : traffic.vehicles) {
        if (&other == &v) continue;
        const auto p = sampleTrajectory(other, time);
        if (!p) continue;
        const double along = glm::dot(p->xy - eye, forward);
        others += along > 0.0 && glm::length(p->xy - eye) < 60.0;
      }
      int near = 0;
      const glm::dvec3 axis = glm::normalize(c - e);
      for (size_t k = 0; k < photos.size(); ++k)
        near += glm::length(glm::dvec2(photos[k].center) - eye) < 30.0 && glm::dot(photoAxes[k], axis) > 0.5;
      score += 2 * std::min(near, 4);
    }
    score += others;
    if (keys.empty() || score <= bestScore) continue;
    bestScore = score;
    best.vehicle = v.id;
    best.keys = std::move(keys);
    best.othersInView = others;
  }
  return best;
}

int writeTrafficFrames(render::Renderer& renderer, const Trajectories& traffic, const TerrainHeight& terrain,
                       const TrafficFramesOptions& o, const std::string& dir, const std::vector<Camera>& photos) {
  const TrafficChase chase = trafficChase(traffic, terrain, o, photos);
  if (chase.keys.empty()) {
    std::cout << "no traffic frames: no vehicle of the simulation drives through the " << o.frames << " frames from "
              << o.start << " s\n";
    return 0;
  }
  fs::create_directories(dir);
  const std::string pathFile = (fs::path(dir) / "path.json").string();
  std::ofstream(pathFile) << cameraPathJson(chase.keys);
  const std::string framesDir = (fs::path(dir) / "frames").string();
  std::cout << "rendering " << o.frames << " frames (" << o.width << "x" << o.height << ", " << o.fps
            << " fps) of the traffic from " << o.start << " s, following vehicle '" << chase.vehicle << "' ("
            << chase.othersInView << " other vehicles ahead over the frames), into " << framesDir << "\n";
  const double start = o.start, fps = o.fps;
  const FlyResult r = flyPath(
      renderer, int(chase.keys.size()), [&](int i) { return chase.keys[size_t(i)].camera; }, framesDir, false,
      [](const FlyFrame& f) { std::cerr << progressLine(f) << std::flush; },
      [start, fps](int i) { return flyTrafficTime(i, fps, start, 1.0); });
  std::cerr << "\n";
  for (const std::string& f : r.failures) std::cerr << "error: " << f << "\n";
  std::cout << "  wrote " << r.frames << " frames to " << framesDir << "/ in " << std::fixed << std::setprecision(1)
            << r.totalMs / 1000.0 << " s; the path is " << pathFile << " (histoview fly SCENE --path " << pathFile
            << " --fps " << std::setprecision(0) << fps << " --time " << start << ")\n";
  return r.frames;
}

}  // namespace hv::app
