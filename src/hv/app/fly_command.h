// `histoview fly`: renders a camera path (hv/camera/camera_path.h) frame by frame to PNGs, either
// converged frames (FrameMode::Batch) or through the progressive machinery a viewer uses
// (FrameMode::Progressive: one render call per frame, the picture improving as depth maps arrive),
// and optionally encodes them with ffmpeg.
#pragma once

#include "hv/camera/camera.h"
#include "hv/render/renderer.h"

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hv::app {

void addFlyCommand(CLI::App& app, int& exitCode);

// What flyPath reports after each frame.
struct FlyFrame {
  int index = 0;  // 0-based
  int total = 0;
  std::string file;        // the PNG written
  double ms = 0.0;         // this frame: render and PNG
  double elapsedMs = 0.0;  // since the sequence started
  bool converged = true;   // every selected image with a current depth map (Renderer::converged)
  int imagesWaiting = 0;   // selected images left out of this frame (progressive)
};
using FlyProgress = std::function<void(const FlyFrame&)>;

struct FlyResult {
  int frames = 0;  // written
  int convergedFrames = 0;
  double totalMs = 0.0;
  double firstMs = 0.0;           // from the start to the end of the first frame written
  int firstShown = -1;            // the first frame that shows a photograph (-1: none)
  double firstShownMs = 0.0;      // from the start to its end
  int firstConverged = -1;        // the first converged frame (-1: none)
  double firstConvergedMs = 0.0;  // from the start to its end
  // Frames that could not be rendered or written, each named with its error ("frame 'f00012': ...").
  std::vector<std::string> failures;
  bool gaveUp = false;  // kMaxConsecutiveFlyFailures frames failed in a row: the rest was not tried
};

// A failed frame is named and the path goes on; this many failures in a row (a full disk, a lost
// GL context) end it.
inline constexpr int kMaxConsecutiveFlyFailures = 8;

// Renders every camera in order to outDir/<id>.png (RGB; outDir is created; ids made safe file
// names by OutputNames, hv/app/outputs.h). `progressive`: one FrameMode::Progressive call per
// frame, as a viewer would make; otherwise FrameMode::Batch, each frame converged. A frame the
// renderer or the PNG writer fails on is reported in FlyResult::failures and the path goes on.
FlyResult flyPath(render::Renderer& renderer, const std::vector<Camera>& frames, const std::string& outDir,
                  bool progressive, const FlyProgress& progress = {});
// The same with frames made one at a time (`frame(i)` for i in [0, count)): a long path is never
// held whole.
// `trafficTime(i)`, when given, is frame i's time on the traffic simulation's clock (seconds): the
// renderer's traffic.time is set to it before the frame, so that the vehicles move while the camera
// does (docs/traffic.md, "fly").
FlyResult flyPath(render::Renderer& renderer, int count, const std::function<Camera(int)>& frame,
                  const std::string& outDir, bool progressive, const FlyProgress& progress = {},
                  const std::function<double(int)>& trafficTime = {});

// The traffic's clock at frame i of a path flown at `fps`: frame i is at i / fps seconds after the
// path's first key (hv::PathFrames), so the clock reads start + scale * i / fps. `start` is the
// setting `time` (--time), `scale` fly's --time-scale (0: the traffic stands still).
double flyTrafficTime(int frame, double fps, double start, double scale);

// One line of the progress bar, starting with '\r' so that each redraws the last:
// "\r[########------------] frame 12/100  12%   85 ms/frame  ETA 0:07".
std::string progressLine(const FlyFrame& frame);

// The full path of an executable found on $PATH; empty when there is none.
std::string findOnPath(const std::string& program);
// ffmpeg's arguments (argv[0] included) to encode outDir/f00000.png ... as `video`.
std::vector<std::string> ffmpegArguments(const std::string& ffmpeg, const std::string& outDir, double fps, int frames,
                                         const std::string& video);

}  // namespace hv::app
