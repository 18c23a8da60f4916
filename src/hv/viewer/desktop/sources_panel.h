// The viewer panel's Sources section (docs/viewer.md): the reads from services at load, the tiles
// and photographs still streaming, and what is missing (hv/viewer/source_status.h). The same
// lines are printed on stdout as "viewer: sources: ..." when they change (missing sources, the
// load's progress), so that a script sees what the panel says.
#pragma once

#include "hv/render/renderer.h"
#include "hv/viewer/source_status.h"

#include <cstddef>
#include <string>
#include <vector>

namespace hv::viewer {

class SourcesPanel {
 public:
  // Gathers the status for the renderer's last frame; prints what changed since the last call.
  void update(const Scene& scene, const render::Renderer& renderer);
  // Draws the section (open by default while something is missing).
  void draw() const;
  bool anyMissing() const { return !lines_.missing.empty(); }

 private:
  SourceStatusLines lines_;
  std::vector<std::string> printed_;  // the progress and missing lines already printed
  std::size_t missingVersion_ = std::size_t(-1), progressCount_ = std::size_t(-1);
};

}  // namespace hv::viewer
