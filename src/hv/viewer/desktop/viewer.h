// The desktop viewer (`histoview view`): a GLFW window with a GLES 3 context, the same
// renderer as `render` in progressive frames, free flight and street-level walking, focus +
// context on the photographs, an ImGui control panel. Built only when GLFW and Dear ImGui are
// found (HV_HAVE_VIEWER); the platform code is under hv/viewer/desktop/.
#pragma once

#include "hv/session/session.h"

#include <string>

namespace hv::viewer {

struct ViewerOptions {
  app::ViewOptions view;         // scene, --views, --size (the window), K, sigma, ...
  std::string camera;            // start at this camera (a view of --views, else a photograph)
  std::string screenshot;        // write the view to this PNG (at exit with --exit-after-converge)
  bool screenshotUi = false;     // ... with the control panel drawn over it
  bool exitAfterConverge = false;
  int frames = 0;                // > 0: stop after this many frames
  bool printFrameTimes = false;
  bool redraw = false;           // render every frame even when nothing changed (measuring)
  bool walk = false;             // start walking
  bool hidePanel = false;
  bool map = false;              // start with the map open (M toggles it)
  double movingScale = 0.5;      // render resolution while the camera moves (progressive)
  std::string timeline;          // "A:B": the time window at these timeline positions (0..1)
  double playYearsPerSecond = 0;  // > 0: play the timeline from the start at this speed
  double trafficRate = 0;         // > 0: play the traffic from --time at this many simulated s per s
  bool thenNow = false;           // start in then and now at --camera (a photograph)
  double thenNowOpacity = -1;     // >= 0: then and now with this opacity
  double thenNowSwipe = -1;       // >= 0: then and now with a swipe at this position
  std::string poseScript;         // pose mode's clicks from this file, at the first frame (pose_panel.h)
};

// True when this build has the viewer.
bool available();
// Runs the viewer until the window closes (or the exit conditions of the options); the exit
// code: 0, 1 when --exit-after-converge stopped at --frames without converging, 2 on errors.
int run(const ViewerOptions& options);

}  // namespace hv::viewer
