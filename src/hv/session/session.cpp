#include "hv/session/session.h"

#include "hv/io/cameras_json.h"
#include "hv/io/native/orthophoto_reader.h"
#include "hv/io/native/scene_loader.h"
#include "hv/layers/native/layer_import.h"
#include "hv/render/settings_schema.h"
#include "hv/scene/robust_extent.h"
#include "hv/session/make_renderer.h"
#include "hv/session/outputs.h"
#include "hv/util/log.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <new>
#include <iostream>
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

namespace {

// CLI11 checks a value with the schema's own parser, so the message is the one every surface
// gives (the option's name is prefixed by CLI11 itself).
CLI::Validator settingValue(const render::Setting& setting) {
  return CLI::Validator(
      [&setting](std::string& text) -> std::string {
        // A list option is checked item by item (the delimiter split it): each as a one-item list.
        try {
          render::parseSettingValue(setting, text);
          return "";
        } catch (const std::invalid_argument& e) {
          const std::string message = e.what(), prefix = "--" + setting.name + ": ";
          return message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
        }
      },
      "");
}

std::string optionHelp(const render::Setting& s) {
  std::string help = s.help;
  if (!s.unit.empty()) help += " (" + s.unit + ")";
  if (s.apply == render::SettingApply::Reload) help += "; read when the renderer is made";
  return help;
}

}  // namespace

