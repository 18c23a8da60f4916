// The scale of a scene, for the distances that default from it (navigation speed, step back, an
// orbit's radius): robust statistics of the geometry and the cameras, so that neither one far
// camera nor the cameras of one rig (centimetres apart) set it.
//
//   extent           the diagonal of the geometry's robust box (hv/scene/robust_extent.h);
//   surfaceDistance  the typical distance from a camera to the surface it sees: for each camera
//                    (at most kScaleCameraSamples of them), the median depth of the geometry
//                    samples (at most kScaleGeometrySamples vertices and points) inside its image;
//                    then the median over the cameras that see some;
//   spacing          the median distance from a camera to its nearest neighbour among the cameras
//                    that look the same way (within kSameHeadingDeg): the step between successive
//                    photographs of a street, which the cameras of one rig (side by side, looking
//                    apart) do not shorten;
//   scale            surfaceDistance, else spacing (within kMetricSpacingScale in a metric CRS),
//                    else extent / 10, else kDefaultScale — `source` says which.
//
// A camera is outlying when it is farther than kOutlierFactor x the reference distance (the
// surface distance, else the median nearest-camera distance; at most kOutlierMetres when the scene
// has a CRS) from every other camera and from the geometry's robust box: it is named in
// `warnings` and left out of the statistics.
#pragma once

#include "hv/scene/scene.h"

#include <cstddef>
#include <string>
#include <vector>

namespace hv {

inline constexpr std::size_t kScaleCameraSamples = 256;
inline constexpr std::size_t kScaleGeometrySamples = 20000;
inline constexpr double kSameHeadingDeg = 45.0;
inline constexpr double kOutlierFactor = 50.0;
inline constexpr double kOutlierMetres = 5000.0;
inline constexpr double kDefaultScale = 10.0;
// A scale taken from the camera spacing alone (no geometry seen) in a metric CRS stays within these
// bounds (metres): street level.
inline constexpr double kMetricSpacingScale[2] = {1.0, 30.0};

struct SceneScale {
  double extent = 0.0;           // 0: no geometry
  double surfaceDistance = 0.0;  // 0: no camera sees geometry
  double spacing = 0.0;          // 0: fewer than two (inlying) cameras looking the same way
  double scale = kDefaultScale;
  std::string source;                 // what `scale` is: "camera-to-surface distance", ...
  std::vector<std::size_t> outlying;  // indices into scene.photos
  std::vector<std::string> warnings;  // one per outlying camera (at most 10, then a count)
};

SceneScale sceneScale(const Scene& scene);

// The up axis the cameras agree on: the normalised mean of their image-up vectors (-y of each
// camera, in the world). `agreement` is the mean's length before normalising (1: all the same;
// near 0: no agreement, e.g. cameras pointing up and down). Zero vector when there is no camera.
struct CameraUp {
  glm::dvec3 up{0.0};
  double agreement = 0.0;
  std::size_t cameras = 0;
};
CameraUp cameraUp(const std::vector<Photo>& photos);
// The cameras agree on an up axis when the mean of their image-up vectors is at least this long
// (a street's cameras, level: about 1; half looking straight down: about 0.5).
inline constexpr double kCameraUpAgreement = 0.5;
// A declared up farther than this from the cameras' is named (a warning).
inline constexpr double kCameraUpDisagreementDeg = 45.0;

// Where a loaded scene's up came from, for `info`: the scene CRS's vertical; inferred from the
// cameras (the scene loader does so when there is no CRS and no `up`, and the cameras agree: the
// up is then exactly cameraUp's); z by default; or as scene.json gives it.
std::string upOrigin(const Scene& scene);

}  // namespace hv
