// Vehicle trajectories from a traffic simulator, in the scene frame's ground plane, and the
// vehicle of one trajectory at a time t (the 2013 paper, §3: a 2D traffic simulation repopulates
// the image-based view).
//
// Conventions (owned here, repeated in docs/traffic.md):
// - time in seconds, as the simulator gives it;
// - (x, y) the vehicle's centre on the ground, in the scene frame (metres), once read: SUMO's FCD
//   gives the front bumper, its reader (hv/io/native/sumo_fcd.h) moves it to the centre;
// - angle in degrees clockwise from north, as SUMO's: north is +y of the scene frame, so angle 0
//   drives towards +y and angle 90 towards +x; the forward direction is (sin a, cos a).
#pragma once

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hv {

struct Diagnostics;
struct VehicleModels;  // hv/traffic/vehicle_model.h

// A vehicle's box (metres): length along its heading, width across, height above the ground.
struct VehicleSize {
  double length = 4.5, width = 1.8, height = 1.5;
};

// The size of a simulator's vehicle type: SUMO's vehicle classes and default type names (a name
// containing "bus", "truck", "trailer", "delivery", "motorcycle", "moped", "bicycle", case
// insensitive), else the default car (4.5 x 1.8 x 1.5 m); `known` says which.
VehicleSize vehicleSizeOf(const std::string& type, bool* known = nullptr);

struct TrajectorySample {
  double t = 0.0;
  glm::dvec2 xy{0.0};     // the vehicle's centre on the ground
  double angleDeg = 0.0;  // clockwise from north (+y)
};

struct Trajectory {
  std::string id;
  std::string type;
  VehicleSize size;
  std::vector<TrajectorySample> samples;  // by increasing t, at least one
};

// What a trajectory file holds: every vehicle's trajectory.
struct Trajectories {
  std::vector<Trajectory> vehicles;
  double tBegin = 0.0, tEnd = 0.0;  // first and last sample over all vehicles (0, 0 when none)
  // The model each vehicle class is drawn with (scene.json traffic.models); null, or a null class:
  // the built-in box with wheels.
  std::shared_ptr<const VehicleModels> models;
  std::size_t samples() const;
};

// Collects (vehicle id, type, sample) rows into trajectories: samples sorted by time, a repeated
// time of one vehicle kept once (the last), the type of a vehicle its first row's; unknown types
// get the default car with one note each in `diag`.
class TrajectoryBuilder {
 public:
  void add(const std::string& id, const std::string& type, const TrajectorySample& sample);
  std::size_t rows() const { return rows_; }
  Trajectories finish(const std::string& source, Diagnostics& diag);

 private:
  std::vector<Trajectory> vehicles_;
  std::vector<std::pair<std::string, std::size_t>> index_;  // id -> position, sorted by id
  std::size_t rows_ = 0;
};

// The CSV trajectories `t,id,x,y,angle,type` (a header naming these columns, in any order; more
// columns allowed; `type` optional). Throws InputError naming the source, line and column for a
// broken file.
Trajectories parseTrajectoriesCsv(std::string_view text, const std::string& source, Diagnostics& diag);

// The vehicle on the ground at time t: linear interpolation of the position between the samples
// around t, shortest-arc interpolation of the heading; nullopt before the first sample and after
// the last (the vehicle is not in the simulation then).
struct GroundPose {
  glm::dvec2 xy{0.0};
  double angleDeg = 0.0;  // in [0, 360)
};
std::optional<GroundPose> sampleTrajectory(const Trajectory& trajectory, double t);

// SUMO's angle (degrees clockwise from north) as the unit forward direction in the scene frame.
glm::dvec2 forwardFromSumoAngle(double angleDeg);

}  // namespace hv
