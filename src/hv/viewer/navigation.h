// Navigation for the viewer: free flight and street-level walking, focus + context
// transitions to a photograph, and the order of the photographs along a street. Plain C++ (no
// GL, no window): the desktop viewer feeds it keys and mouse motion, the tests feed it numbers.
//
// Conventions: world frame and camera frame as in hv/camera/camera.h (camera x right, y down,
// z forward). "Up" is the scene's up (Scene::up, z by default). Headings: yaw is the angle of the
// viewing direction's horizontal part from the frame's `east` axis towards `north`, pitch its
// elevation above the horizontal plane (radians, positive looking up). Times in seconds.
#pragma once

#include "hv/camera/camera.h"

#include <glm/glm.hpp>

#include <vector>

namespace hv {
class RayQuery;  // hv/scene/ray_query.h
}

namespace hv::viewer {

// An orthonormal frame around the scene's up: east x north = up.
struct UpFrame {
  glm::dvec3 up{0, 0, 1}, east{1, 0, 0}, north{0, 1, 0};
};
UpFrame upFrame(const glm::dvec3& up);

struct Heading {
  double yaw = 0.0, pitch = 0.0;
};
Heading headingOf(const glm::dvec3& forward, const UpFrame& frame);
glm::dvec3 forwardOf(const Heading& h, const UpFrame& frame);
// The rotation of a camera looking along `forward` without roll (camera x horizontal).
// `forward` must not be parallel to `up`.
glm::dmat3 camFromWorldLooking(const glm::dvec3& forward, const glm::dvec3& up);
// The world direction a camera looks along (its z axis).
glm::dvec3 forwardOf(const Camera& camera);

enum class Mode { Fly, Walk };

// Tuning of the navigation; distances in scene units (metres for geographic scenes).
struct NavigationSettings {
  double speed = 5.0;                  // units per second (the viewer derives it from the scene)
  double fastFactor = 4.0;             // while shift is held
  double lookRadiansPerPixel = 0.004;  // mouse look
  double maxPitch = 1.45;              // radians; looking straight up or down would lose the heading
  // Walking: the eye stays eyeHeight above the surface below it, found by a ray cast down from
  // maxStep above the feet (so a kerb is climbed, a wall is not); height changes are followed with
  // this time constant so the view does not jump at every step.
  double eyeHeight = 1.6;
  double maxStep = 0.5;
  double heightSmoothingSeconds = 0.12;
  double bodyRadius = 0.4;             // walking stops this far from a wall
};

// One frame's input. `move`: right, forward, up, each in [-1, 1] (keys); `lookPixels`: mouse
// motion (x right, y down).
struct NavigationInput {
  glm::dvec3 move{0.0};
  glm::dvec2 lookPixels{0.0};
  bool fast = false;
  double dt = 0.0;
};

// Holds the viewer's camera and moves it. The rotation of a camera given by setCamera (a
// photograph's, with its roll) is kept exactly until the user looks around; from then on it is
// rebuilt from yaw and pitch, without roll.
class Navigator {
 public:
  // `geometry` (may be null: walking then keeps its height and nothing blocks) is what walking
  // stands on and bumps into; it must outlive the navigator.
  explicit Navigator(const glm::dvec3& up, const RayQuery* geometry = nullptr, NavigationSettings s = {});

  void setCamera(const Camera& camera);
  const Camera& camera() const { return camera_; }
  void setMode(Mode m);
  Mode mode() const { return mode_; }
  NavigationSettings& settings() { return settings_; }
  const NavigationSettings& settings() const { return settings_; }
  const UpFrame& frame() const { return frame_; }

  // Moves the camera by the input over input.dt seconds (time-based, so the speed does not
  // depend on the frame rate). Returns true when the camera changed.
  bool update(const NavigationInput& input);
  // Walking: the eye height the camera is settling to (valid after a walking update).
  double groundEyeTarget() const { return eyeTarget_; }

  // The surface point below `p` (ray cast down from maxStep above p's feet level), if any.
  // Exposed for the tests and the viewer's status line.
  bool groundBelow(const glm::dvec3& eye, glm::dvec3& ground) const;

 private:
  glm::dvec3 walkStep(const glm::dvec3& from, const glm::dvec3& step) const;

