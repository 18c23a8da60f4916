// Viewpoints from the command line (render, eval, fly): a photograph's or a view's camera by id, a
// camera placed by its eye and the point it looks at, focus + context (the camera stepped back
// along its viewing axis), and an output size of another aspect ratio, cropped or padded.
//
// Frames: --eye and --look-at are in the scene frame (the scene CRS, metres; hv/scene/scene.h)
// unless --local says the render frame (scene frame minus the render origin, what `info` prints as
// `origin`). The eye camera has no roll: its image x axis is horizontal about the scene's up.
#pragma once

#include "hv/camera/camera.h"
#include "hv/scene/scene.h"

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hv::app {

struct ViewpointOptions {
  std::vector<std::string> cameras;  // --camera ID[,ID...]: photographs' or views' cameras
  std::string eye, lookAt;           // --eye X,Y,Z --look-at X,Y,Z
  double fovDeg = 60.0;              // --fov: the horizontal field of view of the eye camera
  bool local = false;                // --local: --eye and --look-at in the render frame
  std::optional<double> stepBack;    // --step-back M: the context view, M back along the axis
  double zoomOut = 0.75;             // focal multiplier of the context view (navigation's default)
  std::string fit = "crop";          // --fit crop|pad: --size of another aspect ratio
  bool any() const { return !cameras.empty() || !eye.empty() || !lookAt.empty(); }
};

// The size of an --eye camera when --size is not given.
inline constexpr int kDefaultEyeWidth = 1024, kDefaultEyeHeight = 768;

// Registers --camera, --eye, --look-at, --fov, --local, --step-back and --fit.
void addViewpointOptions(CLI::App& cmd, ViewpointOptions& o);

// "X,Y,Z" -> the vector; throws std::invalid_argument naming the option and the expected form.
glm::dvec3 parseVec3(const std::string& option, const std::string& text);

enum class Fit { Crop, Pad };
Fit parseFit(const std::string& text);  // "crop" | "pad"; throws std::invalid_argument otherwise

// The view at width x height. Same aspect ratio: intrinsics scaled uniformly (Camera::resized).
// Another one: scaled uniformly so that the view covers the output (Crop: what sticks out is cut
// off, equally on both sides) or fits inside it (Pad: the bands around it show what lies beyond
// the original frame), the principal point moved with the centre. Nothing is stretched.
Camera fitView(const Camera& view, int width, int height, Fit fit);
// --size and --fit applied to a view ("": the view's own size).
Camera sizeView(const Camera& view, const std::string& size, const std::string& fit);

// The context view of focus + context (de Castro & Brédif 2022, fig. 5; as the viewer's
// hv/viewer/navigation.h FocusContextPath, without its geometry clearance): `stepBack` units back
// along the viewing axis, the focal length times `zoomOut` about the image centre, roll removed
// about `up` when `level` (a photograph stored upside down gives an upright context view).
Camera contextView(const Camera& focus, double stepBack, double zoomOut, const glm::dvec3& up, bool level = true);

// The views the options ask for, in the order given: each --camera id looked up among the scene's
// photographs, then among `views` (the --views file's cameras); then the --eye camera (id "eye",
// at --size or kDefaultEye*). With --step-back each is replaced by its context view (same id).
// Sizes are not applied here (sizeView does). Throws std::invalid_argument naming the option: an
// unknown id (with a few of the ids that exist), --eye without --look-at or the reverse, an eye on
// its target, a view straight along the up axis, a negative step back.
std::vector<Photo> viewpointViews(const Scene& scene, const std::vector<Photo>& views, const ViewpointOptions& o,
                                  const std::string& size);

// The eye camera alone (used by viewpointViews).
Camera eyeCamera(const Scene& scene, const ViewpointOptions& o, int width, int height);

// The focus camera of each viewpoint (no step back): what `fly` travels between.
std::vector<Photo> focusViews(const Scene& scene, const std::vector<Photo>& views, const ViewpointOptions& o,
                              const std::string& size);

}  // namespace hv::app
