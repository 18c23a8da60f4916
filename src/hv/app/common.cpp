#include "hv/app/common.h"

#include "hv/app/checks.h"
#include "hv/app/outputs.h"
#include "hv/io/cameras_json.h"
#include "hv/io/scene_loader.h"
#include "hv/scene/robust_extent.h"
#include "hv/util/log.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <new>
#include <sstream>
#include <stdexcept>

namespace hv::app {

namespace {

const char* const kDateForms = "YYYY, YYYY-MM, YYYY-MM-DD or YYYY-MM-DDThh:mm[:ss]";

const char* const kDebugForms = "count, weight:ID or depth:ID (ID: a photograph)";

// The kind of a --debug value ("count", "weight", "depth") and its photograph id ("" for count);
// nullopt when it has neither form.
std::optional<std::pair<std::string, std::string>> splitDebug(const std::string& text) {
  if (text == "count") return std::pair<std::string, std::string>{text, ""};
  const size_t colon = text.find(':');
  if (colon == std::string::npos || colon + 1 == text.size()) return std::nullopt;
  const std::string kind = text.substr(0, colon);
  if (kind != "weight" && kind != "depth") return std::nullopt;
  return std::pair<std::string, std::string>{kind, text.substr(colon + 1)};
}

// Rejects a malformed date while the command line is parsed, before the scene loads.
CLI::Validator isoDate() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (parseDate(text)) return "";
        return "expected an ISO 8601 date (" + std::string(kDateForms) + "), got '" + text + "'";
      },
      "DATE");
}

}  // namespace

void setAction(CLI::App& cmd, int& exitCode, std::function<int()> body) {
  // The exit statuses of docs/reliability.md: an input that cannot be used at all (the scene, an
  // option's value) is 2; anything else that stops the command is 1, with a message naming it.
  cmd.footer(exitStatusHelp());
  cmd.callback([&exitCode, body = std::move(body)] {
    try {
      exitCode = body();
    } catch (const InputError& e) {
      std::cerr << "\nerror: " << e.what() << "\n";
      exitCode = kExitNoScene;
    } catch (const std::invalid_argument& e) {
      std::cerr << "\nerror: " << e.what() << "\n";
      exitCode = kExitNoScene;
    } catch (const std::filesystem::filesystem_error& e) {
      std::cerr << "\nerror: " << e.path1().string() << ": " << e.code().message() << "\n";
      exitCode = kExitNotProduced;
    } catch (const std::bad_alloc&) {
      std::cerr << "\nerror: out of memory\n";
      exitCode = kExitNotProduced;
    } catch (const std::exception& e) {
      std::cerr << "\nerror: " << e.what() << "\n";
      exitCode = kExitNotProduced;
    }
  });
}

