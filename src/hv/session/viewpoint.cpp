#include "hv/session/viewpoint.h"

#include "hv/session/session.h"
#include "hv/viewer/navigation.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace hv::app {

void addViewpointOptions(CLI::App& cmd, ViewpointOptions& o) {
  const std::string group = "Viewpoint (instead of, or picking from, a cameras file)";
  cmd.add_option("--camera", o.cameras,
                 "render from this photograph's camera, or a --views camera's (ids, comma separated)")
      ->delimiter(',')
      ->group(group);
  cmd.add_option("--eye", o.eye, "camera position X,Y,Z (scene CRS; with --local, the render frame)")->group(group);
  cmd.add_option("--look-at", o.lookAt, "the point the --eye camera looks at, X,Y,Z")->group(group);
  cmd.add_option("--fov", o.fovDeg, "horizontal field of view of the --eye camera, degrees (default 60)")
      ->check(CLI::Range(1.0, 170.0))
      ->group(group);
  cmd.add_flag("--local", o.local, "--eye and --look-at are in the render frame (scene frame minus `info`'s origin)")
      ->group(group);
  cmd.add_option("--step-back", o.stepBack,
                 "focus + context: step back M scene units along the viewing axis and widen the view (x" +
                     std::to_string(o.zoomOut).substr(0, 4) + " focal), horizon levelled")
      ->check(CLI::NonNegativeNumber)
      ->group(group);
  cmd.add_option("--fit", o.fit,
                 "a --size of another aspect ratio: crop (default: cover the output, cut the overflow) or pad "
                 "(fit inside, show what lies around)")
      ->check(CLI::IsMember({"crop", "pad"}))
      ->group(group);
}

glm::dvec3 parseVec3(const std::string& option, const std::string& text) {
  glm::dvec3 v(0.0);
  std::string rest = text;
  for (char& c : rest)
    if (c == ',') c = ' ';
  std::istringstream in(rest);
  std::string tail;
  if (!(in >> v.x >> v.y >> v.z) || (in >> tail) || !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z) ||
      std::count(text.begin(), text.end(), ',') != 2)
    throw std::invalid_argument(option + ": expected X,Y,Z (three numbers, comma separated), got '" + text + "'");
  return v;
}

Fit parseFit(const std::string& text) {
  if (text == "crop" || text.empty()) return Fit::Crop;
  if (text == "pad") return Fit::Pad;
  throw std::invalid_argument("--fit: expected crop or pad, got '" + text + "'");
}

Camera fitView(const Camera& view, int width, int height, Fit fit) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("--size: expected a positive size");
  if (std::abs(double(view.height) * width / view.width - height) <= 1.0) return view.resized(width, height);
  const double sx = double(width) / view.width, sy = double(height) / view.height;
  const double s = fit == Fit::Crop ? std::max(sx, sy) : std::min(sx, sy);
  Camera c = view.scaled(s, width, height);
  // The scaled frame is centred in the output: its corner moves by half the difference.
  const glm::dvec2 offset((width - view.width * s) / 2.0, (height - view.height * s) / 2.0);
  c.principal += offset;
  if (c.distortion) c.distortion->center += offset;
  return c;
}

Camera sizeView(const Camera& view, const std::string& size, const std::string& fit) {
  if (size.empty()) return view;
  const glm::ivec2 wh = parseSize(size);
  return fitView(view, wh.x, wh.y, parseFit(fit));
}

Camera contextView(const Camera& focus, double stepBack, double zoomOut, const glm::dvec3& up, bool level) {
  viewer::FocusContextSettings s;
  s.stepBack = stepBack;
  s.zoomOut = zoomOut;
  s.up = up;
  s.levelHorizon = level;
  Camera c = viewer::FocusContextPath(focus, focus, s).context();
  c.id = focus.id;
  return c;
}

Camera eyeCamera(const Scene& scene, const ViewpointOptions& o, int width, int height) {
  if (o.eye.empty() != o.lookAt.empty())
    throw std::invalid_argument(o.eye.empty() ? "--look-at needs --eye (the camera position)"
                                              : "--eye needs --look-at (the point the camera looks at)");
  const glm::dvec3 shift = o.local ? scene.origin : glm::dvec3(0.0);
  const glm::dvec3 eye = parseVec3("--eye", o.eye) + shift, target = parseVec3("--look-at", o.lookAt) + shift;
  const glm::dvec3 d = target - eye;
  if (glm::length(d) <= 0.0) throw std::invalid_argument("--eye and --look-at are the same point");
  const glm::dvec3 up = glm::normalize(scene.up);
  if (glm::length(glm::cross(glm::normalize(d), up)) < 1e-6)
    throw std::invalid_argument(
        "--eye to --look-at runs along the scene's up axis; the image's up would be "
        "undefined (move --look-at sideways a little)");
  const double focal = width / 2.0 / std::tan(o.fovDeg * std::numbers::pi / 360.0);
  return lookAtCamera("eye", eye, target, width, height, focal, up);
}

namespace {

std::string someIds(const std::vector<Photo>& a, const std::vector<Photo>& b) {
  std::string list;
  int n = 0;
  for (const auto* v : {&a, &b})
    for (const Photo& p : *v) {
      if (n == 5) return list + ", ...";
      list += (n++ ? ", " : "") + p.camera.id;
    }
  return n ? list : "none: the scene has no photograph and no --views were given";
}

}  // namespace

std::vector<Photo> focusViews(const Scene& scene, const std::vector<Photo>& views, const ViewpointOptions& o,
                              const std::string& size) {
  std::vector<Photo> out;
  for (const std::string& id : o.cameras) {
    const Photo* found = nullptr;
    for (const auto* list : {&scene.photos, &views})
      for (const Photo& p : *list)
        if (!found && p.camera.id == id) found = &p;
    if (!found)
      throw std::invalid_argument("--camera " + id + ": no photograph of " + scene.path +
                                  (views.empty() ? "" : " and no --views camera") +
                                  " has this id (ids: " + someIds(scene.photos, views) + ")");
    out.push_back(*found);
  }
  if (!o.eye.empty() || !o.lookAt.empty()) {
    glm::ivec2 wh(kDefaultEyeWidth, kDefaultEyeHeight);
    if (!size.empty()) wh = parseSize(size);
    Photo p;
    p.camera = eyeCamera(scene, o, wh.x, wh.y);
    out.push_back(p);
  }
  return out;
}

std::vector<Photo> viewpointViews(const Scene& scene, const std::vector<Photo>& views, const ViewpointOptions& o,
                                  const std::string& size) {
  std::vector<Photo> out = focusViews(scene, views, o, size);
  if (o.stepBack) {
    if (*o.stepBack < 0.0 || !std::isfinite(*o.stepBack))
      throw std::invalid_argument("--step-back: expected a distance >= 0");
    for (Photo& p : out) p.camera = contextView(p.camera, *o.stepBack, o.zoomOut, scene.up);
  }
  return out;
}

}  // namespace hv::app
