// The viewer's pose mode (docs/viewer.md), the window side: the chosen photograph in a window of
// its own with the pairs, the pending click and the residuals drawn on it; the list of pairs
// (each removable), "solve the focal", the opacity of the photograph seen from its solved camera,
// and "save" to a cameras.json named in a text field. The state machine, the solving and the
// checks are hv/pose/pose_session.h; this draws them, turns clicks into its calls (a click in
// the 3D view through a ray cast) and runs the scripted form of those clicks (--pose-script).
#pragma once

#include "hv/camera/camera.h"
#include "hv/gpu/present.h"
#include "hv/image/image.h"
#include "hv/pose/pose_session.h"
#include "hv/scene/ray_query.h"
#include "hv/scene/scene.h"

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hv::viewer {

class PosePanel {
 public:
  // `inputs`: the files the viewer read (never written by "save").
  explicit PosePanel(std::vector<std::string> inputs) : inputs_(std::move(inputs)) {}

  bool on() const { return session_ != nullptr; }
  int photo() const { return photo_; }
  // Enters pose mode for photograph `photo` of `scene` (its image read now). False, with the
  // reason in message(), when the image cannot be read.
  bool enter(const Scene& scene, int photo);
  void leave();
  pose::PoseSession* session() { return session_.get(); }
  // The photograph's camera before pose mode (put back on leaving unless saved).
  const Camera& original() const { return original_; }
  // The current solution is the one last saved.
  bool saved() const { return session_ && savedVersion_ == session_->solutionVersion(); }

  // A click in the 3D view at framebuffer pixel `px` of `view`: the ray cast into `scene`.
  void clickView(const Camera& view, glm::dvec2 px, const RayQuery* scene);
  // Writes the photograph with its solved camera to `path` (a native cameras.json) when
  // checkSavePath allows; the outcome in message(). True when written.
  bool save(const Scene& scene, const std::string& path, bool replace);

  struct Result {
    bool cameraChanged = false;   // a new solution (or none any more): the renderer's camera to update
    bool lookFromSolved = false;  // "look from it": then and now at the solved camera
    bool leave = false;
  };
  // Draws the window; `opacity` is the photograph's over the view from its solved camera.
  Result draw(const Scene& scene, double& opacity);

  // The script of --pose-script (docs/viewer.md), one command a line:
  //   enter ID | photo U V | view X Y | remove N | focal on|off | save PATH [replace] | leave
  // `photo` and `view` are the clicks (photograph pixels; framebuffer pixels of `view`). Errors
  // name the line; the first one stops the script. Returns the errors (empty: every line ran).
  std::vector<std::string> runScript(const std::string& path, const Scene& scene, const Camera& view,
                                     const RayQuery* caster);

  const std::string& message() const { return message_; }
  int version() const { return session_ ? session_->solutionVersion() : 0; }

 private:
  std::vector<std::string> inputs_;
  std::unique_ptr<pose::PoseSession> session_;
  int photo_ = -1;
  Camera original_;
  int savedVersion_ = -1;
  Image8 image_;
  gpu::ImageTexture texture_;
  glm::ivec2 textureSize_{0};
  char savePath_[512] = "posed-cameras.json";
  bool replace_ = false;
  std::string message_;
};

}  // namespace hv::viewer