void addViewOptions(CLI::App& cmd, ViewOptions& o, bool withViews) {
  cmd.add_option("scene", o.scenePath, "scene.json")->required()->check(CLI::ExistingFile);
  if (withViews)
    cmd.add_option("--views", o.viewsPath, "cameras to render (cameras.json schema; image optional)")
        ->required()
        ->check(CLI::ExistingFile);
  cmd.add_option("--size", o.size, "output size WxH (intrinsics scaled uniformly; default: each view's own)");
  cmd.add_option("--k", o.k, "images blended per pixel")->check(positiveCount());
  cmd.add_option("--sigma", o.sigma, "sigma of f(d) = 1/(sigma^2 + d^2), scene units (default: camera spacing)")
      ->check(sigmaValue());
  cmd.add_option("--exclude", o.exclude, "photo ids left out (comma separated; an unknown id is named)")
      ->delimiter(',');
  cmd.add_flag("--strict", o.strict,
               "stop with exit status 1 before rendering when any input item was left out (default: render "
               "the rest, exit status 3)");
  cmd.add_option("--depth-size", o.depthSize, "depth-map resolution")->check(CLI::Range(16, 16384));
  cmd.add_option("--binding", o.binding,
                 "array (texture arrays, default) or naive (a sampler2D per image and per depth map: the baseline)")
      ->check(CLI::IsMember({"array", "naive"}));
  cmd.add_option("--depth-maps-per-frame", o.depthMapsPerFrame,
                 "progressive frames: depth maps rendered per frame, nearest camera first (Dmax)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--depth-budget-ms", o.depthBudgetMs,
                 "progressive frames: render depth maps until this many ms are spent (at least one)")
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--background", o.background, "background colour R,G,B (0-255)");
  cmd.add_option("--background-distance", o.backgroundDistance,
                 "project photographs onto a sphere of this radius (scene units) around the view where there "
                 "is no geometry, as iTowns' backgroundDistance; 0: never; default: only in a scene without "
                 "geometry (radius 100)");
  cmd.add_option("--from", o.from,
                 "only photographs dated on or after DATE (ISO 8601; a partial date such as 1905 is the "
                 "interval it names, and matches when the intervals overlap)")
      ->check(isoDate());
  cmd.add_option("--to", o.to, "only photographs dated on or before DATE (ISO 8601, as --from)")
      ->check(isoDate());
  cmd.add_flag("--dated-only", o.datedOnly, "leave out undated photographs (kept by default)");
  cmd.add_flag("--points", o.points, "draw the scene's point cloud as textured sprites");
  cmd.add_option("--point-budget", o.pointBudget, "points drawn per frame (and per depth map)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--point-radius", o.pointRadius,
                 "sprite radius, scene units (default: 0.75 x each chunk's point spacing)");
  cmd.add_option("--sprite-form", o.spriteForm,
                 "nprime (one vec3 varying, 2022) or mat3 (a mat3 varying per image, 2016; K capped by the varyings)")
      ->check(CLI::IsMember({"nprime", "mat3"}));
  cmd.add_option("--point-filter", o.pointFilter,
                 "auto (class when the cloud is classified, else epsilon), class, epsilon or none")
      ->check(CLI::IsMember({"auto", "class", "epsilon", "none"}));
  cmd.add_option("--kept-classes", o.keptClasses, "non-transient ASPRS classes, textured (default 2,6,9,10,11,17)")
      ->delimiter(',');
  cmd.add_flag("--no-points-in-depth-maps", o.noPointsInDepthMaps,
               "class filter: depth maps hold the model only (default: also the kept points)");
  cmd.add_flag("--hide-transient", o.hideTransient, "do not draw transient points (default: their own colour)");
  cmd.add_option("--epsilon", o.epsilon,
                 "epsilon filter: a point is textured by an image when within this of the model's depth there, "
                 "scene units (default: 2e-3 of the scene extent)");
  cmd.add_option("--mesh-offset", o.meshOffset,
                 "hybrid: the mesh pushed back by this along its normal behind the points, scene units "
                 "(default: 6e-4 of the scene extent)")
      ->check(CLI::NonNegativeNumber);
  cmd.add_option("--point-color", o.pointColor, "untextured points: auto, rgb, intensity or class")
      ->check(CLI::IsMember({"auto", "rgb", "intensity", "class"}));
  cmd.add_flag("--no-eye-dome", o.noEyeDome, "no eye-dome lighting on untextured points");
  cmd.add_flag("--no-masks", o.noMasks, "ignore the photographs' masks");
  cmd.add_flag("--no-distortion", o.noDistortion,
               "project the photographs as pinhole cameras, ignoring their lens distortion (to see what the "
               "correction does)");
  cmd.add_option("--hide", o.hide, "geometry left out of the view and of the depth maps: terrain, buildings, mesh")
      ->delimiter(',')
      ->check(CLI::IsMember({"terrain", "buildings", "mesh"}));
  cmd.add_flag("--frusta", o.frusta,
               "draw the photographs' frusta over the picture (the frame's images yellow, the --debug "
               "photograph cyan)");
  cmd.add_option("--frustum-depth", o.frustumDepth, "frustum length along the camera axis, scene units "
                 "(default: the camera spacing)")
      ->check(CLI::PositiveNumber);
}

