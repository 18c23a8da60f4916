// The browser entry (docs/web.md): a WebGL2 context on the page's canvas and the same
// hv::render::Renderer as `render` and the desktop viewer, driven from JavaScript through embind.
// Platform code only: the page (web/histoview.js) fetches the export over HTTP and writes what
// arrives into Emscripten's in-memory file system; this class reads the scene (meshes, points,
// cameras) from there, and a
// photograph joins the selection once its bytes have arrived (photoArrived). No threads: the
// renderer decodes on this thread (decodeThreads 0), at most one photograph per frame, so the
// picture improves from frame to frame while the page stays responsive.
#include "hv/gpu/gl.h"
#include "hv/gpu/present.h"
#include "hv/io/cameras_json.h"
#include "hv/io/web_orthophoto.h"
#include "hv/io/web_scene.h"
#include "hv/pose/pose_session.h"
#include "hv/render/renderer.h"
#include "hv/render/settings_schema.h"
#include "hv/traffic/trajectories.h"
#include "hv/util/log.h"
#include "hv/viewer/map_overview.h"
#include "hv/viewer/navigation.h"
#include "hv/viewer/then_now.h"
#include "hv/viewer/timeline.h"
#include "hv/viewer/traffic_clock.h"
#include "hv/viewer/view_state.h"
#include "web_services.h"

#include <emscripten.h>
#include <emscripten/bind.h>
#include <emscripten/html5.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace hv::web {

using json = nlohmann::json;
using namespace hv::viewer;

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

class WebViewer {
 public:
  // `canvas`: a CSS selector ("#view"). Throws (reported to JS) when WebGL2 is unavailable.
  explicit WebViewer(const std::string& canvas) {
    EmscriptenWebGLContextAttributes attrs;
    emscripten_webgl_init_context_attributes(&attrs);
    attrs.majorVersion = 2;
    attrs.minorVersion = 0;
    attrs.alpha = false;
    attrs.depth = false;
    attrs.stencil = false;
    attrs.antialias = false;
    attrs.preserveDrawingBuffer = true;  // frames are drawn only when something changed
    context_ = emscripten_webgl_create_context(canvas.c_str(), &attrs);
    if (context_ <= 0) {
      error_ = "WebGL2 is not available on this page (emscripten_webgl_create_context: " + std::to_string(context_) + ")";
      return;
    }
    emscripten_webgl_make_context_current(context_);
  }

  std::string error() const { return error_; }
  std::string glInfo() const { return context_ > 0 ? gpu::glDescription() : std::string(); }

