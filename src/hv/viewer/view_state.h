// The state of a view as a URL query (the page's shared link, docs/web.md "The shared URL"): the
// camera's pose, and any other parameters (the time window, the traffic's time, changed render
// settings) as name=value pairs. Plain text in and out, so the encoding is tested on the CPU and
// the page only puts the query into its address (history.replaceState).
//
// Conventions: the pose is `pose=x,y,z,qw,qx,qy,qz,fov`: the camera centre (world, scene units,
// to 0.1 mm), camFromWorld as a unit quaternion (w first, 8 decimals), and the vertical field of
// view in degrees (6 decimals): independent of the canvas's size, so the link restores the view at
// any window size (square pixels, principal point at the centre, no lens distortion: a viewer's
// camera). Query text: application/x-www-form-urlencoded (RFC 3986 unreserved characters as they
// are, others %XX; '+' reads as a space).
#pragma once

#include "hv/camera/camera.h"

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace hv::viewer {

struct CameraPose {
  glm::dvec3 center{0.0};
  glm::dquat camFromWorld{1.0, 0.0, 0.0, 0.0};  // unit
  double fovYDeg = 60.0;                        // vertical field of view
};

// The pose of a camera (its vertical field of view from its height and fy).
CameraPose poseOf(const Camera& camera);
// A camera of `width` x `height` pixels at `pose`: square pixels, principal point at the centre.
Camera cameraAt(const CameraPose& pose, int width, int height, const std::string& id = "view");

// "x,y,z,qw,qx,qy,qz,fov" and back. parsePose throws std::invalid_argument naming `what` and
// what was expected (eight finite numbers, a non-zero quaternion, a field of view in (0, 180)).
std::string formatPose(const CameraPose& pose);
CameraPose parsePose(std::string_view text, const std::string& what = "pose");

struct ViewState {
  std::optional<CameraPose> pose;
  std::vector<std::pair<std::string, std::string>> params;  // the others, in order (names unique)
};

// "pose=...&name=value&..." (no leading '?'; the pose first when there is one).
std::string encodeViewState(const ViewState& state);
// Reads a query (a leading '?' allowed; empty pairs skipped; a name without '=' has the value "").
// Throws std::invalid_argument for a bad pose or a broken %XX escape, naming the parameter.
ViewState decodeViewState(std::string_view query);

std::string urlEncode(std::string_view text);
std::string urlDecode(std::string_view text, const std::string& what = "query");

}  // namespace hv::viewer
