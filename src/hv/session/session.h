// What the subcommands share: loading a scene and its views, parsing option values, and the
// headless renderer set-up.
#pragma once

#include "hv/gpu/context.h"
#include "hv/render/renderer.h"
#include "hv/scene/scene.h"
#include "hv/session/viewpoint.h"
#include "hv/util/dates.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace CLI {
class App;
class Validator;
}

namespace hv::app {

// Makes `body` the subcommand's action: its return value is the exit code; an exception is
// printed as "error: ..." and gives exit code 2 (bad input never crashes the program).
void setAction(CLI::App& cmd, int& exitCode, std::function<int()> body);

// Options shared by render, eval, fly and view.
struct ViewOptions {
  std::string scenePath;
  std::string viewsPath;            // empty: no views file (fly reads a path instead)
  std::string size;                 // "WxH", empty: each view's own
  // The render settings given on the command line, as text by setting name
  // (render/settings_schema.h); renderSettings() applies them through the schema.
  std::map<std::string, std::string> settings;
  std::vector<std::string> hide;    // --hide terrain,buildings,mesh: --no-terrain ... in one option
  std::string debug;                // count | weight:ID | depth:ID (empty: none)
  bool strict = false;  // stop before rendering when an input item was left out
  // --camera, --eye/--look-at, --step-back, --fit (render, eval, fly; registered by
  // addViewpointOptions): when any is given, the session's views are the viewpoints asked for.
  ViewpointOptions viewpoint;
};
// Registers the scene argument, --size, and one option per render setting of the schema (a flag
// pair --NAME / --no-NAME for a boolean), checked while the command line is parsed.
// `withViews`: the required --views option (render); the other commands declare their own.
void addViewOptions(CLI::App& cmd, ViewOptions& o, bool withViews = true);

// "640x480" -> (640, 480); throws std::invalid_argument with the expected form.
glm::ivec2 parseSize(const std::string& s);

// The --from/--to window: [first day of --from, last day of --to], either end open when absent;
// nullopt when both are. Throws std::invalid_argument naming the option and the text for a date
// that is not ISO 8601, or when --from is after --to.
std::optional<DateInterval> timeWindow(const std::string& from, const std::string& to);

// Warns (file, camera id, field "date") for every photograph whose date is not an ISO 8601 date:
// such a photograph is treated as undated by the time window.
void checkPhotoDates(const Scene& scene, Diagnostics& diag);

// Warns (never an error: the exit status stays) about what the options and the scene leave
// unsaid: no photograph at all, --exclude ids no photograph has, outlying coordinates
// (hv/scene/robust_extent.h, left out of the origin and the depth ranges).
void checkSessionInputs(const Scene& scene, const ViewOptions& o, Diagnostics& diag);

// When the time window (--from/--to, --dated-only) selects no photograph of the scene: a message
// saying so, with the span of the photographs' dates; "" otherwise (also without a window).
std::string timeWindowSelection(const Scene& scene, const ibr::BlendSettings& blend);

// The view camera at the requested output size: intrinsics scaled uniformly; a different aspect
// ratio is an error (std::invalid_argument naming the view).
Camera resizeView(const Camera& view, const std::string& size);

struct Session {
  Scene scene;
  std::shared_ptr<const Orthophoto> orthophoto;  // scene.json "orthophoto" (hv::loadOrthophoto); null: none
  std::vector<Photo> views;
  std::unique_ptr<gpu::Context> context;
  std::unique_ptr<render::Renderer> renderer;
};

// Loads the scene and the views (when o.viewsPath is set; o.viewpoint, when given, picks and makes
// the views: viewpointViews), prints what failed, creates the context
// (`makeContext`, e.g. a window's; default: headless EGL) and renderer. Throws (InputError,
// std::invalid_argument for option values) when nothing can be rendered; option values are checked
// before anything is loaded.
std::unique_ptr<Session> openSession(const ViewOptions& o, Diagnostics& diag,
                                     const std::function<std::unique_ptr<gpu::Context>()>& makeContext = {});
// The settings the command line asked for: a default RenderSettings with o.settings (and --hide)
// applied through the schema. Throws std::invalid_argument naming the option and the value.
render::RenderSettings renderSettings(const ViewOptions& o);

// --debug: "count", "weight:ID" or "depth:ID" (ID a photograph of the scene) into `debug` (view
// and photo); "" leaves it as it is. Throws std::invalid_argument naming the option and the text,
// or the id no photograph has.
void applyDebugOption(const std::string& text, const Scene& scene, render::DebugSettings& debug);
// Checks the form of a --debug value while the command line is parsed (CLI11 validator).
CLI::Validator debugValue();

}  // namespace hv::app
