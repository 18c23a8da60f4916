// The desktop viewer's loop and control panel (hv/viewer/viewer.h). Platform code (window, UI
// backends) is glfw_window.cpp; navigation maths is hv/viewer/navigation.h; rendering is the
// shared hv::render::Renderer in progressive frames.
#include "hv/viewer/desktop/viewer.h"

#include "hv/gpu/gl.h"
#include "hv/gpu/platform/glfw/glfw_window.h"
#include "hv/gpu/present.h"
#include "hv/image/image.h"
#include "hv/image/native/png_write.h"
#include "hv/io/camera_path_json.h"
#include "hv/scene/native/raycast.h"
#include "hv/scene/scene_scale.h"
#include "hv/session/make_renderer.h"
#include "hv/viewer/desktop/debug_panel.h"
#include "hv/viewer/desktop/map_panel.h"
#include "hv/viewer/desktop/pose_panel.h"
#include "hv/viewer/desktop/settings_panel.h"
#include "hv/viewer/desktop/sources_panel.h"
#include "hv/viewer/desktop/timeline_panel.h"
#include "hv/viewer/desktop/traffic_panel.h"
#include "hv/viewer/key_events.h"
#include "hv/viewer/navigation.h"
#include "hv/viewer/then_now.h"

#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>
#include <utility>

namespace hv::viewer {

bool available() { return true; }

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t0) { return std::chrono::duration<double, std::milli>(Clock::now() - t0).count(); }

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// A camera at `size` keeping the vertical field of view and the principal point's offset from the
// centre (the window was resized).
Camera reframe(const Camera& c, glm::ivec2 size) {
  if (c.width == size.x && c.height == size.y) return c;
  Camera r = c;
  const double s = double(size.y) / c.height;
  r.width = size.x;
  r.height = size.y;
  r.focal = c.focal * s;
  r.principal = glm::dvec2(size) / 2.0 + (c.principal - glm::dvec2(c.width, c.height) / 2.0) * s;
  r.skew = c.skew * s;
  r.distortion.reset();
  return r;
}

// Everything the panel edits that the renderer reads at construction (changing it recreates the
// renderer) or per frame.
struct PanelState {
  char search[128] = "";
  char screenshotName[256] = "histoview-screenshot.png";
  char pathName[256] = "histoview-path.json";
  bool screenshotWithUi = false;
  std::string message;
};

// Then and now (hv/viewer/then_now.h): the photograph over the render of the scene without it.
struct ThenNowState {
  bool on = false;
  int photo = -1;
  bool excluded = false;  // its id was added to the exclusions by this mode (and is removed after)
  ThenNowSettings settings;
  Image8 image;               // the photograph as decoded
  gpu::ImageTexture texture;  // it, at the size it covers in the window
  glm::ivec2 textureSize{0};
};

class Viewer {
 public:
  explicit Viewer(const ViewerOptions& o) : o_(o) {}

  int run() {
    Diagnostics diag;
    const glm::ivec2 size = app::parseSize(o_.view.size);
    // Everything that can be checked before the window opens and the scene loads.
    app::renderSettings(o_.view);
    vsync_ = !(o_.redraw || o_.printFrameTimes);
    session_ = app::openSession(o_.view, diag, [&] {
      auto w = std::make_unique<GlfwWindow>(size.x, size.y, "histoview", vsync_);
      window_ = w.get();
      window_->setKeyHandler([this](int key, bool down) {
        if (key < 0) return keys_.releaseAll();
        keys_.event(key, down);
      });
      return w;
    });
    for (const auto& e : diag.errors) std::cerr << "error: " << e << "\n";
    renderer_ = session_->renderer.get();
    renderer_->settings().readBackColour = false;
    const Scene& scene = session_->scene;
    app::applyDebugOption(o_.view.debug, scene, renderer_->settings().debug);
    std::cout << "viewer: " << scene.photos.size() << " photographs, " << window_->description() << "\n";

    Mesh all = scene.terrain;
    all.append(scene.buildings);
    all.append(scene.mesh);
    if (!all.empty()) caster_ = std::make_unique<RayCaster>(all);
    nav_ = std::make_unique<Navigator>(scene.up, caster_.get());
    const SceneScale scale = sceneScale(scene);
    for (const std::string& w : scale.warnings) std::cerr << "warning: " << scene.path << ": " << w << "\n";
    const ScaleDefaults defaults = scaleDefaults(scale.scale);
    nav_->settings().speed = defaults.speed;
    focusSettings_.stepBack = defaults.stepBack;
    focusSettings_.up = scene.up;
    std::cout << "viewer: scale " << scale.scale << " (" << scale.source << "): speed " << defaults.speed
              << "/s, step back " << defaults.stepBack << "\n";
    std::vector<glm::dvec3> centres;
    for (const auto& p : scene.photos) centres.push_back(p.camera.center);
    order_ = streetOrder(centres);
    showPanel_ = !o_.hidePanel;

    timeline_ = std::make_unique<TimelinePanel>(scene);
    render::RenderSettings& rs = renderer_->settings();
    if (!o_.timeline.empty()) {
      rs.blend.window = timeline_->windowAtPositions(o_.timeline);
      std::cout << "viewer: timeline " << timeline_->describe(*rs.blend.window) << "\n";
    }
    if (o_.playYearsPerSecond > 0.0) {
      timeline_->play().yearsPerSecond = o_.playYearsPerSecond;
      timeline_->startPlay(rs);
    }
    traffic_ = std::make_unique<TrafficPanel>(scene, rs);
    std::vector<bool> dated;
    for (const auto& d : timeline_->dates().when) dated.push_back(d.has_value());
    map_ = std::make_unique<MapPanel>(scene, dated, session_->orthophoto);
    if (o_.map) map_->toggle(), map_->printDots(true);
    if (o_.trafficRate > 0.0 && traffic_->present()) traffic_->play().rate = o_.trafficRate, traffic_->toggle(rs);

    nav_->setCamera(startCamera(window_->framebufferSize()));
    if (o_.walk) nav_->setMode(Mode::Walk);
    if (o_.thenNow || o_.thenNowOpacity >= 0.0 || o_.thenNowSwipe >= 0.0) {
      if (focused_ < 0)
        throw std::invalid_argument(
            "--then-now: --camera must name a photograph (then and now is seen from its camera)");
      if (o_.thenNowOpacity >= 0.0) thenNow_.settings.opacity = o_.thenNowOpacity;
      if (o_.thenNowSwipe >= 0.0) thenNow_.settings = {ThenNowMode::Swipe, 1.0, o_.thenNowSwipe};
      enterThenNow(focused_, false);
    }
    pose_ = std::make_unique<PosePanel>(std::vector<std::string>{o_.view.scenePath, o_.view.viewsPath});
    presenter_ = std::make_unique<gpu::Presenter>();
    return loop();
  }

