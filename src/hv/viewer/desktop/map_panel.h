// The viewer's map (docs/viewer.md, key M): a window with the 2D overview of the scene
// (hv/viewer/map_overview.h) — the terrain's hillshade (under the scene's orthophoto where it has
// one), the buildings' footprints, every
// photograph as a dot with its viewing direction (dated ones orange, undated ones blue-grey), the
// view's position and heading in red — drawn with Dear ImGui's draw list. The wheel zooms about
// the pointer, a drag pans, "Whole map" goes back to the whole extent (MapZoom). A click (a release
// without a drag) on a dot picks that photograph, elsewhere the ground there; the viewer flies to it.
#pragma once

#include "hv/gpu/present.h"
#include "hv/scene/orthophoto.h"
#include "hv/scene/scene.h"
#include "hv/viewer/map_overview.h"

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace hv::viewer {

class MapPanel {
 public:
  // `dated[i]`: photograph i has a date (the timeline's PhotoDates); `orthophoto` (null: none) is
  // drawn over the hillshade (orthophotoOnMap).
  MapPanel(const Scene& scene, const std::vector<bool>& dated, std::shared_ptr<const Orthophoto> orthophoto = nullptr);

  bool open() const { return open_; }
  void toggle() { open_ = !open_; }
  // For scripts and tests: print where each photograph's dot is in the window ("viewer: map:
  // photograph INDEX at X Y", window pixels) whenever the map moves, is resized, zoomed or panned.
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
  std::shared_ptr<const Orthophoto> orthophoto_;
  std::optional<PlaneBox> orthophotoBox_;  // where it lies on the map; none: not drawn
  gpu::ImageTexture orthophotoTexture_;
  bool open_ = false;
  bool printDots_ = false;
  MapZoom zoom_;
  MapZoom panFrom_;                    // the zoom when the drag began
  std::array<double, 7> printedAt_{};  // the map's rectangle and scale when its dots were last printed
};

}  // namespace hv::viewer
