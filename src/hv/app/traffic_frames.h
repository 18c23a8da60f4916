// The demo's traffic sequence (docs/traffic.md, "The demo's frame sequence"): a camera path that
// follows one vehicle of the simulation along the streets, from behind and above, flown with the
// traffic's clock (`histoview fly` with time) into a short sequence of frames.
#pragma once

#include "hv/camera/camera_path.h"
#include "hv/render/renderer.h"
#include "hv/traffic/lift.h"
#include "hv/traffic/trajectories.h"

#include <string>
#include <vector>

namespace hv::app {

struct TrafficFramesOptions {
  int frames = 36;  // frame i at start + i / fps on the traffic's clock
  double fps = 12.0;
  int width = 480, height = 360;
  double fovDeg = 65.0;       // horizontal
  double start = 20.0;        // seconds on the simulation's clock
  double behind = 12.0;       // metres: the eye follows the vehicle's own path this far back
  double ahead = 12.0;        // metres: it looks at the vehicle's path this far ahead
  double eyeHeight = 3.0;     // above the terrain under the eye
  double targetHeight = 1.0;  // above the terrain under the point looked at
};

// The vehicle followed and the path's keys, one per frame (key i at time i / fps, the path's own
// clock: fly draws the traffic at start + i / fps). The vehicle is one present over the whole
// sequence that moves at 2 m/s on average or more, with the best score summed over the frames
// (ties: the first in the file): 2 per photograph within 30 m of the eye looking within 60° of
// its way (at most 4 counted: the frame is textured), plus 1 per other vehicle within 60 m ahead
// of the eye. The eye stays on the vehicle's own track (on the street), `behind` metres of it
// back, extended straight back before its first sample. Empty keys when no vehicle qualifies.
struct TrafficChase {
  std::string vehicle;
  std::vector<PathKey> keys;
  int othersInView = 0;  // other vehicles ahead, summed over the frames
};
TrafficChase trafficChase(const Trajectories& traffic, const TerrainHeight& terrain, const TrafficFramesOptions& o,
                          const std::vector<Camera>& photos = {});

// Writes dir/path.json (the keys, `histoview fly --path` reads it) and dir/frames/f00000.png ...,
// rendered by `renderer` (its settings, traffic.time set per frame) with a progress bar on
// stderr. Returns the number of frames written; a message on stdout says where they went or why
// there are none.
int writeTrafficFrames(render::Renderer& renderer, const Trajectories& traffic, const TerrainHeight& terrain,
                       const TrafficFramesOptions& o, const std::string& dir, const std::vector<Camera>& photos = {});

}  // namespace hv::app
