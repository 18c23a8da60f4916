// Lifting a vehicle on the ground (hv/traffic/trajectories.h) onto the terrain (the 2013 paper, §3:
// "2D trajectories lifted onto the DTM give each vehicle's 3D position and rotation"): its wheels
// on the terrain surface, its heading from the simulator, its pitch and roll from the slope under
// its wheelbase.
//
// Vehicle frame (owned here, repeated in docs/traffic.md): x right, y forward, z up, origin at the
// centre of its footprint on the ground. worldFromVehicle maps vehicle directions to world
// directions. Pitch is nose-up (asin of forward.z), roll right-side-down (asin of -right.z): a
// right-handed rotation about the forward axis.
#pragma once

#include "hv/scene/mesh.h"
#include "hv/traffic/trajectories.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <optional>
#include <vector>

namespace hv {

// The terrain's height under a point of the ground plane, as an interface: the scene's terrain
// mesh (MeshTerrainHeight) answers it whatever the terrain came from (a DTM meshed whole, the tiles
// of a quadtree, a ground plane `"terrain": {"height": h}`).
class TerrainHeight {
 public:
  virtual ~TerrainHeight() = default;
  // The terrain's elevation at (x, y) in the scene frame; nullopt off the terrain.
  virtual std::optional<double> heightAt(double x, double y) const = 0;
};

// Heights on a triangle mesh seen from above (z up): the highest triangle over (x, y), linear in
// it. Triangles seen edge-on from above (skirts, walls) are left out. A grid of buckets over the
// mesh's extent keeps a query to the few triangles near it.
class MeshTerrainHeight final : public TerrainHeight {
 public:
  explicit MeshTerrainHeight(const Mesh& mesh);
  std::optional<double> heightAt(double x, double y) const override;
  bool empty() const { return triangles_.empty(); }

 private:
  struct Tri {
    glm::dvec3 a, b, c;
  };
  std::vector<Tri> triangles_;
  glm::dvec2 lo_{0.0}, cell_{1.0};
  int nx_ = 0, ny_ = 0;
  std::vector<std::uint32_t> start_;  // nx * ny + 1 offsets into items_
  std::vector<std::uint32_t> items_;
};

// Where the wheels touch, as fractions of the vehicle's size: the wheelbase along its length, the
// track across its width.
struct WheelLayout {
  double wheelbaseFraction = 0.6;
  double trackFraction = 0.85;
};

struct VehiclePose {
  glm::dvec3 position{0.0};  // centre of the footprint, on the terrain (world)
  glm::dmat3 worldFromVehicle{1.0};
  double headingDeg = 0.0;         // the simulator's angle, clockwise from north
  double pitch = 0.0, roll = 0.0;  // radians
};

// The pose of a vehicle at `ground` on the terrain: the terrain's heights under its four wheels
// (at +-wheelbase/2 along the heading, +-track/2 across); the forward axis rises by the mean front
// minus back height over the wheelbase, the right axis by the mean right minus left height over
// the track, and the centre sits at the mean of the four heights, so that on a plane every wheel
// is on it. A wheel off the terrain takes the centre's height; nullopt when the centre is
// off the terrain.
std::optional<VehiclePose> liftOntoTerrain(const GroundPose& ground, const VehicleSize& size,
                                           const TerrainHeight& terrain, const WheelLayout& wheels = {});

// The four wheels' contact points of a pose (front-left, front-right, back-left, back-right).
std::vector<glm::dvec3> wheelContacts(const VehiclePose& pose, const VehicleSize& size, const WheelLayout& wheels = {});

}  // namespace hv