void applyDebugOption(const std::string& text, const Scene& scene, render::DebugSettings& debug) {
  if (text.empty()) return;
  const auto parts = splitDebug(text);
  if (!parts) throw std::invalid_argument("--debug: expected " + std::string(kDebugForms) + ", got '" + text + "'");
  const auto& [kind, id] = *parts;
  if (kind == "count") {
    debug.view = render::DebugView::Counts;
    return;
  }
  debug.view = kind == "weight" ? render::DebugView::Weight : render::DebugView::DepthMap;
  for (size_t i = 0; i < scene.photos.size(); ++i)
    if (scene.photos[i].camera.id == id) {
      debug.photo = int(i);
      return;
    }
  throw std::invalid_argument("--debug " + text + ": no photograph has the id '" + id + "'");
}

CLI::Validator debugValue() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        if (splitDebug(text)) return "";
        return "expected " + std::string(kDebugForms) + ", got '" + text + "'";
      },
      "DEBUG");
}

std::optional<DateInterval> timeWindow(const std::string& from, const std::string& to) {
  if (from.empty() && to.empty()) return std::nullopt;
  auto read = [](const std::string& option, const std::string& text) {
    const auto d = parseDate(text);
    if (!d)
      throw std::invalid_argument(option + ": expected an ISO 8601 date (" + kDateForms + "), got '" + text +
                                  "'");
    return *d;
  };
  DateInterval w;  // open on both sides
  if (!from.empty()) w.first = read("--from", from).first;
  if (!to.empty()) w.last = read("--to", to).last;
  if (w.first > w.last)
    throw std::invalid_argument("--from " + from + " is after --to " + to + ": the time window is empty");
  return w;
}

void checkPhotoDates(const Scene& scene, Diagnostics& diag) {
  for (const auto& p : scene.photos)
    if (!p.date.empty() && !parseDate(p.date))
      diag.warn(inputMessage(scene.path, "camera '" + p.camera.id + "': date",
                             "expected an ISO 8601 date (" + std::string(kDateForms) + "), got '" + p.date +
                                 "'; the photograph is treated as undated"));
}

glm::ivec2 parseSize(const std::string& s) {
  int w = 0, h = 0;
  char x = 0;
  std::istringstream in(s);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || w <= 0 || h <= 0 || !in.eof())
    throw std::invalid_argument("--size: expected WxH with positive integers, got '" + s + "'");
  return {w, h};
}

glm::dvec3 parseColour(const std::string& s) {
  std::istringstream in(s);
  glm::dvec3 c;
  char comma = 0;
  if (!(in >> c.r >> comma >> c.g) || comma != ',' || !(in >> comma >> c.b) || comma != ',')
    throw std::invalid_argument("--background: expected R,G,B in 0-255, got '" + s + "'");
  for (int i = 0; i < 3; ++i)
    if (c[i] < 0 || c[i] > 255) throw std::invalid_argument("--background: components must be in 0-255");
  return c / 255.0;
}

Camera resizeView(const Camera& view, const std::string& size) {
  if (size.empty()) return view;
  const glm::ivec2 wh = parseSize(size);
  return view.resized(wh.x, wh.y);
}