void addViewOptions(CLI::App& cmd, ViewOptions& o, bool withViews) {
  cmd.add_option("scene", o.scenePath, "scene.json")->required()->check(CLI::ExistingFile);
  if (withViews)
    cmd.add_option("--views", o.viewsPath, "cameras to render (cameras.json schema; image optional)")
        ->required()
        ->check(CLI::ExistingFile);
  cmd.add_option("--size", o.size, "output size WxH (intrinsics scaled uniformly; default: each view's own)");
  cmd.add_flag("--strict", o.strict,
               "stop with exit status 1 before rendering when any input item was left out (default: render "
               "the rest, exit status 3)");
  for (const render::Setting& s : render::settingsSchema()) {
    const std::string name = s.name, def = render::defaultText(s);
    CLI::Option* opt = nullptr;
    switch (s.type) {
      case render::SettingType::Bool:
        // --NAME sets it, --no-NAME clears it (CLI11 counts a negated flag as -1).
        opt = cmd.add_flag_function(
            "--" + name + ",!--no-" + name,
            [&o, name](std::int64_t count) { o.settings[name] = count > 0 ? "true" : "false"; },
            optionHelp(s) + (def == "true" ? " (default on; --no-" + name + ": off)" : ""));
        break;
      case render::SettingType::IntList:
      case render::SettingType::TextList:
        opt = cmd.add_option_function<std::vector<std::string>>(
                     "--" + name,
                     [&o, name](const std::vector<std::string>& items) {
                       std::string text;
                       for (const std::string& item : items) text += (text.empty() ? "" : ",") + item;
                       o.settings[name] = text;
                     },
                     optionHelp(s) + ", comma separated")
                  ->delimiter(',');
        break;
      default:
        opt = cmd.add_option_function<std::string>(
            "--" + name, [&o, name](const std::string& text) { o.settings[name] = text; }, optionHelp(s));
        break;
    }
    if (s.type != render::SettingType::Bool) {
      opt->check(settingValue(s));
      opt->type_name(s.type == render::SettingType::Enum ? "{" + CLI::detail::join(s.spellings, ",") + "}"
                                                         : std::string(render::typeName(s.type)));
      if (!def.empty()) opt->default_str(def);
    }
    opt->group("Render settings (" + s.group + ")");
  }
  cmd.add_option("--hide", o.hide,
                 "geometry left out of the view and of the depth maps: terrain, buildings, mesh (as --no-terrain, "
                 "--no-buildings, --no-mesh)")
      ->delimiter(',')
      ->check(CLI::IsMember({"terrain", "buildings", "mesh"}))
      ->group("Render settings (" + render::setting("terrain").group + ")");
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
  render::RenderSettings s;
  render::setFromText(s, "from", from);
  render::setFromText(s, "to", to);
  return s.blend.window;
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

Camera resizeView(const Camera& view, const std::string& size) {
  if (size.empty()) return view;
  const glm::ivec2 wh = parseSize(size);
  return view.resized(wh.x, wh.y);
}

render::RenderSettings renderSettings(const ViewOptions& o) {
  render::RenderSettings s;
  // In the schema's order (not the command line's): --from is applied before --to.
  for (const render::Setting& setting : render::settingsSchema())
    if (const auto it = o.settings.find(setting.name); it != o.settings.end())
      setting.set(s, render::parseSettingValue(setting, it->second));
  // A background colour given on the command line is the colour of what no photograph covers and no
  // geometry fills, as before there was a sky: the sky stays only when asked for as well.
  if (o.settings.count("background") && !o.settings.count("sky")) s.untextured.sky = false;
  for (const std::string& layer : o.hide) {
    if (layer != "terrain" && layer != "buildings" && layer != "mesh")
      throw std::invalid_argument("--hide: expected terrain, buildings or mesh, got '" + layer + "'");
    render::setFromText(s, layer, "false");
  }
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
  const auto excluded = o.settings.find("exclude");
  if (excluded != o.settings.end()) {
    std::stringstream ids(excluded->second);
    for (std::string id; std::getline(ids, id, ',');) {
      id.erase(0, id.find_first_not_of(' '));
      id.erase(id.find_last_not_of(' ') + 1);
      if (id.empty()) continue;
      const bool known = std::any_of(scene.photos.begin(), scene.photos.end(),
                                     [&](const Photo& p) { return p.camera.id == id; });
      if (!known) warn("--exclude: no photograph of " + scene.path + " has the id '" + id + "' (ignored)");
    }
  }
  for (const std::string& outlier : robustExtent(scene).outliers) warn(scene.path + ": " + outlier);
  if (const std::string window = timeWindowSelection(scene, renderSettings(o).blend); !window.empty()) warn(window);
}

std::string timeWindowSelection(const Scene& scene, const ibr::BlendSettings& blend) {
  if ((!blend.window && !blend.datedOnly) || scene.photos.empty()) return "";
  int selected = 0, undated = 0;
  std::optional<DateInterval> span;
  for (const Photo& p : scene.photos) {
    const std::optional<DateInterval> when = p.date.empty() ? std::nullopt : parseDate(p.date);
    if (!when) {
      ++undated;
      if (!blend.datedOnly) ++selected;  // as ibr::planFrame: undated photographs pass the window
      continue;
    }
    span = span ? DateInterval{std::min(span->first, when->first), std::max(span->last, when->last)} : *when;
    if (!blend.window || overlaps(*when, *blend.window)) ++selected;
  }
  if (selected > 0) return "";
  auto end = [](std::int64_t day, bool open) { return open ? std::string("open") : formatDay(day); };
  std::string what = blend.window ? "the time window " +
                                        end(blend.window->first, blend.window->first == DateInterval{}.first) +
                                        " .. " + end(blend.window->last, blend.window->last == DateInterval{}.last)
                                  : std::string("the time window");
  if (blend.datedOnly) what += " with --dated-only";
  std::string dates = span ? "the photographs' dates span " + formatDay(span->first) + " .. " + formatDay(span->last)
                           : std::string("no photograph has a date");
  if (undated > 0 && span) dates += ", " + std::to_string(undated) + " undated";
  return what + " (--from/--to) selects 0 of " + std::to_string(scene.photos.size()) + " photographs of " +
         scene.path + " (" + dates + "): the views show the geometry untextured";
}

namespace {

// The photographs' edited layers (scene.json "layers", docs/layers.md): each file read back and
// its visibility layers peeled again at the file's size with the export's default settings, then
// given to the renderer, which textures each sub-image onto its own layer's surfaces. A file that
// cannot be used is reported (its path, why) and the photograph renders as itself.
void applyLayers(const Scene& scene, render::Renderer& renderer, Diagnostics& diag) {
  for (const auto& [id, path] : layers::readLayerFiles(scene, diag)) {
    const auto it = std::find_if(scene.photos.begin(), scene.photos.end(),
                                 [&](const Photo& p) { return p.camera.id == id; });
    if (it == scene.photos.end()) continue;  // readLayerFiles named it
    const std::size_t photo = std::size_t(it - scene.photos.begin());
    try {
      const layers::ImportedLayers in = layers::importLayers(path, it->camera);
      renderer.setLayeredPhotograph(int(photo), std::make_shared<const layers::LayeredPhotograph>(layers::layeredPhotograph(
                                                    scene, photo, in, layers::LayerExportSettings{}, diag)));
      log::info("layers: photograph '" + id + "' textured with " + std::to_string(in.subImages.size()) +
              " edited sub-image(s) of " + path);
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (layers of photograph '" + id + "' left out; it renders as itself)");
    }
  }
}

}  // namespace

std::unique_ptr<Session> openSession(const ViewOptions& o, Diagnostics& diag,
                                     const std::function<std::unique_ptr<gpu::Context>()>& makeContext) {
  const render::RenderSettings settings = renderSettings(o);  // bad option values fail before loading
  auto session = std::make_unique<Session>();
  session->scene = loadScene(o.scenePath, diag);
  session->orthophoto = loadOrthophoto(session->scene, diag);
  checkPhotoDates(session->scene, diag);
  checkSessionInputs(session->scene, o, diag);
  if (!o.viewsPath.empty()) {
    CameraFileOptions viewOpts;
    viewOpts.requireImages = false;
    viewOpts.checkImageFiles = false;
    session->views = readCameraFile(o.viewsPath, viewOpts, diag);
    if (session->views.empty()) throw InputError(o.viewsPath + ": no usable view camera");
  }
  if (o.viewpoint.any()) session->views = viewpointViews(session->scene, session->views, o.viewpoint, o.size);
  if (o.strict && !diag.ok())
    throw std::runtime_error("--strict: " + std::to_string(diag.errors.size()) +
                             " input item(s) would be left out (named above); nothing rendered");
  session->context = makeContext ? makeContext() : gpu::createHeadlessContext();
  session->renderer = makeRenderer(session->scene, settings, diag, session->orthophoto);
  return session;
}

std::unique_ptr<render::Renderer> makeRenderer(const Scene& scene, const render::RenderSettings& settings,
                                               Diagnostics& diag, std::shared_ptr<const Orthophoto> orthophoto) {
  auto renderer = std::make_unique<render::Renderer>(scene, settings, diag);
  applyLayers(scene, *renderer, diag);
  if (orthophoto) renderer->setOrthophoto(std::move(orthophoto));
  return renderer;
}

}  // namespace hv::app