 private:
  Camera startCamera(glm::ivec2 fb) {
    const Scene& scene = session_->scene;
    if (!o_.camera.empty()) {
      const Camera* found = nullptr;
      for (const auto& v : session_->views)
        if (v.camera.id == o_.camera) found = &v.camera;
      for (size_t i = 0; !found && i < scene.photos.size(); ++i)
        if (scene.photos[i].camera.id == o_.camera) {
          found = &scene.photos[i].camera;
          focused_ = int(i);
          if (renderer_->settings().debug.photo < 0) renderer_->settings().debug.photo = focused_;
        }
      if (!found)
        throw std::invalid_argument("--camera: no view (--views) or photograph has the id '" + o_.camera + "'");
      // The exact camera when its aspect ratio is the window's (so the picture is `render`'s),
      // else letterboxed into the window.
      try {
        return found->resized(fb.x, fb.y);
      } catch (const std::invalid_argument&) {
        return photoInWindow(*found, fb.x, fb.y);
      }
    }
    // An overview: from the south-west, above the scene, looking at its centre.
    const UpFrame f = upFrame(scene.up);
    const Aabb b = scene.bounds();
    const double extent = std::max(1.0, std::max(b.size().x, b.size().y));
    const glm::dvec3 centre = b.center();
    const glm::dvec3 eye = centre - (0.55 * f.north + 0.25 * f.east) * extent + 0.35 * extent * f.up;
    const double focal = fb.y / 2.0 / std::tan(30.0 * M_PI / 180.0);
    return lookAtCamera("viewer", eye, centre, fb.x, fb.y, focal, f.up);
  }

  NavigationInput readInput(double dt) {
    NavigationInput in;
    in.dt = dt;
    const ImGuiIO& io = ImGui::GetIO();
    if (!io.WantCaptureKeyboard) {
      auto down = [&](int key) { return keys_.held(key) ? 1.0 : 0.0; };
      in.move.x = down(GLFW_KEY_D) + down(GLFW_KEY_RIGHT) - down(GLFW_KEY_A) - down(GLFW_KEY_LEFT);
      in.move.y = down(GLFW_KEY_W) + down(GLFW_KEY_UP) - down(GLFW_KEY_S) - down(GLFW_KEY_DOWN);
      in.move.z = down(GLFW_KEY_E) - down(GLFW_KEY_Q);
      in.fast = down(GLFW_KEY_LEFT_SHIFT) + down(GLFW_KEY_RIGHT_SHIFT) > 0.0;
    }
    if (!io.WantCaptureMouse) {
      if (ImGui::IsMouseDown(ImGuiMouseButton_Left) || ImGui::IsMouseDown(ImGuiMouseButton_Right))
        in.lookPixels = {io.MouseDelta.x, io.MouseDelta.y};
      if (io.MouseWheel != 0.0f)
        nav_->settings().speed = std::clamp(nav_->settings().speed * std::pow(1.25, double(io.MouseWheel)), 0.05, 1e4);
    }
    return in;
  }

