#include "hv/app/fly_command.h"

#include "hv/camera/camera_path.h"
#include "hv/image/image.h"
#include "hv/image/native/png_write.h"
#include "hv/io/camera_path_json.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"
#include "hv/viewer/tour.h"

#include <CLI/CLI.hpp>

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <optional>
#include <sstream>

extern char** environ;

namespace hv::app {

namespace fs = std::filesystem;

namespace {

std::string duration(double seconds) {
  const long s = std::lround(std::max(seconds, 0.0));
  std::ostringstream out;
  if (s >= 3600)
    out << s / 3600 << ":" << std::setw(2) << std::setfill('0') << (s / 60) % 60;
  else
    out << s / 60;
  out << ":" << std::setw(2) << std::setfill('0') << s % 60;
  return out.str();
}

// Runs argv[0] (looked up on $PATH) and waits; its exit status, or -1 when it could not start.
// posix_spawn rather than system(): no shell, so paths need no quoting.
int runProgram(const std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawnp(&pid, argv[0], nullptr, nullptr, argv.data(), environ) != 0) return -1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

// For printing a command the user can paste: single-quotes what a shell would otherwise expand.
std::string shellQuoted(const std::string& arg) {
  const bool plain = !arg.empty() && arg.find_first_not_of(
                                         "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz"
                                         "0123456789_./%:=+,-") == std::string::npos;
  if (plain) return arg;
  std::string out = "'";
  for (char c : arg) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

struct FlyOptions {
  ViewOptions view;
  std::string path;
  std::string out;
  double fps = 25.0;
  bool progressive = false;
  std::string video;
  double timeScale = 1.0;  // traffic seconds per path second
};

// fly --camera/--eye: the focus + context walk through the viewpoints (hv/viewer/tour.h), at
// --size or the first viewpoint's size.
CameraPath viewpointPath(const Scene& scene, const FlyOptions& o) {
  const std::vector<Photo> focus = focusViews(scene, {}, o.view.viewpoint, o.view.size);
  std::vector<Camera> cameras;
  for (const Photo& p : focus) cameras.push_back(p.camera);
  glm::ivec2 size(cameras.front().width, cameras.front().height);
  if (!o.view.size.empty()) size = parseSize(o.view.size);
  viewer::TourSettings t;
  t.focus.up = scene.up;
  t.focus.stepBack = o.view.viewpoint.stepBack.value_or(0.0);
  t.focus.zoomOut = o.view.viewpoint.stepBack ? o.view.viewpoint.zoomOut : 1.0;
  return CameraPath(viewer::focusContextKeys(cameras, size.x, size.y, t));
}

int runFly(const FlyOptions& o) {
  Diagnostics diag;
  const bool fromPath = !o.path.empty();
  if (fromPath == o.view.viewpoint.any())
    throw std::invalid_argument(
        "fly: give either --path FILE or viewpoints (--camera ID, --eye X,Y,Z --look-at "
        "X,Y,Z)");
  // Everything that can be checked without the scene is checked first.
  std::optional<PathFrames> frames;
  try {
    if (fromPath) {
      frames.emplace(readCameraPath(o.path, diag), o.fps);
      sizeView((*frames)[0], o.view.size, o.view.viewpoint.fit);  // every frame has the keys' size
    }
    renderSettings(o.view);  // the option values (dates, colour)
  } catch (const std::exception& e) {
    std::cerr << "error: " << o.path << ": " << e.what() << "\n";
    return kExitNoScene;
  }
  std::string ffmpeg;
  if (!o.video.empty()) {
    ffmpeg = findOnPath("ffmpeg");
    if (ffmpeg.empty())
      std::cerr << "warning: --video: ffmpeg is not on PATH; the frames will be written as PNGs but not encoded\n";
  }
  ViewOptions sessionOptions = o.view;
  sessionOptions.viewpoint = {};  // the viewpoints make the path, not views
  const std::unique_ptr<Session> s = openSession(sessionOptions, diag);
  if (!fromPath) frames.emplace(viewpointPath(s->scene, o), o.fps);
  const Camera first = sizeView((*frames)[0], o.view.size, o.view.viewpoint.fit);
  std::cout << "flying " << frames->size() << " frame(s) of " << first.width << "x" << first.height << " at " << o.fps
            << " fps (" << (o.progressive ? "progressive" : "converged") << " frames) to " << o.out << "\n";
  const FlyResult r = flyPath(
      *s->renderer, frames->size(), [&](int i) { return sizeView((*frames)[i], o.view.size, o.view.viewpoint.fit); },
      o.out, o.progressive, [](const FlyFrame& f) { std::cerr << progressLine(f) << std::flush; },
      [&, start = s->renderer->settings().traffic.time](int i) {
        return flyTrafficTime(i, o.fps, start, o.timeScale);
      });
  std::cerr << "\n";
  for (const std::string& f : r.failures) std::cerr << "error: " << f << "\n";
  if (r.gaveUp)
    std::cerr << "error: " << kMaxConsecutiveFlyFailures << " frames failed in a row; the remaining "
              << frames->size() - r.frames - int(r.failures.size()) << " frame(s) were not tried\n";
  std::cout << "wrote " << r.frames << " frame(s) to " << o.out << " in " << std::fixed << std::setprecision(1)
            << r.totalMs / 1000.0 << " s";
  if (o.progressive) std::cout << " (" << r.convergedFrames << " converged)";
  if (!r.failures.empty()) std::cout << "; " << r.failures.size() << " failed";
  std::cout << "\n";
  if (o.progressive && r.frames > 0) {
    std::cout << "first frame after " << std::setprecision(2) << r.firstMs / 1000.0 << " s";
    if (r.firstShown >= 0)
      std::cout << "; first frame showing photographs: " << r.firstShown << ", after " << r.firstShownMs / 1000.0
                << " s";
    if (r.firstConverged >= 0)
      std::cout << "; first converged frame: " << r.firstConverged << ", after " << r.firstConvergedMs / 1000.0 << " s";
    std::cout << "\n";
  }
  std::cout << fetchedSummary();
  if (const std::string m = s->scene.missing->summary(); !m.empty()) std::cout << m << "\n";
  const std::size_t missing = std::size_t(frames->size() - r.frames);
  const int code = exitStatus(diag, missing);
  if (!o.video.empty() && missing > 0) {
    std::cerr << "error: --video: " << missing << " frame(s) are missing, so " << o.video
              << " was not encoded; the PNG frames are in " << o.out << "\n";
    return code;
  }
  if (!o.video.empty()) {
    const auto args = ffmpegArguments(ffmpeg.empty() ? "ffmpeg" : ffmpeg, o.out, o.fps, r.frames, o.video);
    std::string command;
    for (const auto& a : args) command += (command.empty() ? "" : " ") + shellQuoted(a);
    if (ffmpeg.empty()) {
      std::cerr << "error: --video: ffmpeg is not installed (not found on PATH), so " << o.video
                << " was not written; the PNG frames are in " << o.out << ". With ffmpeg: " << command << "\n";
      return 1;
    }
    std::cout << "encoding: " << command << "\n";
    const int status = runProgram(args);
    if (status != 0) {
      std::cerr << "error: --video: ffmpeg "
                << (status < 0 ? "could not be started" : "failed (exit status " + std::to_string(status) + ")")
                << "; the PNG frames are in " << o.out << "\n";
      return 1;
    }
    std::cout << "wrote " << o.video << "\n";
  }
  return code;
}

}  // namespace

FlyResult flyPath(render::Renderer& renderer, const std::vector<Camera>& frames, const std::string& outDir,
                  bool progressive, const FlyProgress& progress) {
  return flyPath(
      renderer, int(frames.size()), [&](int i) { return frames[size_t(i)]; }, outDir, progressive, progress);
}

double flyTrafficTime(int frame, double fps, double start, double scale) { return start + scale * frame / fps; }

FlyResult flyPath(render::Renderer& renderer, int count, const std::function<Camera(int)>& frame,
                  const std::string& outDir, bool progressive, const FlyProgress& progress,
                  const std::function<double(int)>& trafficTime) {
  using clock = std::chrono::steady_clock;
  fs::create_directories(outDir);
  FlyResult result;
  OutputNames names;
  const auto start = clock::now();
  const render::FrameMode mode = progressive ? render::FrameMode::Progressive : render::FrameMode::Batch;
  int consecutiveFailures = 0;
  for (int i = 0; i < count; ++i) {
    const Camera cam = frame(i);
    const auto t0 = clock::now();
    FlyFrame f;
    f.index = i;
    f.total = count;
    std::string note;
    f.file = (fs::path(outDir) / (names.stem(cam.id, &note) + ".png")).string();
    if (!note.empty()) std::cerr << "note: frame " << note << "\n";
    if (trafficTime) renderer.settings().traffic.time = trafficTime(i);
    try {
      const render::RenderOutput out = renderer.render(cam, false, mode);
      writePng(f.file, rgbOf(out.rgba));
      consecutiveFailures = 0;
    } catch (const std::exception& e) {
      result.failures.push_back("frame '" + cam.id + "' (" + f.file + "): " + e.what());
      if (++consecutiveFailures >= kMaxConsecutiveFlyFailures) {
        result.gaveUp = i + 1 < count;
        break;
      }
      continue;
    }
    const auto t1 = clock::now();
    f.ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
    f.elapsedMs = std::chrono::duration<double, std::milli>(t1 - start).count();
    f.converged = renderer.converged();
    f.imagesWaiting = renderer.stats().imagesWaiting;
    if (result.frames == 0) result.firstMs = f.elapsedMs;
    if (result.firstShown < 0 && renderer.lastPlan().images.size() > std::size_t(f.imagesWaiting)) {
      result.firstShown = i;
      result.firstShownMs = f.elapsedMs;
    }
    if (f.converged && result.firstConverged < 0) {
      result.firstConverged = i;
      result.firstConvergedMs = f.elapsedMs;
    }
    ++result.frames;
    result.convergedFrames += f.converged;
    result.totalMs = f.elapsedMs;
    if (progress) progress(f);
  }
  return result;
}

std::string progressLine(const FlyFrame& f) {
  constexpr int kWidth = 24;
  const int done = f.index + 1;
  const double fraction = f.total > 0 ? double(done) / f.total : 1.0;
  const int filled = std::clamp(int(std::lround(fraction * kWidth)), 0, kWidth);
  // Mean over the frames so far: the first frames (images loading, depth maps) are slower, and
  // the mean settles faster than an exponential average would forget them.
  const double msPerFrame = f.elapsedMs / std::max(done, 1);
  std::ostringstream s;
  s << "\r[" << std::string(size_t(filled), '#') << std::string(size_t(kWidth - filled), '-') << "] frame " << done
    << "/" << f.total << "  " << std::setw(3) << std::lround(100.0 * fraction) << "%  " << std::setw(5)
    << std::lround(msPerFrame) << " ms/frame  ETA " << duration(msPerFrame * (f.total - done) / 1000.0);
  if (!f.converged) s << "  (" << f.imagesWaiting << " waiting)";
  s << "   ";  // clears what a longer previous line left
  return s.str();
}

std::string findOnPath(const std::string& program) {
  const char* env = std::getenv("PATH");
  if (!env) return "";
  std::istringstream dirs(env);
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / program;
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return "";
}

std::vector<std::string> ffmpegArguments(const std::string& ffmpeg, const std::string& outDir, double fps, int frames,
                                         const std::string& video) {
  std::ostringstream rate;
  rate << std::setprecision(10) << fps;
  return {ffmpeg, "-hide_banner", "-loglevel", "error", "-y", "-framerate", rate.str(), "-i",
          (fs::path(outDir) / "f%05d.png").string(),
          // Only this run's frames (an earlier, longer run may have left more in the directory).
          "-frames:v", std::to_string(frames),
          // yuv420p halves the chroma in both directions, so H.264 needs even sizes: pad by a pixel.
          "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-pix_fmt", "yuv420p", video};
}

void addFlyCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("fly", "render a camera path (PATH.json) frame by frame to PNGs, optionally a video");
  auto o = std::make_shared<FlyOptions>();
  addViewOptions(*cmd, o->view, false);
  cmd->add_option("--path", o->path,
                  "key cameras (cameras.json schema, optional time t in seconds per camera; `histoview path` "
                  "makes one); or fly to the viewpoints given by --camera/--eye")
      ->check(CLI::ExistingFile);
  addViewpointOptions(*cmd, o->view.viewpoint);
  cmd->add_option("--out", o->out, "output directory (<frame id>.png: f00000.png, f00001.png, ...)")->required();
  cmd->add_option("--fps", o->fps, "frames per second along the path (default 25)")->check(CLI::PositiveNumber);
  cmd->add_flag("--progressive", o->progressive,
                "render as a viewer does: one progressive frame per camera, improving as depth maps arrive "
                "(default: every frame converged)");
  cmd->add_option("--time-scale", o->timeScale,
                  "the traffic's clock: at frame i it reads --time + time-scale * i / fps, the path's own "
                  "seconds since its first key scaled (default 1: the vehicles move in real time; 0: they stand "
                  "still at --time)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--video", o->video, "also encode the frames with ffmpeg (when installed), e.g. out.mp4");
  setAction(*cmd, exitCode, [o] { return runFly(*o); });
}

}  // namespace hv::app
