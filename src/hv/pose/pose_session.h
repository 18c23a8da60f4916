// The viewer's pose mode (docs/viewer.md): pairs of a pixel clicked on a photograph and the point
// of the scene clicked in the 3D view, the photograph's camera solved from them (hv/pose/pose.h)
// as soon as there are enough, and what to draw: the pairs, the pending click, each pair's
// residual. Plain C++: the desktop viewer draws it (viewer/desktop/pose_panel.h) and turns a
// click in the 3D view into a world point by a ray cast; the tests drive it with the same calls.
//
// A pair is made in two clicks, the photograph first:
//
//   Photo --clickPhoto--> Scene --clickScene(hit)--> Photo (a pair added, solved when enough)
//                         Scene --clickScene(none)--> Scene (the sky: nothing added, said why)
//                         Scene --clickPhoto--> Scene (the pending pixel replaced)
//                         Scene --cancel--> Photo
#pragma once

#include "hv/camera/camera.h"
#include "hv/pose/pose.h"

#include <glm/glm.hpp>

#include <optional>
#include <string>
#include <vector>

namespace hv::pose {

struct PosePair {
  glm::dvec2 pixel{0.0};  // in the photograph, pixels from its top-left corner (docs/conventions.md)
  glm::dvec3 world{0.0};  // scene frame
};

// A residual to draw on the photograph: from the clicked pixel to where the solved camera puts
// the pair's world point.
struct ResidualLine {
  glm::dvec2 clicked{0.0}, projected{0.0};
  double pixels = 0.0;
  bool inlier = true;
};

class PoseSession {
 public:
  enum class Step { Photo, Scene };  // the next click expected

  // `photo`: the photograph's camera as the scene has it. Its intrinsics are kept unless
  // `solveFocal` (then 6 pairs are needed, else 4); its centre and rotation are never a first
  // guess: they are what the pairs replace.
  explicit PoseSession(const Camera& photo, bool solveFocal = false);

  Step step() const { return pending_ ? Step::Scene : Step::Photo; }
  const std::optional<glm::dvec2>& pending() const { return pending_; }
  const std::vector<PosePair>& pairs() const { return pairs_; }
  int pairsNeeded() const { return solveFocal_ ? 6 : 4; }
  bool solveFocal() const { return solveFocal_; }
  // Solves again with the focal freed (6 pairs) or kept (4).
  void setSolveFocal(bool on);

  // A click on the photograph (its pixels). False, with a message, outside the image.
  bool clickPhoto(glm::dvec2 pixel);
  // A click in the 3D view: the surface point the ray hit, none for the sky. False, with a
  // message, when no photograph pixel is pending or nothing was hit.
  bool clickScene(const std::optional<glm::dvec3>& world);
  void cancel() { pending_.reset(); }
  // Removes pair `index` (and solves again). False when there is no such pair.
  bool removePair(int index);
  // Moves pair `index`'s pixel on the photograph (a dragged point: its world point kept) and
  // solves again. False, with a message, when there is no such pair or the pixel is outside the
  // photograph.
  bool movePair(int index, glm::dvec2 pixel);

  // The last solution; none before enough pairs or when the pairs cannot give one (message()).
  const std::optional<pose::PoseResult>& solution() const { return solution_; }
  // Bumped by every new solution (the viewer puts the camera into the renderer when it changes).
  int solutionVersion() const { return version_; }
  std::vector<ResidualLine> residualLines() const;
  // What happened last, said for the panel: a refusal, the residuals, what to click next.
  const std::string& message() const { return message_; }

 private:
  void solve();

  Camera photo_;
  bool solveFocal_ = false;
  std::optional<glm::dvec2> pending_;
  std::vector<PosePair> pairs_;
  std::optional<pose::PoseResult> solution_;
  int version_ = 0;
  std::string message_;
};

// The ray a click at `px` (pixels of the view, distorted when the camera has distortion) casts
// into the scene: from the camera's centre along the pixel's direction. Not valid where the
// distortion cannot be inverted.
struct WorldRay {
  glm::dvec3 origin{0.0}, direction{0.0};
  bool valid = false;
};
WorldRay rayThroughPixel(const Camera& view, glm::dvec2 px);

// Where the pose mode may write its cameras.json: an error message, or empty when `path` may be
// written. Refuses an empty path, one of `inputs` (the files the viewer read: scene.json, its
// cameras, --views; compared as absolute, normalised paths) and, unless `replace`, a file that
// `exists` (never overwritten silently).
std::string checkSavePath(const std::string& path, const std::vector<std::string>& inputs, bool exists, bool replace);

}  // namespace hv::pose