  void handleKeys() {
    // Presses since the last frame, however short (key_events.h); none while a text field has
    // the keyboard.
    if (ImGui::GetIO().WantCaptureKeyboard) return;
    if (keys_.pressed(GLFW_KEY_ESCAPE)) window_->requestClose();
    if (keys_.pressed(GLFW_KEY_TAB))
      nav_->setMode(nav_->mode() == Mode::Fly ? Mode::Walk : Mode::Fly);
    if (keys_.pressed(GLFW_KEY_H)) showPanel_ = !showPanel_;
    render::DebugSettings& debug = renderer_->settings().debug;
    if (keys_.pressed(GLFW_KEY_C)) {
      debug.view = debug.view == render::DebugView::Counts ? render::DebugView::None : render::DebugView::Counts;
      settingsChanged_ = true;
    }
    if (keys_.pressed(GLFW_KEY_F)) debug.frusta = !debug.frusta, settingsChanged_ = true;
    if (keys_.pressed(GLFW_KEY_N) || keys_.pressed(GLFW_KEY_PAGE_DOWN)) stepPhoto(+1);
    if (keys_.pressed(GLFW_KEY_P) || keys_.pressed(GLFW_KEY_PAGE_UP)) stepPhoto(-1);
    screenshotsRequested_ += keys_.presses(GLFW_KEY_F2);  // every tap a picture, several in one frame too
    if (keys_.pressed(GLFW_KEY_R)) toggleRecording();
    if (keys_.pressed(GLFW_KEY_T)) {
      if (thenNow_.on)
        leaveThenNow();
      else if (focused_ >= 0)
        enterThenNow(focused_, true);
      else
        panel_.message = "then and now: choose a photograph first (the list, N or P)";
    }
    if (keys_.pressed(GLFW_KEY_SPACE)) togglePlay();
    if (keys_.pressed(GLFW_KEY_O)) togglePose();
    if (keys_.pressed(GLFW_KEY_Y)) traffic_->toggle(renderer_->settings());
    if (keys_.pressed(GLFW_KEY_M)) map_->toggle();
  }

  // Pose mode (pose_panel.h) at the chosen photograph; its solved camera replaces the
  // photograph's in the renderer while the mode lasts, and after it once saved.
  void togglePose() {
    if (pose_->on()) return leavePose();
    if (focused_ < 0) return void(panel_.message = "pose mode: choose a photograph first (the list, N or P)");
    if (!pose_->enter(session_->scene, focused_)) panel_.message = pose_->message();
  }
  void leavePose() {
    const int photo = pose_->photo();
    const bool restore = pose_->session() && pose_->session()->solution() && !pose_->saved();
    pose_->leave();
    if (restore) setPhotoCamera(photo, pose_->original());
  }
  void setPhotoCamera(int photo, const Camera& camera) {
    leaveThenNow();
    session_->scene.photos[size_t(photo)].camera = camera;
    const render::RenderSettings s = renderer_->settings();
    rebuildRenderer(s);
  }
  void poseFrame() {
    if (!o_.poseScript.empty()) {
      const Camera view = nav_->camera();  // the script's clicks are in this view, the first one
      for (const std::string& e :
           pose_->runScript(std::exchange(o_.poseScript, ""), session_->scene, view, caster_.get()))
        std::cerr << "error: " << e << "\n", poseScriptFailed_ = true;
      if (pose_->on() && pose_->session()->solution())
        setPhotoCamera(pose_->photo(), pose_->session()->solution()->camera);
    }
    if (!pose_->on()) return;
    const ImGuiIO& io = ImGui::GetIO();
    if (!io.WantCaptureMouse && ImGui::IsMouseReleased(ImGuiMouseButton_Left) && io.MouseDragMaxDistanceSqr[0] < 9.0f)
      pose_->clickView(nav_->camera(),
                       {io.MousePos.x * io.DisplayFramebufferScale.x, io.MousePos.y * io.DisplayFramebufferScale.y},
                       caster_.get());
    const int photo = pose_->photo();
    const PosePanel::Result r = pose_->draw(session_->scene, thenNow_.settings.opacity);
    if (r.cameraChanged)
      setPhotoCamera(photo, pose_->session()->solution() ? pose_->session()->solution()->camera : pose_->original());
    if (r.lookFromSolved) thenNow_.settings.mode = ThenNowMode::Opacity, enterThenNow(photo, true);
    if (r.leave) leavePose();
  }

  void togglePlay() {
    render::RenderSettings& rs = renderer_->settings();
    if (timeline_->dates().dated.empty()) return;
    if (timeline_->player().playing()) return timeline_->player().stop();
    timeline_->startPlay(rs);
    settingsChanged_ = true;
  }

  // Then and now at photograph `photo`: the view at its camera (flown to when `fly`), the
  // photograph left out of the render (leave-one-out) and drawn over it.
  void enterThenNow(int photo, bool fly) {
    if (thenNow_.on) leaveThenNow();
    const Photo& p = session_->scene.photos[size_t(photo)];
    try {
      thenNow_.image = readImage(p.imagePath, 3);
    } catch (const std::exception& e) {
      panel_.message = std::string("then and now: ") + e.what();
      std::cerr << "error: " << panel_.message << "\n";
      return;
    }
    thenNow_.on = true;
    thenNow_.photo = photo;
    thenNow_.textureSize = glm::ivec2(0);
    std::vector<std::string>& exclude = renderer_->settings().blend.exclude;
    thenNow_.excluded = std::find(exclude.begin(), exclude.end(), p.camera.id) == exclude.end();
    if (thenNow_.excluded) exclude.push_back(p.camera.id);
    settingsChanged_ = true;
    focused_ = photo;
    renderer_->settings().debug.photo = photo;
    if (fly) {
      // To the photograph's camera and no further: no step back, no zoom out, its roll kept, so
      // the photograph lies exactly over the view.
      FocusContextSettings s = focusSettings_;
      s.holdSeconds = s.backSeconds = 0.0;
      s.stepBack = 0.0;
      s.zoomOut = 1.0;
      s.levelHorizon = false;
      focusPath_ = std::make_unique<FocusContextPath>(nav_->camera(), p.camera, s, caster_.get());
      focusStart_ = Clock::now();
      nav_->setMode(Mode::Fly);
    }
  }