render::RenderSettings renderSettings(const ViewOptions& o) {
  render::RenderSettings s;
  s.blend.k = o.k;
  s.blend.sigma = o.sigma;
  s.blend.exclude = o.exclude;
  s.depthSize = o.depthSize;
  s.binding = o.binding == "naive" ? render::Binding::Naive : render::Binding::Array;
  s.depthMapsPerFrame = o.depthMapsPerFrame;
  s.depthBudgetMs = o.depthBudgetMs;
  s.background = parseColour(o.background);
  s.backgroundSphere = o.backgroundDistance;
  s.blend.window = timeWindow(o.from, o.to);
  s.blend.datedOnly = o.datedOnly;
  s.points.enabled = o.points;
  s.points.budget = o.pointBudget;
  s.points.radius = o.pointRadius;
  s.points.form = o.spriteForm == "mat3" ? render::SpriteForm::Mat3 : render::SpriteForm::PlaneVector;
  s.points.filter = o.pointFilter == "class"     ? render::PointFilter::Classification
                    : o.pointFilter == "epsilon" ? render::PointFilter::Epsilon
                    : o.pointFilter == "none"    ? render::PointFilter::None
                                                 : render::PointFilter::Auto;
  s.points.keptClasses = o.keptClasses;
  s.points.keptInDepthMaps = !o.noPointsInDepthMaps;
  s.points.hideTransient = o.hideTransient;
  s.points.epsilon = o.epsilon;
  s.points.meshOffset = o.meshOffset;
  s.points.color = o.pointColor == "rgb"         ? PointColorMode::Rgb
                   : o.pointColor == "intensity" ? PointColorMode::Intensity
                   : o.pointColor == "class"     ? PointColorMode::Classification
                                                 : PointColorMode::Auto;
  s.points.eyeDome = !o.noEyeDome;
  s.blend.masks = !o.noMasks;
  s.layers.lensDistortion = !o.noDistortion;
  for (const std::string& layer : o.hide) {
    if (layer == "terrain") s.layers.terrain = false;
    else if (layer == "buildings") s.layers.buildings = false;
    else if (layer == "mesh") s.layers.mesh = false;
    else throw std::invalid_argument("--hide: expected terrain, buildings or mesh, got '" + layer + "'");
  }
  s.debug.frusta = o.frusta;
  s.debug.frustumDepth = o.frustumDepth;
  return s;
}

void checkSessionInputs(const Scene& scene, const ViewOptions& o, Diagnostics& diag) {
  // Printed whatever HV_LOG says: these name what the user asked for or gave, once.
  auto warn = [&](std::string message) {
    std::cerr << "warning: " << message << "\n";
    diag.warnings.push_back(std::move(message));
  };
  if (scene.photos.empty())
    warn(scene.path + ": no photograph loaded (the cameras file has none, or none could be read): the views "
                      "show the geometry untextured");
  for (const std::string& id : o.exclude) {
    const bool known = std::any_of(scene.photos.begin(), scene.photos.end(),
                                   [&](const Photo& p) { return p.camera.id == id; });
    if (!known) warn("--exclude: no photograph of " + scene.path + " has the id '" + id + "' (ignored)");
  }
  for (const std::string& outlier : robustExtent(scene).outliers) warn(scene.path + ": " + outlier);
}

std::unique_ptr<Session> openSession(const ViewOptions& o, Diagnostics& diag,
                                     const std::function<std::unique_ptr<gpu::Context>()>& makeContext) {
  const render::RenderSettings settings = renderSettings(o);  // bad option values fail before loading
  auto session = std::make_unique<Session>();
  session->scene = loadScene(o.scenePath, diag);
  checkPhotoDates(session->scene, diag);
  checkSessionInputs(session->scene, o, diag);
  if (!o.viewsPath.empty()) {
    CameraFileOptions viewOpts;
    viewOpts.requireImages = false;
    viewOpts.checkImageFiles = false;
    session->views = readCameraFile(o.viewsPath, viewOpts, diag);
    if (session->views.empty()) throw InputError(o.viewsPath + ": no usable view camera");
  }
  if (o.strict && !diag.ok())
    throw std::runtime_error("--strict: " + std::to_string(diag.errors.size()) +
                             " input item(s) would be left out (named above); nothing rendered");
  session->context = makeContext ? makeContext() : gpu::createHeadlessContext();
  session->renderer = std::make_unique<render::Renderer>(session->scene, settings, diag);
  return session;
}

}  // namespace hv::app