  // Reads the scene from the in-memory file system (manifest path) and creates the renderer with
  // the settings set so far (setSetting). Every photograph starts excluded until photoArrived.
  // Returns "" or the errors, one per line.
  std::string load(const std::string& manifest) {
    if (context_ <= 0) return error_;
    try {
      Diagnostics diag;
      WebSceneOptions options;
      options.checkImageFiles = false;  // the images are fetched afterwards
      const auto t0 = std::chrono::steady_clock::now();
      installPageRemoteReader(manifest.substr(0, manifest.rfind('/') + 1));  // photographs by URL
      scene_ = std::make_unique<Scene>(readWebScene(manifest, options, diag));
      orthophoto_ = readWebOrthophoto(manifest, diag);  // draped where no photograph reaches
      sceneMs_ = msSince(t0);  // the points' chunk organisation (hv::organizeChunks) included
      arrivedPhoto_.assign(scene_->photos.size(), false);
      // The points as `render --points` draws them (its defaults): on when the scene has some and
      // they fit in one frame's point budget (2 M by default), unless the page said otherwise.
      if (!pointsSet_) settings_.points.enabled = pointsOnAtStart(settings_.points.budget);
      renderer_ = std::make_unique<render::Renderer>(*scene_, rendererSettings(), diag_);
      if (orthophoto_) renderer_->setOrthophoto(orthophoto_);
      presenter_ = std::make_unique<gpu::Presenter>();
      nav_ = std::make_unique<Navigator>(scene_->up, nullptr);
      const double spacing = scene_->cameraSpacing();
      nav_->settings().speed = std::clamp(spacing, 1.0, 50.0);
      focus_.stepBack = 2.0 * spacing;
      std::vector<glm::dvec3> centres;
      for (const auto& p : scene_->photos) centres.push_back(p.camera.center);
      order_ = streetOrder(centres);
      std::vector<std::string> dates;
      for (const auto& p : scene_->photos) dates.push_back(p.date);
      dates_ = readPhotoDates(dates);
      histogram_ = dateHistogram(dates_);
      const DateInterval axisDays = histogram_.days();
      axis_ = {axisDays.first, axisDays.last};
      if (scene_->traffic && !scene_->traffic->vehicles.empty())
        clock_ = TrafficClock(scene_->traffic->tBegin, scene_->traffic->tEnd);
      clock_.seek(settings_.traffic.time);
      std::string errors;
      for (const auto& e : diag.errors) errors += e + "\n";
      for (const auto& w : diag.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      if (scene_->photos.empty()) errors += manifest + ": no photographs\n";
      return errors;
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
  }

  // The photographs as JSON: [{"id", "date", "image", "mask"}] (paths in the file system).
  std::string photos() const {
    json a = json::array();
    if (!scene_) return a.dump();
    for (const auto& p : scene_->photos)
      a.push_back({{"id", p.camera.id}, {"date", p.date}, {"image", p.imagePath}, {"mask", p.maskPath}});
    return a.dump();
  }
  // Photograph indices, nearest camera centre to the current view first (the order to fetch in).
  std::string fetchOrder() const {
    std::vector<int> idx(scene_ ? scene_->photos.size() : 0);
    for (size_t i = 0; i < idx.size(); ++i) idx[i] = int(i);
    if (nav_) {
      const glm::dvec3 c = nav_->camera().center;
      std::stable_sort(idx.begin(), idx.end(), [&](int a, int b) {
        return glm::distance(scene_->photos[size_t(a)].camera.center, c) <
               glm::distance(scene_->photos[size_t(b)].camera.center, c);
      });
    }
    return json(idx).dump();
  }
  // The photograph's files are in the file system: it may texture the view from the next frame.
  void photoArrived(int i) {
    if (!scene_ || i < 0 || size_t(i) >= scene_->photos.size() || arrivedPhoto_[size_t(i)]) return;
    arrivedPhoto_[size_t(i)] = true;
    renderer_->settings().blend.exclude = rendererSettings().blend.exclude;
    ++arrived_;
    dirty_ = true;
  }
  int arrived() const { return arrived_; }
  // Photographs from services (web_services.h): the requests of a IIIF image service for
  // photograph i (which is then read from them), and where the page puts a URL's bytes.
  std::string iiifPlan(int i, const std::string& infoText, const std::string& url) {
    if (!scene_ || i < 0 || size_t(i) >= scene_->photos.size()) return json{{"error", "no such photograph"}}.dump();
    return web::iiifPlan(scene_->photos[size_t(i)], infoText, url);
  }
  std::string remoteFilePath(const std::string& url) const { return web::remoteFilePath("", url); }
  // The full image of IIIF photograph i is in the file system: it replaces the preview the
  // photograph joined with, in place (Renderer::replaceImage). False when none was pending.
  bool photoFullArrived(int i) {
    if (!scene_ || !renderer_ || i < 0 || size_t(i) >= scene_->photos.size()) return false;
    if (!web::iiifFullArrived(scene_->photos[size_t(i)])) return false;
    renderer_->replaceImage(i);
    dirty_ = true;
    return true;
  }

  // Cameras. The views file (cameras.json schema, images optional) is in the file system.
  std::string setViewFromFile(const std::string& path, const std::string& id, int width, int height) {
    try {
      Diagnostics diag;
      CameraFileOptions o;
      o.requireImages = false;
      o.checkImageFiles = false;
      for (const auto& v : readCameraFile(path, o, diag))
        if (v.camera.id == id) return setCameraFitted(v.camera, width, height);
      for (const auto& p : scene_->photos)
        if (p.camera.id == id) return setCameraFitted(p.camera, width, height);
      return "no view or photograph has the id '" + id + "'";
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  // An overview from the south-west, above the scene (the desktop viewer's start).
  void overview(int width, int height) {
    const UpFrame f = upFrame(scene_->up);
    const Aabb b = scene_->bounds();
    const double extent = std::max(1.0, std::max(b.size().x, b.size().y));
    const glm::dvec3 centre = b.center();
    const glm::dvec3 eye = centre - (0.55 * f.north + 0.25 * f.east) * extent + 0.35 * extent * f.up;
    const double focal = height / 2.0 / std::tan(30.0 * M_PI / 180.0);
    nav_->setCamera(lookAtCamera("web", eye, centre, width, height, focal, f.up));
    focusPath_.reset();
    dirty_ = true;
  }
  // Keeps the camera, at another canvas size (the focal scaled with the height).
  void resize(int width, int height) {
    const Camera& c = nav_->camera();
    if (c.width == width && c.height == height) return;
    nav_->setCamera(c.scaled(double(height) / c.height, width, height));
    dirty_ = true;
  }

  // One frame's navigation input (keys: right, forward, up in [-1, 1]; mouse motion in pixels).
  void move(double right, double forward, double up, double lookX, double lookY, bool fast, double dt) {
    if (!nav_) return;
    NavigationInput in;
    in.move = {right, forward, up};
    in.lookPixels = {lookX, lookY};
    in.fast = fast;
    in.dt = dt;
    if (glm::length(in.move) > 0.0 || glm::length(in.lookPixels) > 0.0) {
      focusPath_.reset();
      leaveThenNow();  // the photograph fits only its own camera
    }
    if (nav_->update(in)) dirty_ = true;
  }
  void setSpeed(double s) { if (nav_) nav_->settings().speed = s; }
  double speed() const { return nav_ ? nav_->settings().speed : 0.0; }

  // Focus + context on photograph i: travel to its camera, hold, step back.
  void focusPhoto(int i) {
    if (!scene_ || i < 0 || size_t(i) >= scene_->photos.size()) return;
    leaveThenNow();
    focused_ = i;
    settings_.debug.photo = i;
    renderer_->settings().debug.photo = i;  // the weight and depth-map views show the chosen one
    dirty_ = true;
    focusPath_ = std::make_unique<FocusContextPath>(nav_->camera(), scene_->photos[size_t(i)].camera, focus_, nullptr);
    focusStart_ = std::chrono::steady_clock::now();
    nav_->setMode(Mode::Fly);
  }
  // The photograph `steps` along the street from the focused one (N / P).
  int stepPhoto(int steps) {
    if (order_.empty()) return -1;
    const int next = stepAlong(order_, focused_, steps);
    focusPhoto(next);
    return next;
  }
  int focused() const { return focused_; }

  void setStepBack(double d) { focus_.stepBack = d; }
  bool hasPoints() const { return scene_ && !scene_->points.empty(); }
  // A large cloud (more points than `budget`, a frame's: the page would draw a subset and each
  // frame would cost the whole budget) starts hidden; the Points group switches it on.
  bool pointsOnAtStart(std::uint64_t budget) const { return hasPoints() && scene_->points.size() <= budget; }

  // Any render setting by its name and text, as on the command line (render/settings_schema.h:
  // "k" "4", "point-filter" "epsilon", "terrain" "false"); one read when the renderer is made
  // makes a new one. Before load(), the settings the renderer starts with. Returns "" or the error
  // (the option, the text and what was expected).
  std::string setSetting(const std::string& name, const std::string& text) {
    try {
      render::setFromText(settings_, name, text);
      pointsSet_ |= name == "points";
      if (name == "time") clock_.seek(settings_.traffic.time);
      if (!renderer_) return "";
      const render::Setting& s = render::setting(name);
      if (s.apply == render::SettingApply::Live) {
        s.set(renderer_->settings(), s.get(rendererSettings()));
      } else {
        rebuildRenderer();
      }
      dirty_ = true;
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  // The settings schema with the current values (render::settingsJson), from which the page
  // builds its controls.
  std::string settingsSchema() const { return render::settingsJson(settings_); }

  // Renders a progressive frame into the canvas when something changed (or `force`); returns
  // false when nothing was drawn. `timed`: waits for the GPU (a 1-pixel read-back: glFinish does
  // not block in WebGL) so lastFrameMs is the frame's time, not its submission's.
  bool frame(int width, int height, bool force, bool timed) {
    if (!renderer_ || context_ <= 0) return false;
    emscripten_webgl_make_context_current(context_);
    advancePlayers();
    if (focusPath_) {
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - focusStart_).count();
      Camera c = focusPath_->at(std::min(t, focusPath_->duration()));
      nav_->setCamera(c.width == width && c.height == height ? c : c.scaled(double(height) / c.height, width, height));
      if (t >= focusPath_->duration()) focusPath_.reset();
      dirty_ = true;
    }
    resize(width, height);
    if (!force && !dirty_ && renderer_->converged()) return false;
    const auto t0 = std::chrono::steady_clock::now();
    try {
      renderer_->render(nav_->camera(), false, render::FrameMode::Progressive);
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, width, height);
      presenter_->blitFlipped(renderer_->colorTexture(), {width, height}, {width, height});
      if (timed) {
        unsigned char px[4];
        glReadPixels(0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, px);
      }
    } catch (const std::exception& e) {
      error_ = e.what();
      renderer_.reset();
      return false;
    }
    lastFrameMs_ = msSince(t0);
    renderedSinceMade_ = true;
    dirty_ = false;
    ++frames_;
    return true;
  }

  // {"converged", "arrived", "photos", "frames", "lastFrameMs", "sceneMs", "points", "chunks",
  //  "imagesLoaded", "depthMaps", "waiting", "pointsDrawn", "errors": [...]} (errors: photographs
  //  that failed to decode, and fatal ones).
  std::string status() const {
    json s = {{"converged", renderer_ ? renderer_->converged() : false},
              {"arrived", arrived_},
              {"photos", scene_ ? scene_->photos.size() : 0},
              {"frames", frames_},
              {"lastFrameMs", lastFrameMs_},
              {"focusing", bool(focusPath_)},
              {"sceneMs", sceneMs_},
              {"points", scene_ ? scene_->points.size() : 0},
              {"chunks", scene_ ? scene_->points.chunks.size() : 0},
              {"time", settings_.traffic.time},
              {"trafficPlaying", clock_.playing()},
              {"vehicles", vehiclesOnRoad()},
              {"timelinePlaying", player_.playing()},
              {"thenNow", thenNow_},
              {"orthophoto", orthophoto_ ? json{orthophoto_->width, orthophoto_->height} : json(nullptr)},
              {"errors", diag_.errors}};
    if (!error_.empty()) s["errors"].push_back(error_);
    if (renderer_) {
      const auto& st = renderer_->stats();
      s["imagesLoaded"] = st.imagesLoaded;
      s["depthMaps"] = st.depthMapsRendered;
      s["waiting"] = st.imagesWaiting;
      s["selected"] = renderer_->lastPlan().images.size();
      s["pointsDrawn"] = renderer_->settings().points.enabled ? st.pointsDrawn : 0;
    }
    return s.dump();
  }
  // The timeline (hv/viewer/timeline.h, as the desktop viewer's): {"first", "last" (the axis's days),
  // "firstDate", "lastDate", "firstYear", "yearsPerBin", "counts" (photographs per bar), "dated",
  // "undated", "undatedPhotos" (their indices: no date, or one that is not an ISO 8601 date)}.
  std::string timeline() const {
    json t = {{"first", axis_.first},
              {"last", axis_.last},
              {"firstDate", formatDay(axis_.first)},
              {"lastDate", formatDay(axis_.last)},
              {"firstYear", histogram_.firstYear},
              {"yearsPerBin", histogram_.yearsPerBin},
              {"counts", histogram_.counts},
              {"dated", dates_.dated.size()},
              {"undated", dates_.undated.size()},
              {"undatedPhotos", dates_.undated}};
    return t.dump();
  }
  // The time window at two slider positions (fractions of the axis, 0 <= a <= b <= 1), as the
  // desktop viewer's --timeline; writes the settings `from`/`to`. Returns "" or the error.
  std::string setTimeWindow(double a, double b) {
    if (!(a >= 0.0 && a <= b && b <= 1.0))
      return "time window: expected positions 0 <= from <= to <= 1, got " + std::to_string(a) + ", " +
             std::to_string(b);
    setWindow(DateInterval{axis_.dayAt(a), axis_.dayAt(b)});
    return "";
  }
  // No window: every photograph (the settings from/to empty).
  void clearTimeWindow() {
    player_.stop();
    setWindow(std::nullopt);
  }
  // {"open", "a", "b" (slider positions), "from", "to" (days as dates), "count" (dated photographs
  // in it), "inWindow": [per photograph: dated and overlapping it, or undated and not dated-only],
  // "datedOnly", "playing"}.
  std::string timeWindow() const {
    const DateInterval w = windowOnAxis(settings_.blend.window, axis_);
    json inWindow = json::array();
    for (const auto& d : dates_.when) inWindow.push_back(d ? overlaps(*d, w) : !settings_.blend.datedOnly);
    return json{{"open", !settings_.blend.window.has_value()},
                {"a", axis_.positionOf(w.first)},
                {"b", axis_.positionOf(w.last)},
                {"from", formatDay(w.first)},
                {"to", formatDay(w.last)},
                {"count", countInWindow(dates_, w)},
                {"inWindow", inWindow},
                {"datedOnly", settings_.blend.datedOnly},
                {"playing", player_.playing()}}
        .dump();
  }
  // Play walks the window forward at `yearsPerSecond` (TimelinePlayer: wall-clock time).
  void playTimeline(double yearsPerSecond, bool loop) {
    if (dates_.dated.empty()) return;
    play_.yearsPerSecond = yearsPerSecond > 0.0 ? yearsPerSecond : play_.yearsPerSecond;
    play_.loop = loop;
    DateInterval w = windowOnAxis(settings_.blend.window, axis_);
    player_.start(w, axis_, std::max<std::int64_t>(1, histogram_.binDays(0).last - histogram_.binDays(0).first + 1));
    setWindow(w);
  }
  void stopTimeline() { player_.stop(); }

  // The traffic (scene.json "traffic", exported as traffic.csv): {"vehicles", "begin", "end"};
  // vehicles 0 when the scene has none.
  std::string traffic() const {
    const std::size_t n = scene_ && scene_->traffic ? scene_->traffic->vehicles.size() : 0;
    return json{{"vehicles", n}, {"begin", clock_.begin()}, {"end", clock_.end()}}.dump();
  }
  // The traffic's clock (TrafficClock): the setting `time`, clamped to the trajectories' span.
  void setTrafficTime(double t) {
    clock_.seek(t);
    writeTrafficTime();
  }
  void playTraffic(bool on, double rate, bool loop) {
    if (rate > 0.0) trafficPlay_.rate = rate;
    trafficPlay_.loop = loop;
    if (on && !clock_.playing()) {
      clock_.seek(settings_.traffic.time);  // the settings panel may have moved it
      clock_.play();
    } else if (!on) {
      clock_.pause();
    }
  }
  // Vehicles on the road (between their first and last sample) at the current time.
  int vehiclesOnRoad() const {
    int n = 0;
    if (scene_ && scene_->traffic)
      for (const Trajectory& v : scene_->traffic->vehicles)
        n += sampleTrajectory(v, settings_.traffic.time).has_value();
    return n;
  }

  // The camera's pose as a link gives it (hv/viewer/view_state.h: "x,y,z,qw,qx,qy,qz,fov").
  std::string pose() const { return nav_ ? formatPose(poseOf(nav_->camera())) : std::string(); }
  std::string setPose(const std::string& text, int width, int height) {
    if (!nav_) return "no scene";
    try {
      nav_->setCamera(cameraAt(parsePose(text, "pose"), width, height, "web"));
      focusPath_.reset();
      dirty_ = true;
      return "";
    } catch (const std::exception& e) {
      return e.what();
    }
  }
  // The query of a link to this view: the pose, then every render setting that differs from
  // the page's defaults (the time window `from`/`to` and the traffic's `time` among them).
  std::string shareQuery() const {
    ViewState state;
    if (nav_) state.pose = poseOf(nav_->camera());
    render::RenderSettings defaults = webDefaults();
    defaults.points.enabled = pointsOnAtStart(settings_.points.budget);
    for (const render::Setting& st : render::settingsSchema()) {
      const std::string now = render::toText(settings_, st.name);
      if (now != render::toText(defaults, st.name)) state.params.emplace_back(st.name, now);
    }
    return encodeViewState(state);
  }
  // Then and now (hv/viewer/then_now.h, as the desktop viewer's): the view at photograph i's
  // camera fitted to the canvas, the photograph left out of the render (leave-one-out); the page
  // lays the photograph over the canvas. Returns {"image" (its path in the file system), "lo",
  // "hi" (its rectangle on the canvas, photoRectInWindow)} or {"error"}.
  std::string enterThenNow(int i, int width, int height) {
    if (!scene_ || i < 0 || size_t(i) >= scene_->photos.size())
      return json{{"error", "then and now: choose a photograph first (the list, N or P)"}}.dump();
    const Photo& p = scene_->photos[size_t(i)];
    focusPath_.reset();
    focused_ = i;
    thenNow_ = i;
    nav_->setMode(Mode::Fly);
    nav_->setCamera(photoInWindow(p.camera, width, height));
    renderer_->settings().blend.exclude = rendererSettings().blend.exclude;
    dirty_ = true;
    const PixelRect r = photoRectInWindow({p.camera.width, p.camera.height}, {width, height});
    return json{{"image", p.imagePath}, {"lo", {r.lo.x, r.lo.y}}, {"hi", {r.hi.x, r.hi.y}}}.dump();
  }
  void leaveThenNow() {
    if (thenNow_ < 0) return;
    thenNow_ = -1;
    if (renderer_) renderer_->settings().blend.exclude = rendererSettings().blend.exclude;
    dirty_ = true;
  }
  int thenNow() const { return thenNow_; }

  // The map (hv/viewer/map_overview.h, as the desktop viewer's; web/map.js draws it) in a canvas of
  // width x height pixels: {"hillshade": {"lo", "hi" (its box's north-west and south-east corners
  // in canvas pixels), "width", "height", "grey", "alpha" (row by row, north first)} or null,
  // "outlines" (x0, y0, x1, y1, ... segments), "footprints" (x, y triangles), "dots": [{"photo",
  // "id", "x", "y", "dx", "dy" (the viewing direction on the canvas, unit), "dated"}],
  // "undated": [photograph indices]}.
  std::string mapData(int width, int height) {
    if (!scene_) return "{}";
    const MapOverview& m = mapOverview_();
    const MapFrame f = fitMap(m.extent, width, height);
    auto px = [&](json& a, const glm::dvec2& p) {
      const glm::dvec2 q = f.toPixel(p);
      a.push_back(std::round(q.x * 100.0) / 100.0);
      a.push_back(std::round(q.y * 100.0) / 100.0);
    };
    json out = {{"hillshade", nullptr}};
    if (!m.shade.data.empty()) {
      json grey = json::array(), alpha = json::array();
      for (int y = 0; y < m.shade.height; ++y)
        for (int x = 0; x < m.shade.width; ++x)
          grey.push_back(m.shade.at(x, y, 0)), alpha.push_back(m.shade.at(x, y, 1));
      json lo = json::array(), hi = json::array();
      px(lo, {m.terrain.box.lo.x, m.terrain.box.hi.y});
      px(hi, {m.terrain.box.hi.x, m.terrain.box.lo.y});
      out["hillshade"] = {{"lo", lo}, {"hi", hi}, {"width", m.shade.width}, {"height", m.shade.height},
                          {"grey", grey}, {"alpha", alpha}};
    }
    json outlines = json::array(), footprints = json::array(), dots = json::array();
    for (const glm::dvec2& p : m.outlineSegments) px(outlines, p);
    for (const glm::dvec2& p : m.footprintTriangles) px(footprints, p);
    for (const MapDot& d : m.dots) {
      const glm::dvec2 q = f.toPixel(d.at), dir = pixelDirection(d.direction);
      dots.push_back({{"photo", d.photo}, {"id", scene_->photos[size_t(d.photo)].camera.id}, {"x", q.x}, {"y", q.y},
                      {"dx", dir.x}, {"dy", dir.y}, {"dated", d.dated}});
    }
    out["outlines"] = outlines;
    out["footprints"] = footprints;
    out["dots"] = dots;
    out["undated"] = dates_.undated;
    return out.dump();
  }
  // The map zoomed and panned (MapZoom, as the desktop viewer's map): the wheel by `factor` about
  // canvas pixel (x, y), a drag by (dx, dy) canvas pixels, back to the whole map. Each returns the
  // canvas pixels of the zoomed map from mapData's (those of the whole map): {"zoom", "tx", "ty"},
  // zoomed = zoom * whole + (tx, ty). mapView and mapClick are in the zoomed map's pixels.
  std::string mapZoomAt(double x, double y, double factor, int width, int height) {
    if (!scene_) return "{}";
    mapZoom_ = zoomAbout(mapOverview_().extent, width, height, mapZoom_, {x, y}, factor);
    return mapTransform_(width, height);
  }
  std::string mapPan(double dx, double dy, int width, int height) {
    if (!scene_) return "{}";
    mapZoom_ = panBy(mapOverview_().extent, width, height, mapZoom_, {dx, dy});
    return mapTransform_(width, height);
  }
  std::string mapWhole(int width, int height) {
    mapZoom_ = MapZoom{};
    return scene_ ? mapTransform_(width, height) : "{}";
  }
  // The view on that map: {"x", "y" (canvas pixels), "dx", "dy" (its heading, unit; 0 looking
  // straight down)}.
  std::string mapView(int width, int height) {
    if (!nav_) return "{}";
    const MapOverview& m = mapOverview_();
    const MapFrame f = zoomedMap(m.extent, width, height, mapZoom_);
    const MapView v = viewer::mapView(m, nav_->camera());
    const glm::dvec2 q = f.toPixel(v.at), dir = pixelDirection(v.direction);
    return json{{"x", q.x}, {"y", q.y}, {"dx", dir.x}, {"dy", dir.y}}.dump();
  }
  // A click at (x, y) on that map: a photograph's dot (within 6 pixels) starts focus + context on
  // it, elsewhere the view flies to the ground there, its heading kept, at its height above the
  // ground (at least eye height). Returns {"photo"} or {"ground": [x, y, z]}.
  std::string mapClick(double x, double y, int width, int height) {
    if (!nav_) return "{}";
    const MapOverview& m = mapOverview_();
    const MapClick click = clickMap(m, zoomedMap(m.extent, width, height, mapZoom_), {x, y}, 6.0);
    if (click.photo >= 0) {
      focusPhoto(click.photo);
      return json{{"photo", click.photo}}.dump();
    }
    leaveThenNow();
    const Camera cam = nav_->camera();
    const double above = glm::dot(cam.center - m.groundAt(m.toPlane(cam.center)), m.axes.up);
    const double over = std::max(nav_->settings().eyeHeight, above);
    FocusContextSettings s = focus_;
    s.holdSeconds = s.backSeconds = s.stepBack = 0.0;
    s.zoomOut = 1.0;
    s.levelHorizon = false;
    focusPath_ =
        std::make_unique<FocusContextPath>(cam, viewOverGround(cam, click.ground, m.axes.up, over), s, nullptr);
    focusStart_ = std::chrono::steady_clock::now();
    dirty_ = true;
    return json{{"ground", {click.ground.x, click.ground.y, click.ground.z}}}.dump();
  }
  // Pose mode (docs/pose.md, "In the browser"; web/pose.js): pairs of a pixel of photograph i and
  // the scene point under a click on the view (Renderer::pickViewPoint: the view's own depth, the
  // browser having no ray caster), the camera solved from them (hv/pose/pose_session.h, as the
  // desktop viewer's pose mode) and, as there, put into the scene: the renderer is made again with
  // it, so the photograph is projected from its solved camera. Leaving puts the scene's camera back
  // unless the solution was saved. Returns poseState() or {"error"}.
  std::string poseStart(int i, bool solveFocal) {
    if (!scene_ || i < 0 || size_t(i) >= scene_->photos.size())
      return json{{"error", "pose mode: choose a photograph first (the list, N or P)"}}.dump();
    if (poseSession_) poseLeave();
    leaveThenNow();
    posePhoto_ = i;
    poseOriginal_ = scene_->photos[size_t(i)].camera;
    poseSession_ = std::make_unique<pose::PoseSession>(poseOriginal_, solveFocal);
    poseApplied_ = poseSession_->solutionVersion();
    poseSaved_ = -1;
    return poseState();
  }
  // The scene point under canvas pixel (x, y) of the last frame: {"hit", "x", "y", "z"}.
  std::string pickView(double x, double y) {
    const std::optional<glm::dvec3> p = pickAt(x, y);
    if (!p) return json{{"hit", false}}.dump();
    return json{{"hit", true}, {"x", p->x}, {"y", p->y}, {"z", p->z}}.dump();
  }
  // A click on the photograph (its pixels, top-left-corner origin), then one on the view
  // (canvas pixels, picked): a pair. Each returns poseState(), its "message" saying what happened.
  std::string poseClickPhoto(double u, double v) {
    if (!poseSession_) return json{{"error", "pose mode is off"}}.dump();
    poseSession_->clickPhoto({u, v});
    return poseState();
  }
  std::string poseClickView(double x, double y) {
    if (!poseSession_) return json{{"error", "pose mode is off"}}.dump();
    poseSession_->clickScene(pickAt(x, y));
    return poseApply();
  }
  // A pair given whole (a pixel of the photograph and a world point, scene frame).
  std::string poseAddPair(double u, double v, double x, double y, double z) {
    if (!poseSession_) return json{{"error", "pose mode is off"}}.dump();
    if (poseSession_->clickPhoto({u, v})) poseSession_->clickScene(glm::dvec3(x, y, z));
    return poseApply();
  }
  std::string poseMovePair(int index, double u, double v) {
    if (!poseSession_) return json{{"error", "pose mode is off"}}.dump();
    poseSession_->movePair(index, {u, v});
    return poseApply();
  }
  std::string poseRemovePair(int index) {
    if (!poseSession_) return json{{"error", "pose mode is off"}}.dump();
    poseSession_->removePair(index);
    return poseApply();
  }
  std::string poseSetSolveFocal(bool on) {
    if (!poseSession_) return json{{"error", "pose mode is off"}}.dump();
    poseSession_->setSolveFocal(on);
    return poseApply();
  }
  // {"on", "photo", "id", "image", "width", "height", "step" ("photo" | "view"), "pending" ([u, v] |
  // null), "needed", "solveFocal", "pairs": [{"u", "v", "x", "y", "z", and once solved "pu", "pv"
  // (where the solved camera puts the point), "residual" (pixels), "inlier"}], "solved", "camera"
  // (the solved camera, cameras.json schema; "original": the scene's before pose mode), "rms", "inliers",
  // "centerSigma", "rotationSigmaDeg", "notes", "saved", "message"}.
  std::string poseState() const {
    if (!poseSession_) return json{{"on", false}}.dump();
    const pose::PoseSession& s = *poseSession_;
    const Photo& photo = scene_->photos[size_t(posePhoto_)];
    json pairs = json::array();
    const std::vector<pose::ResidualLine> lines = s.residualLines();
    for (size_t k = 0; k < s.pairs().size(); ++k) {
      const pose::PosePair& p = s.pairs()[k];
      json j = {{"u", p.pixel.x}, {"v", p.pixel.y}, {"x", p.world.x}, {"y", p.world.y}, {"z", p.world.z}};
      if (k < lines.size())
        j.update({{"pu", lines[k].projected.x},
                  {"pv", lines[k].projected.y},
                  {"residual", lines[k].pixels},
                  {"inlier", lines[k].inlier}});
      pairs.push_back(j);
    }
    json out = {{"on", true},
                {"photo", posePhoto_},
                {"id", poseOriginal_.id},
                {"image", photo.imagePath},
                {"width", poseOriginal_.width},
                {"height", poseOriginal_.height},
                {"step", s.step() == pose::PoseSession::Step::Photo ? "photo" : "view"},
                {"pending", s.pending() ? json{s.pending()->x, s.pending()->y} : json(nullptr)},
                {"needed", s.pairsNeeded()},
                {"solveFocal", s.solveFocal()},
                {"pairs", pairs},
                {"solved", s.solution().has_value()},
                {"saved", s.solution() && poseSaved_ == s.solutionVersion()},
                {"message", s.message()}};
    {
      Photo o = photo;
      o.camera = poseOriginal_;
      out["original"] = json::parse(cameraJson({o}, "/scene"))["cameras"][0];
    }
    if (const auto& r = s.solution()) {
      Photo p = photo;
      p.camera = r->camera;
      out["camera"] = json::parse(cameraJson({p}, "/scene"))["cameras"][0];
      out["rms"] = r->rmsPixels;
      out["inliers"] = r->inlierCount;
      out["centerSigma"] = {r->centerSigma.x, r->centerSigma.y, r->centerSigma.z};
      out["rotationSigmaDeg"] = r->rotationSigmaDegrees;
      out["notes"] = r->notes;
    }
    return out.dump();
  }
  // Where the photograph's camera before pose mode puts world point (x, y, z): {"u", "v", "inFront"}
  // (its pixels, distorted). For scripts and the test: a known camera's pixels of picked points.
  std::string poseProjectOriginal(double x, double y, double z) const {
    if (!poseSession_) return json{{"error", "pose mode is off"}}.dump();
    const Projection p = poseOriginal_.project({x, y, z});
    return json{{"u", p.pxDistorted.x}, {"v", p.pxDistorted.y}, {"inFront", p.inFront}}.dump();
  }
  // The view from the solved camera with the photograph over it (then and now at its solved
  // camera, the page's opacity slider fading it): enterThenNow's answer.
  std::string poseLookFromSolved(int width, int height) {
    if (!poseSession_ || !poseSession_->solution())
      return json{{"error", "pose mode: nothing solved yet (" +
                                std::to_string(poseSession_ ? poseSession_->pairsNeeded() : 4) + " pairs or more)"}}
          .dump();
    return enterThenNow(posePhoto_, width, height);
  }
  // The solved camera as a native cameras.json (the photograph's image path relative to the
  // export), to download; marks the solution saved (kept on leaving). {"error"} before a solution.
  std::string poseSave() {
    if (!poseSession_ || !poseSession_->solution()) return json{{"error", "pose mode: nothing solved to save"}}.dump();
    Photo p = scene_->photos[size_t(posePhoto_)];
    p.camera = poseSession_->solution()->camera;
    poseSaved_ = poseSession_->solutionVersion();
    return cameraJson({p}, "/scene");
  }
  void poseLeave() {
    if (!poseSession_) return;
    const bool restore = poseSession_->solution() && poseSaved_ != poseSession_->solutionVersion();
    const int photo = posePhoto_;
    poseSession_.reset();
    posePhoto_ = -1;
    if (restore) setPhotoCamera(photo, poseOriginal_);
  }
  bool poseOn() const { return poseSession_ != nullptr; }

  // The current camera (cameras.json schema), e.g. to share a view.
  std::string camera() const {
    if (!nav_) return "{}";
    Photo p;
    p.camera = nav_->camera();
    return cameraJson({p}, "");
  }

 private:
  // The map, made on first use (the terrain's hillshade is rasterised then).
  const MapOverview& mapOverview_() {
    if (!map_) {
      std::vector<bool> dated;
      for (const auto& d : dates_.when) dated.push_back(d.has_value());
      map_ = std::make_unique<MapOverview>(mapOverview(*scene_, dated, 192));
    }
    return *map_;
  }

  std::string mapTransform_(int width, int height) {
    const PlaneBox& box = mapOverview_().extent;
    const MapFrame whole = fitMap(box, width, height), zoomed = zoomedMap(box, width, height, mapZoom_);
    // zoomed.offset + ppu q = zoom (whole.offset + ppu0 q) + t, ppu = zoom ppu0.
    const glm::dvec2 t = zoomed.offset - mapZoom_.zoom * whole.offset;
    return json{{"zoom", mapZoom_.zoom}, {"tx", t.x}, {"ty", t.y}}.dump();
  }

  // The time window into the settings and the renderer's (live: BlendSettings::window).
  void setWindow(const std::optional<DateInterval>& window) {
    settings_.blend.window = window;
    if (renderer_) renderer_->settings().blend.window = window;
    dirty_ = true;
  }
  void writeTrafficTime() {
    settings_.traffic.time = clock_.time();
    if (renderer_) renderer_->settings().traffic.time = clock_.time();
    dirty_ = true;
  }
  // Play: the timeline's window and the traffic's clock advance with the wall-clock time since
  // the previous frame (at most a second: a hidden tab gets no frames).
  void advancePlayers() {
    const auto now = std::chrono::steady_clock::now();
    const double seconds = std::min(1.0, std::chrono::duration<double>(now - lastTick_).count());
    lastTick_ = now;
    if (player_.playing()) {
      DateInterval w = windowOnAxis(settings_.blend.window, axis_);
      if (player_.step(w, axis_, seconds, play_)) setWindow(w);
    }
    if (clock_.step(seconds, trafficPlay_)) writeTrafficTime();
  }

  // settings_ as the renderer takes them here: no threads in the browser, the colour presented
  // from the GPU, and the photographs that have not arrived left out.
  render::RenderSettings rendererSettings() const {
    render::RenderSettings s = settings_;
    s.decodeThreads = 0;
    s.geometryThreads = 0;
    s.readBackColour = false;
    for (size_t i = 0; scene_ && i < scene_->photos.size(); ++i)
      if (!arrivedPhoto_[i] || int(i) == thenNow_) s.blend.exclude.push_back(scene_->photos[i].camera.id);
    return s;
  }
  // The browser's defaults where they differ from the native ones: smaller slices and budgets
  // (a tab's memory); decoding on the render thread.
  static render::RenderSettings webDefaults() {
    render::RenderSettings s;
    s.maxSliceSize = 1024;
    s.memoryBudgetBytes = std::size_t(384) << 20;
    s.decodeMemoryBytes = std::size_t(96) << 20;
    s.decodeThreads = 0;
    s.geometryThreads = 0;
    return s;
  }

  std::string setCameraFitted(const Camera& c, int width, int height) {
    Camera fitted;
    try {
      fitted = c.resized(width, height);  // the exact camera (render's picture) at the same aspect
    } catch (const std::invalid_argument&) {
      fitted = photoInWindow(c, width, height);
    }
    nav_->setCamera(fitted);
    focusPath_.reset();
    dirty_ = true;
    return "";
  }

  // Pose mode: a new solution (or none any more) goes into the scene, as the desktop viewer's
  // (setPhotoCamera): the renderer, which holds the scene's cameras, is made again.
  std::string poseApply() {
    if (poseSession_ && poseSession_->solutionVersion() != poseApplied_) {
      poseApplied_ = poseSession_->solutionVersion();
      setPhotoCamera(posePhoto_, poseSession_->solution() ? poseSession_->solution()->camera : poseOriginal_);
    }
    return poseState();
  }
  // The scene point under canvas pixel (x, y), from the view depth of the frame on the canvas: a
  // renderer made since (a new solution) draws its first frame now.
  std::optional<glm::dvec3> pickAt(double x, double y) {
    if (!renderer_ || !nav_ || context_ <= 0) return std::nullopt;
    const Camera& c = nav_->camera();
    if (!renderedSinceMade_ && !frame(c.width, c.height, true, false)) return std::nullopt;
    emscripten_webgl_make_context_current(context_);
    return renderer_->pickViewPoint({x, y});
  }
  void setPhotoCamera(int photo, const Camera& camera) {
    leaveThenNow();
    scene_->photos[size_t(photo)].camera = camera;
    rebuildRenderer();
    dirty_ = true;
  }
  // A new renderer with the page's settings (a setting that does not apply live, a photograph's
  // new camera), the debug view's photograph kept; the old one is released first (its GL objects).
  void rebuildRenderer() {
    render::RenderSettings next = rendererSettings();
    next.debug.photo = renderer_->settings().debug.photo;
    renderer_.reset();
    renderer_ = std::make_unique<render::Renderer>(*scene_, next, diag_);
    if (orthophoto_) renderer_->setOrthophoto(orthophoto_);
    renderedSinceMade_ = false;
  }

  EMSCRIPTEN_WEBGL_CONTEXT_HANDLE context_ = 0;
  std::string error_;
  Diagnostics diag_;
  std::unique_ptr<Scene> scene_;
  std::shared_ptr<const Orthophoto> orthophoto_;  // the manifest's (hv/io/web_orthophoto.h); null: none
  render::RenderSettings settings_ = webDefaults();  // as set by the page (exclusions apart)
  bool pointsSet_ = false;                            // the page set "points" before load
  std::vector<bool> arrivedPhoto_;
  std::unique_ptr<render::Renderer> renderer_;
  std::unique_ptr<gpu::Presenter> presenter_;
  std::unique_ptr<Navigator> nav_;
  std::unique_ptr<FocusContextPath> focusPath_;
  std::chrono::steady_clock::time_point focusStart_;
  FocusContextSettings focus_;
  std::vector<int> order_;
  int focused_ = -1;
  int arrived_ = 0;
  int frames_ = 0;
  double lastFrameMs_ = 0.0;
  double sceneMs_ = 0.0;
  bool dirty_ = true;
  int thenNow_ = -1;  // the photograph of then and now, -1: off
  std::unique_ptr<pose::PoseSession> poseSession_;
  int posePhoto_ = -1;
  Camera poseOriginal_;             // the photograph's camera before pose mode
  int poseApplied_ = 0;             // the solution version in the scene
  int poseSaved_ = -1;              // the solution version saved, -1: none
  bool renderedSinceMade_ = false;  // the renderer has drawn the canvas's frame (picking reads it)
  PhotoDates dates_;
  DateHistogram histogram_;
  TimelineAxis axis_;
  PlaySettings play_;
  TimelinePlayer player_;
  TrafficClock clock_;
  TrafficPlaySettings trafficPlay_;
  std::unique_ptr<MapOverview> map_;
  MapZoom mapZoom_;
  std::chrono::steady_clock::time_point lastTick_ = std::chrono::steady_clock::now();
};

// "debug", "info" (the default), "warn", "error" or "off": what hv::log prints to the console.
void setLogLevel(const std::string& level) {
  log::setLevel(level == "debug"  ? log::Level::Debug
                : level == "warn"  ? log::Level::Warn
                : level == "error" ? log::Level::Error
                : level == "off"   ? log::Level::Off
                                   : log::Level::Info);
}

EMSCRIPTEN_BINDINGS(histoview) {
  emscripten::function("setLogLevel", &setLogLevel);
  emscripten::class_<WebViewer>("WebViewer")
      .constructor<std::string>()
      .function("error", &WebViewer::error)
      .function("glInfo", &WebViewer::glInfo)
      .function("load", &WebViewer::load)
      .function("photos", &WebViewer::photos)
      .function("fetchOrder", &WebViewer::fetchOrder)
      .function("photoArrived", &WebViewer::photoArrived)
      .function("arrived", &WebViewer::arrived)
      .function("iiifPlan", &WebViewer::iiifPlan)
      .function("remoteFilePath", &WebViewer::remoteFilePath)
      .function("photoFullArrived", &WebViewer::photoFullArrived)
      .function("setViewFromFile", &WebViewer::setViewFromFile)
      .function("overview", &WebViewer::overview)
      .function("move", &WebViewer::move)
      .function("setSpeed", &WebViewer::setSpeed)
      .function("speed", &WebViewer::speed)
      .function("focusPhoto", &WebViewer::focusPhoto)
      .function("stepPhoto", &WebViewer::stepPhoto)
      .function("focused", &WebViewer::focused)
      .function("setStepBack", &WebViewer::setStepBack)
      .function("hasPoints", &WebViewer::hasPoints)
      .function("setSetting", &WebViewer::setSetting)
      .function("settingsSchema", &WebViewer::settingsSchema)
      .function("frame", &WebViewer::frame)
      .function("status", &WebViewer::status)
      .function("camera", &WebViewer::camera)
      .function("timeline", &WebViewer::timeline)
      .function("setTimeWindow", &WebViewer::setTimeWindow)
      .function("clearTimeWindow", &WebViewer::clearTimeWindow)
      .function("timeWindow", &WebViewer::timeWindow)
      .function("playTimeline", &WebViewer::playTimeline)
      .function("stopTimeline", &WebViewer::stopTimeline)
      .function("traffic", &WebViewer::traffic)
      .function("setTrafficTime", &WebViewer::setTrafficTime)
      .function("playTraffic", &WebViewer::playTraffic)
      .function("vehiclesOnRoad", &WebViewer::vehiclesOnRoad)
      .function("pose", &WebViewer::pose)
      .function("setPose", &WebViewer::setPose)
      .function("shareQuery", &WebViewer::shareQuery)
      .function("enterThenNow", &WebViewer::enterThenNow)
      .function("leaveThenNow", &WebViewer::leaveThenNow)
      .function("thenNow", &WebViewer::thenNow)
      .function("mapData", &WebViewer::mapData)
      .function("mapView", &WebViewer::mapView)
      .function("mapClick", &WebViewer::mapClick)
      .function("pickView", &WebViewer::pickView)
      .function("poseStart", &WebViewer::poseStart)
      .function("poseClickPhoto", &WebViewer::poseClickPhoto)
      .function("poseClickView", &WebViewer::poseClickView)
      .function("poseAddPair", &WebViewer::poseAddPair)
      .function("poseMovePair", &WebViewer::poseMovePair)
      .function("poseRemovePair", &WebViewer::poseRemovePair)
      .function("poseSetSolveFocal", &WebViewer::poseSetSolveFocal)
      .function("poseState", &WebViewer::poseState)
      .function("poseProjectOriginal", &WebViewer::poseProjectOriginal)
      .function("poseLookFromSolved", &WebViewer::poseLookFromSolved)
      .function("poseSave", &WebViewer::poseSave)
      .function("poseLeave", &WebViewer::poseLeave)
      .function("poseOn", &WebViewer::poseOn)
      .function("mapZoomAt", &WebViewer::mapZoomAt)
      .function("mapPan", &WebViewer::mapPan)
      .function("mapWhole", &WebViewer::mapWhole);
}

}  // namespace hv::web