  void leaveThenNow() {
    if (!thenNow_.on) return;
    std::vector<std::string>& exclude = renderer_->settings().blend.exclude;
    const std::string& id = session_->scene.photos[size_t(thenNow_.photo)].camera.id;
    if (thenNow_.excluded) exclude.erase(std::remove(exclude.begin(), exclude.end(), id), exclude.end());
    thenNow_.on = false;
    thenNow_.excluded = false;
    settingsChanged_ = true;
  }

  // The photograph over the picture, as a textured quad in the UI's background layer (drawn
  // under the panel); compositeThenNow (then_now.h) is its CPU reference.
  void drawThenNow(glm::ivec2 fb) {
    const Image8& img = thenNow_.image;
    const glm::ivec2 photoSize(img.width, img.height);
    const std::optional<OverlayQuad> q = thenNowQuad(photoSize, fb, thenNow_.settings);
    if (!q) return;
    // The texture at the size the photograph covers (1:1 when the window is the photograph's
    // size), resampled on the CPU rather than minified by GL without mipmaps.
    const PixelRect rect = photoRectInWindow(photoSize, fb);
    const glm::ivec2 want(std::max(1L, std::lround(rect.hi.x - rect.lo.x)),
                          std::max(1L, std::lround(rect.hi.y - rect.lo.y)));
    if (want != thenNow_.textureSize) {
      thenNow_.texture.upload(want == photoSize ? img : resizeImage(img, want.x, want.y));
      thenNow_.textureSize = want;
    }
    const ImVec2 scale = ImGui::GetIO().DisplayFramebufferScale;
    auto at = [&](glm::dvec2 px) { return ImVec2(float(px.x) / scale.x, float(px.y) / scale.y); };
    ImGui::GetBackgroundDrawList()->AddImage(
        reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(thenNow_.texture.id())), at(q->window.lo),
        at(q->window.hi), ImVec2(float(q->uv.lo.x), float(q->uv.lo.y)), ImVec2(float(q->uv.hi.x), float(q->uv.hi.y)),
        IM_COL32(255, 255, 255, int(std::lround(q->alpha * 255.0))));
  }

  void stepPhoto(int steps) {
    const std::vector<glm::dvec3> centres = photoCentres();
    const int current = focused_ >= 0 ? focused_ : nearestCentre(centres, nav_->camera().center);
    const int next = focused_ >= 0 ? stepAlong(order_, current, steps) : current;
    if (next >= 0) focusOn(next);
  }

  std::vector<glm::dvec3> photoCentres() const {
    std::vector<glm::dvec3> c;
    for (const auto& p : session_->scene.photos) c.push_back(p.camera.center);
    return c;
  }

  void focusOn(int photo) {
    if (thenNow_.on) return enterThenNow(photo, true);  // then and now goes on at the next photograph
    focused_ = photo;
    renderer_->settings().debug.photo = photo;  // the weight and depth-map views show the chosen one
    settingsChanged_ = true;
    focusPath_ = std::make_unique<FocusContextPath>(nav_->camera(), session_->scene.photos[size_t(photo)].camera,
                                                    focusSettings_, caster_.get());
    focusStart_ = Clock::now();
    nav_->setMode(Mode::Fly);
    thumbnailFor_ = -1;
  }

  // The map (map_panel.h): a photograph's dot flies to it (focus + context), elsewhere to the
  // ground there, the heading kept, at the view's height above the ground (walking: eye height).
  void mapFrame() {
    const MapPanel::Result r = map_->draw(nav_->camera(), focused_);
    if (r.photo >= 0) {
      std::cout << "viewer: map: to photograph " << r.photo << " (" << session_->scene.photos[size_t(r.photo)].camera.id
                << ")" << std::endl;
      focusOn(r.photo);
    }
    if (!r.ground) return;
    leaveThenNow();
    const MapOverview& m = map_->overview();
    const Camera& cam = nav_->camera();
    const double above = glm::dot(cam.center - m.groundAt(m.toPlane(cam.center)), m.axes.up);
    const double eye = nav_->settings().eyeHeight;
    const double height = nav_->mode() == Mode::Walk ? eye : std::max(eye, above);
    FocusContextSettings s = focusSettings_;
    s.holdSeconds = s.backSeconds = s.stepBack = 0.0;
    s.zoomOut = 1.0;
    s.levelHorizon = false;
    focusPath_ =
        std::make_unique<FocusContextPath>(cam, viewOverGround(cam, *r.ground, m.axes.up, height), s, caster_.get());
    focusStart_ = Clock::now();
    focused_ = -1;
  }

  void toggleRecording() {
    if (!recording_) {
      recording_ = true;
      recordStart_ = Clock::now();
      recorded_.clear();
      panel_.message = "recording the camera path";
      return;
    }
    recording_ = false;
    if (recorded_.empty()) return;
    std::ofstream out(panel_.pathName);
    out << cameraPathJson(recorded_) << "\n";
    panel_.message = out ? "wrote " + std::to_string(recorded_.size()) + " keys to " + panel_.pathName +
                               " (histoview fly SCENE --path " + panel_.pathName + " --out DIR)"
                         : std::string("cannot write ") + panel_.pathName;
    std::cout << panel_.message << "\n";
  }

  void record(const Camera& cam) {
    const double t = msSince(recordStart_) / 1000.0;
    // Keys at 5 Hz at most: fly's Catmull-Rom spline fills in between.
    if (!recorded_.empty() && t < recorded_.back().time + 0.2) return;
    if (!recorded_.empty() &&
        (cam.width != recorded_.front().camera.width || cam.height != recorded_.front().camera.height)) {
      panel_.message = "the window size changed: recording stopped";
      toggleRecording();
      return;
    }
    PathKey k;
    k.camera = cam;
    k.camera.distortion.reset();
    k.camera.id = "k" + std::to_string(recorded_.size());
    k.time = t;
    recorded_.push_back(k);
  }

  // A setting read at construction (settings_panel.h) or a photograph's camera (pose mode)
  // changed: a new renderer with `s`, given the scene's edited layers again (makeRenderer).
  void rebuildRenderer(const render::RenderSettings& s) {
    session_->renderer.reset();
    Diagnostics diag;
    session_->renderer = app::makeRenderer(session_->scene, s, diag, session_->orthophoto);
    for (const auto& e : diag.errors) panel_.message = e;
    renderer_ = session_->renderer.get();
    settingsChanged_ = true;
  }

  void drawPanel() {
    render::RenderSettings& rs = renderer_->settings();
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(360, 0), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSizeConstraints(ImVec2(260, 80), ImVec2(600, std::max(120.0f, ImGui::GetIO().DisplaySize.y - 16)));
    ImGui::Begin("histoview", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
    ImGui::Text("%.1f fps  (%.0f ms/frame, render %.0f ms)", smoothedMs_ > 0 ? 1000.0 / smoothedMs_ : 0.0,
                smoothedMs_, lastRenderMs_);
    const render::RenderStats& st = renderer_->stats();
    ImGui::Text("%s  %s  %d waiting", nav_->mode() == Mode::Walk ? "walking" : "flying",
                renderer_->converged() ? "converged" : "refining", st.imagesWaiting);
    if (!panel_.message.empty()) ImGui::TextWrapped("%s", panel_.message.c_str());
    sources_.draw();

    if (ImGui::CollapsingHeader("Navigation")) {
      int mode = nav_->mode() == Mode::Walk;
      if (ImGui::RadioButton("fly", &mode, 0)) nav_->setMode(Mode::Fly);
      ImGui::SameLine();
      if (ImGui::RadioButton("walk (Tab)", &mode, 1)) nav_->setMode(Mode::Walk);
      float speed = float(nav_->settings().speed);
      if (ImGui::SliderFloat("speed", &speed, 0.1f, 200.0f, "%.1f /s", ImGuiSliderFlags_Logarithmic))
        nav_->settings().speed = speed;
      float eye = float(nav_->settings().eyeHeight);
      if (ImGui::SliderFloat("eye height", &eye, 0.3f, 10.0f, "%.2f")) nav_->settings().eyeHeight = eye;
      float ms = float(movingScale_);
      if (ImGui::SliderFloat("resolution moving", &ms, 0.1f, 1.0f, "%.2f")) movingScale_ = ms;
      ImGui::TextDisabled(
          "WASD/arrows move, Q/E down/up, drag to look,\nshift faster, wheel speed, N/P next/previous "
          "photo,\nC heat map, F frusta, F2 screenshot, R record path, H panel,\nO pose mode");
    }

    if (ImGui::CollapsingHeader("Photographs", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::InputTextWithHint("##search", "search id or date", panel_.search, sizeof panel_.search);
      ImGui::SameLine();
      if (ImGui::ArrowButton("##prev", ImGuiDir_Left)) stepPhoto(-1);
      ImGui::SameLine();
      if (ImGui::ArrowButton("##next", ImGuiDir_Right)) stepPhoto(+1);
      ImGui::BeginChild("photos", ImVec2(0, 150), true);
      const std::string needle = panel_.search;
      for (int i : order_) {
        const Photo& p = session_->scene.photos[size_t(i)];
        if (!needle.empty() && p.camera.id.find(needle) == std::string::npos && p.date.find(needle) == std::string::npos)
          continue;
        const std::string label = p.camera.id + (p.date.empty() ? "" : "   " + p.date);
        if (ImGui::Selectable(label.c_str(), focused_ == i)) focusOn(i);
        if (focused_ == i && focusPath_ && msSince(focusStart_) < 50.0) ImGui::SetScrollHereY();
      }
      ImGui::EndChild();
      if (focused_ >= 0) {
        updateThumbnail();
        if (thumbnail_.id()) {
          const glm::ivec2 ts = thumbnail_.size();
          ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(thumbnail_.id())),
                       ImVec2(float(ts.x), float(ts.y)));
        }
      }
      if (focused_ >= 0) {
        bool on = thenNow_.on;
        if (ImGui::Checkbox("then and now (T)", &on)) on ? enterThenNow(focused_, true) : leaveThenNow();
        ImGui::SameLine();
        if (bool posing = pose_->on(); ImGui::Checkbox("pose (O)", &posing)) togglePose();
        if (thenNow_.on) {
          int mode = thenNow_.settings.mode == ThenNowMode::Swipe;
          ImGui::SameLine();
          if (ImGui::RadioButton("opacity", &mode, 0)) thenNow_.settings.mode = ThenNowMode::Opacity;
          ImGui::SameLine();
          if (ImGui::RadioButton("swipe", &mode, 1)) thenNow_.settings.mode = ThenNowMode::Swipe;
          float v = float(mode ? thenNow_.settings.swipe : thenNow_.settings.opacity);
          if (ImGui::SliderFloat(mode ? "swipe line" : "photograph", &v, 0.0f, 1.0f, "%.2f"))
            (mode ? thenNow_.settings.swipe : thenNow_.settings.opacity) = v;
          ImGui::TextDisabled("%s left out of the render; moving ends it",
                              session_->scene.photos[size_t(thenNow_.photo)].camera.id.c_str());
        }
      }
      float back = float(focusSettings_.stepBack);
      if (ImGui::SliderFloat("step back", &back, 0.0f, 100.0f, "%.1f", ImGuiSliderFlags_Logarithmic))
        focusSettings_.stepBack = back;
      float zoom = float(focusSettings_.zoomOut);
      if (ImGui::SliderFloat("zoom out", &zoom, 0.3f, 1.0f, "%.2f")) focusSettings_.zoomOut = zoom;
    }

    if (ImGui::CollapsingHeader("Timeline", ImGuiTreeNodeFlags_DefaultOpen)) {
      const TimelinePanel::Result t = timeline_->draw(rs);
      settingsChanged_ |= t.changed;
      if (t.chosen >= 0) focusOn(t.chosen);
    }
    if (ImGui::CollapsingHeader("Traffic", ImGuiTreeNodeFlags_DefaultOpen)) settingsChanged_ |= traffic_->draw(rs);

    // The render settings, a section per group of the schema (render/settings_schema.h).
    const Scene& scene = session_->scene;
    SettingsPanel::Result edits;
    auto lacking = [&](const render::Setting& st) {
      return (st.name == "terrain" && scene.terrain.triangles.empty()) ||
             (st.name == "buildings" && scene.buildings.triangles.empty()) ||
             (st.name == "mesh" && scene.mesh.triangles.empty());
    };
    for (const std::string& group : render::settingGroups()) {
      ImGuiTreeNodeFlags flags = group == "Blending" ? ImGuiTreeNodeFlags_DefaultOpen : 0;
      if (group == "Points") {
        if (scene.points.empty()) continue;
        if (rs.points.enabled) ImGui::SetNextItemOpen(true, ImGuiCond_Once);  // --points asked for them
      }
      if (group == "Debug" && (rs.debug.view != render::DebugView::None || rs.debug.frusta))
        ImGui::SetNextItemOpen(true, ImGuiCond_Once);
      if (!ImGui::CollapsingHeader(group.c_str(), flags)) continue;
      settingsPanel_.drawGroup(group, rs, edits, lacking);
      if (group == "Points")
        ImGui::Text("%llu points drawn", static_cast<unsigned long long>(renderer_->stats().pointsDrawn));
      if (group == "Debug") settingsChanged_ |= drawDebugState(*renderer_, scene, rs.debug);
    }
    settingsChanged_ |= edits.changed;
    if (!edits.error.empty()) panel_.message = edits.error;

    if (ImGui::CollapsingHeader("Capture")) {
      ImGui::InputText("png", panel_.screenshotName, sizeof panel_.screenshotName);
      ImGui::Checkbox("with the panel", &panel_.screenshotWithUi);
      ImGui::SameLine();
      if (ImGui::Button("screenshot (F2)")) ++screenshotsRequested_;
      ImGui::InputText("path", panel_.pathName, sizeof panel_.pathName);
      if (ImGui::Button(recording_ ? "stop recording (R)" : "record camera path (R)")) toggleRecording();
      if (recording_) {
        ImGui::SameLine();
        ImGui::Text("%zu keys", recorded_.size());
      }
    }
    ImGui::End();
    // After the panel: `rs` refers to the current renderer's settings.
    if (edits.rebuild) rebuildRenderer(*edits.rebuild);
  }

  void updateThumbnail() {
    if (thumbnailFor_ == focused_) return;
    thumbnailFor_ = focused_;
    try {
      const Image8 img = readImage(session_->scene.photos[size_t(focused_)].imagePath, 3);
      const int w = 240, h = std::max(1, int(std::lround(double(img.height) * w / img.width)));
      thumbnail_.upload(resizeImage(img, w, h));
    } catch (const std::exception& e) {
      panel_.message = e.what();
    }
  }

  void writeScreenshot(const std::string& path, glm::ivec2 fb) {
    writePng(path, gpu::readFramebufferFlipped(fb));
    std::cout << "wrote " << path << " (" << fb.x << "x" << fb.y << ")\n";
  }

  // F2 and the panel's button: one picture per request, each under the next free name of the
  // panel's series (shot.png gives shot-001.png, shot-002.png…; never one written before), the
  // last one's full path said in the panel.
  void writeRequestedScreenshots(glm::ivec2 fb) {
    const int n = std::exchange(screenshotsRequested_, 0);
    for (int i = 0; i < n; ++i) writeRequestedScreenshot(fb);
  }

  void writeRequestedScreenshot(glm::ivec2 fb) {
    std::string name;
    try {
      name = nextNumberedName(panel_.screenshotName, [](const std::string& n) {
        std::error_code ec;
        return std::filesystem::exists(n, ec) || ec;
      });
      writeScreenshot(name, fb);
      std::error_code ec;
      const auto full = std::filesystem::absolute(name, ec);
      panel_.message = "wrote " + (ec ? name : full.string());
    } catch (const std::exception& e) {
      panel_.message = std::string("screenshot not written: ") + e.what();
      std::cerr << "error: " << panel_.message << "\n";
    }
  }

  int loop() {
    auto last = Clock::now();
    int frame = 0;
    bool haveFrame = false;
    double renderedScale = 0.0;
    Camera rendered;
    std::vector<double> convergedMs, allMs;
    int exitCode = 0;
    while (!window_->shouldClose()) {
      const auto t0 = Clock::now();
      // Idle (nothing moving, the view converged): sleep until an event instead of spinning.
      const bool idle = haveFrame && !focusPath_ && renderer_->converged() && renderedScale == 1.0 && !o_.redraw &&
                        !settingsChanged_ && !recording_ && !o_.exitAfterConverge && !timeline_->player().playing() &&
                        !traffic_->clock().playing();
      window_->pollEvents(idle ? 0.25 : 0.0);
      const double elapsed = std::max(0.0, std::chrono::duration<double>(Clock::now() - last).count());
      const double dt = std::min(elapsed, 0.1);
      last = Clock::now();

      window_->beginUi();
      handleKeys();

      const glm::ivec2 fb = window_->framebufferSize();
      if (fb.x <= 0 || fb.y <= 0) {  // minimised
        ImGui::EndFrame();
        continue;
      }
      // Camera: a focus + context transition, else the keys and mouse.
      const NavigationInput in = readInput(dt);
      keys_.endFrame();  // this frame has seen every press since the last one
      if (thenNow_.on && (in.move != glm::dvec3(0.0) || in.lookPixels != glm::dvec2(0.0)))
        leaveThenNow();  // the photograph fits only its own camera
      if (timeline_->step(elapsed, renderer_->settings())) settingsChanged_ = true;  // play, at wall-clock speed
      if (traffic_->step(elapsed, renderer_->settings())) settingsChanged_ = true;
      if (focusPath_) {
        const double t = msSince(focusStart_) / 1000.0;
        nav_->setCamera(focusPath_->at(t));
        if (t >= focusPath_->duration()) focusPath_.reset();
        if (in.move != glm::dvec3(0.0) || in.lookPixels != glm::dvec2(0.0)) focusPath_.reset();  // the user takes over
      } else if (nav_->update(in)) {
        if (nav_->camera().distortion) {  // a distorted start view stays distorted only until it moves
          Camera c = nav_->camera();
          c.distortion.reset();
          nav_->setCamera(c);
        }
        if (in.move != glm::dvec3(0.0)) focused_ = -1;
      }
      if (nav_->camera().width != fb.x || nav_->camera().height != fb.y)
        nav_->setCamera(thenNow_.on && !focusPath_
                            ? photoInWindow(session_->scene.photos[size_t(thenNow_.photo)].camera, fb.x, fb.y)
                            : reframe(nav_->camera(), fb));
      const Camera& cam = nav_->camera();
      const bool moved = !haveFrame || cam.center != rendered.center || cam.camFromWorld != rendered.camFromWorld ||
                         cam.focal != rendered.focal || cam.width != rendered.width || cam.height != rendered.height;
      if (recording_) record(cam);

      // Progressive rendering: reduced resolution while moving, full once still; frames go on
      // until every selected image is resident with a current depth map.
      const double scale = moved && haveFrame ? movingScale_ : 1.0;
      // A building tile that failed is read again after a back-off: frames keep coming (at the idle
      // poll's pace) while one waits, so that its next try is made.
      const bool needRender = moved || settingsChanged_ || !renderer_->converged() || renderedScale != scale ||
                              o_.redraw || renderer_->stats().buildingTilesRetrying > 0;
      Camera view = cam;
      if (scale < 1.0) {
        const int w = std::max(16, int(std::lround(cam.width * scale))), h = std::max(16, int(std::lround(cam.height * scale)));
        view = cam.scaled(double(h) / cam.height, w, h);
      }
      if (needRender) {
        const auto r0 = Clock::now();
        renderer_->render(view, false, render::FrameMode::Progressive);
        lastRenderMs_ = msSince(r0);
        rendered = cam;
        renderedScale = scale;
        renderedSize_ = {view.width, view.height};
        haveFrame = true;
        settingsChanged_ = false;
      }
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glViewport(0, 0, fb.x, fb.y);
      glClearColor(0.f, 0.f, 0.f, 1.f);
      glClear(GL_COLOR_BUFFER_BIT);
      // The picture, or the debug view the renderer drew in its place.
      if (renderer_->colorTexture()) presenter_->blitFlipped(renderer_->colorTexture(), renderedSize_, fb);
      sources_.update(session_->scene, *renderer_);

      const bool converged =
          renderer_->converged() && renderedScale == 1.0 && !focusPath_ && !timeline_->player().playing();
      const bool finalShot = o_.exitAfterConverge && converged && !o_.screenshot.empty();
      // Then and now draws the photograph in the UI's background layer: a screenshot without the
      // panel is then taken after the UI pass, the panel left out of that frame.
      const bool overlay = thenNow_.on && !focusPath_;
      bool shotAfterUi = false, panelThisFrame = showPanel_;
      if (finalShot && !o_.screenshotUi && !overlay) writeScreenshot(o_.screenshot, fb);
      if (finalShot && (o_.screenshotUi || overlay)) shotAfterUi = true;
      if (finalShot && !o_.screenshotUi && overlay) panelThisFrame = false;
      bool requestedAfterUi = screenshotsRequested_ > 0;
      if (requestedAfterUi && !panel_.screenshotWithUi) {
        if (overlay)
          panelThisFrame = false;
        else
          writeRequestedScreenshots(fb), requestedAfterUi = false;
      }
      if (overlay) drawThenNow(fb);
      // The panel after the frame, so it shows this frame's state; what it changes applies next frame.
      if (panelThisFrame) drawPanel();
      if (panelThisFrame == showPanel_) mapFrame();  // not in a frame whose screenshot leaves the UI out
      poseFrame();
      window_->endUi();
      if (shotAfterUi) writeScreenshot(o_.screenshot, fb);
      if (requestedAfterUi) writeRequestedScreenshots(fb);
      window_->swapBuffers();

      const double ms = msSince(t0);
      ++frame;
      smoothedMs_ = smoothedMs_ <= 0.0 ? ms : 0.9 * smoothedMs_ + 0.1 * ms;
      if (needRender) {
        allMs.push_back(ms);
        if (converged) convergedMs.push_back(ms);
      }
      if (o_.printFrameTimes)
        std::cout << "frame " << frame << ": " << std::fixed << std::setprecision(1) << ms << " ms (render "
                  << lastRenderMs_ << " ms, " << view.width << "x" << view.height << ", "
                  << (converged ? "converged" : std::to_string(renderer_->stats().imagesWaiting) + " waiting")
                  << ")" << std::endl;  // flushed: read live by scripts waiting for frames
      if (frame % 15 == 0) {
        std::ostringstream title;
        title << "histoview - " << std::fixed << std::setprecision(1) << 1000.0 / std::max(smoothedMs_, 1e-3) << " fps";
        window_->setTitle(title.str());
      }
      if (o_.exitAfterConverge && converged) {
        std::cout << "converged after " << frame << " frame(s)\n";
        break;
      }
      if (o_.frames > 0 && frame >= o_.frames) {
        if (o_.exitAfterConverge) {
          std::cerr << "error: not converged after " << frame << " frame(s) (--frames)\n";
          exitCode = 1;
        }
        break;
      }
    }
    if (recording_) toggleRecording();
    if (poseScriptFailed_) exitCode = 2;
    if (o_.trafficRate > 0.0) std::cout << "viewer: traffic at " << renderer_->settings().traffic.time << " s\n";
    if (o_.printFrameTimes) {
      std::cout << std::fixed << std::setprecision(1) << "frame times: " << allMs.size() << " rendered frame(s), median "
                << median(allMs) << " ms";
      if (!convergedMs.empty())
        std::cout << "; " << convergedMs.size() << " converged, median " << median(convergedMs) << " ms ("
                  << 1000.0 / median(convergedMs) << " fps)";
      std::cout << "\n";
    }
    return exitCode;
  }

  ViewerOptions o_;
  bool vsync_ = true;
  std::unique_ptr<app::Session> session_;
  GlfwWindow* window_ = nullptr;  // owned by session_ (its context)
  render::Renderer* renderer_ = nullptr;
  std::unique_ptr<RayCaster> caster_;
  std::unique_ptr<Navigator> nav_;
  std::unique_ptr<gpu::Presenter> presenter_;
  std::vector<int> order_;
  int focused_ = -1;
  FocusContextSettings focusSettings_;
  std::unique_ptr<FocusContextPath> focusPath_;
  Clock::time_point focusStart_;
  PanelState panel_;
  SettingsPanel settingsPanel_;
  SourcesPanel sources_;
  std::unique_ptr<TimelinePanel> timeline_;
  std::unique_ptr<PosePanel> pose_;
  bool poseScriptFailed_ = false;
  std::unique_ptr<TrafficPanel> traffic_;
  std::unique_ptr<MapPanel> map_;
  ThenNowState thenNow_;
  bool showPanel_ = true;
  bool settingsChanged_ = false;
  int screenshotsRequested_ = 0;  // F2 taps and button clicks not yet written
  KeyEvents keys_;
  bool recording_ = false;
  Clock::time_point recordStart_;
  std::vector<PathKey> recorded_;
  gpu::ImageTexture thumbnail_;
  int thumbnailFor_ = -1;
  double movingScale_ = 0.5;
  double smoothedMs_ = 0.0, lastRenderMs_ = 0.0;
  glm::ivec2 renderedSize_{0};

 public:
  void setMovingScale(double s) { movingScale_ = s; }
};

}  // namespace

int run(const ViewerOptions& options) {
  Viewer v(options);
  v.setMovingScale(options.movingScale);
  return v.run();
}

}  // namespace hv::viewer
