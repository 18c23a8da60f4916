// The viewer panel's Sources section (docs/viewer.md): what the services sent while the scene
// loaded (per source, hv/util/load_progress.h), what the renderer still streams, and what is
// missing (hv/scene/missing_sources.h), as lines of text. Plain C++: the panel draws these lines,
// and the viewer prints them on stdout when they change ("viewer: sources: ...").
#pragma once

#include "hv/scene/missing_sources.h"
#include "hv/util/load_progress.h"

#include <string>
#include <vector>

namespace hv::viewer {

struct SourceStatus {
  std::vector<SourceProgress> progress;  // the reads from services at load
  std::vector<MissingSource> missing;
  int buildingTilesPending = 0, buildingTilesRetrying = 0, terrainTilesPending = 0, imagesWaiting = 0;
};

struct SourceStatusLines {
  std::vector<std::string> progress;  // "read buildings from WFS:…: 5 responses, 12 KB"
  std::vector<std::string> streaming; // "3 building tiles being read", "1 building tile to be read again"
  std::vector<std::string> missing;   // "missing buildings: WFS:…: HTTP error code : 404"
  bool empty() const { return progress.empty() && streaming.empty() && missing.empty(); }
};

SourceStatusLines sourceStatusLines(const SourceStatus& s);

}  // namespace hv::viewer
