// The viewer's map (docs/viewer.md, key M): a window with the 2D overview of the scene
// (hv/viewer/map_overview.h) — the terrain's hillshade, the buildings' footprints, every
// photograph as a dot with its viewing direction (dated ones orange, undated ones blue-grey), the
// view's position and heading in red — drawn with Dear ImGui's draw list. A click on a dot picks
// that photograph, elsewhere the ground there; the viewer flies to it.
#pragma once

#include "hv/gpu/present.h"
#include "hv/scene/scene.h"
#include "hv/viewer/map_overview.h"

#include <optional>
#include <vector>

namespace hv::viewer {

class MapPanel {
 public:
  // `dated[i]`: photograph i has a date (the timeline's PhotoDates).
  MapPanel(const Scene& scene, const std::vector<bool>& dated);

  bool open() const { return open_; }
  void toggle() { open_ = !open_; }
  // For scripts and tests: print where each photograph's dot is in the window ("viewer: map:
  // photograph INDEX at X Y", window pixels) whenever the map moves or is resized.
  void printDots(bool on) { printDots_ = on; }
  const MapOverview& overview() const { return map_; }

  struct Result {
    int photo = -1;                    // a photograph's dot was clicked
    std::optional<glm::dvec3> ground;  // else the ground there (world)
  };
  // The window (when open) with the view `view` on it; `chosen` (-1: none) ringed.
  Result draw(const Camera& view, int chosen);

 private:
  MapOverview map_;
  gpu::ImageTexture shade_;
  bool uploaded_ = false;
  bool open_ = false;
  bool printDots_ = false;
  glm::vec4 printedAt_{-1.0f};  // the map's rectangle when its dots were last printed
};

}  // namespace hv::viewer