  UpFrame frame_;
  const RayQuery* geometry_;
  NavigationSettings settings_;
  Camera camera_;
  Heading heading_;
  Mode mode_ = Mode::Fly;
  double eyeTarget_ = 0.0;
  bool haveTarget_ = false;
};

// The photograph's camera as a window of width x height shows it: same centre and rotation,
// intrinsics scaled uniformly so the whole photograph fits the window, centred (letterboxed);
// no distortion (the viewer renders pinhole views).
Camera photoInWindow(const Camera& photo, int width, int height);

// Navigation distances from the scene's scale (hv/scene/scene_scale.h: the typical distance from
// a camera to the surface it sees, else the spacing of the cameras): the speed crosses that
// distance in two seconds, the step back of focus + context is that distance (the photograph then
// covers about half the context view), an orbit keeps twice it.
struct ScaleDefaults {
  double speed = 5.0;  // units per second
  double stepBack = 10.0;
  double orbitRadius = 20.0;
};
ScaleDefaults scaleDefaults(double scale);

// Focus + context (de Castro & Brédif 2022, fig. 5): the view travels to the photograph's
// camera (focus: the photograph fills the window, aligned with the city around it), holds, then
// steps back along the viewing axis and widens the field of view (context: the photograph sits in
// its surroundings). Positions ease in and out (smoothstep), rotations slerp, intrinsics blend.
struct FocusContextSettings {
  double travelSeconds = 1.2;
  double holdSeconds = 0.6;
  double backSeconds = 1.2;
  double stepBack = 10.0;   // scene units along -forward (the viewer derives it from the scene's scale)
  double zoomOut = 0.75;    // focal multiplier at the context view (< 1 widens the view)
  double clearance = 0.5;   // kept between the context camera and geometry behind it
  // The horizon stays level: a photograph whose roll about its axis exceeds maxKeptRollDeg (a rig
  // camera stored upside down) is shown with the roll removed about `up` (the scene's up), at the
  // focus and the context view; a smaller roll is kept so the photograph fills the window exactly.
  bool levelHorizon = true;
  double maxKeptRollDeg = 10.0;
  glm::dvec3 up{0.0, 0.0, 1.0};
};

// The roll of a camera about its viewing axis, radians in (-pi, pi]: the angle between the image's
// up (-y) and the projection of `up` on the image plane, positive when `up` leans towards the
// image's x axis; 0 for an image whose x axis is horizontal and whose up points up, pi for one
// upside down, 0 when the camera looks along `up`.
double rollOf(const Camera& camera, const glm::dvec3& up);
// The camera with its roll removed about `up` (image x horizontal, image up upwards); unchanged
// when it looks along `up`.
Camera levelled(const Camera& camera, const glm::dvec3& up);

class FocusContextPath {
 public:
  // `from` and `photo` may differ in size: the path runs at `from`'s size (the window).
  // `geometry` (may be null) shortens the step back so the camera stays in front of walls.
  FocusContextPath(const Camera& from, const Camera& photo, const FocusContextSettings& s,
                   const RayQuery* geometry = nullptr);
  Camera at(double t) const;
  double duration() const;
  const Camera& focus() const { return focus_; }
  const Camera& context() const { return context_; }

 private:
  Camera from_, focus_, context_;
  FocusContextSettings s_;
};

// Blends two cameras of the same size: centre lerp, rotation slerp, intrinsics lerp, s in [0, 1].
Camera blendCameras(const Camera& a, const Camera& b, double s);
double smoothstep01(double s);

// The photographs in street order: a nearest-neighbour chain that starts at the centre farthest
// from the centroid (an end of the street) and always goes to the nearest centre not yet
// visited. Returns indices into `centres`.
std::vector<int> streetOrder(const std::vector<glm::dvec3>& centres);
// The photograph `steps` positions after `current` in `order` (before, when negative), clamped
// to the ends. `current` not in `order`: the first (steps > 0) or last element.
int stepAlong(const std::vector<int>& order, int current, int steps);
// The index of the centre nearest to p (-1 when empty).
int nearestCentre(const std::vector<glm::dvec3>& centres, const glm::dvec3& p);

}  // namespace hv::viewer
