#include "hv/viewer/source_status.h"

namespace hv::viewer {
namespace {

std::string count(int n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

SourceStatusLines sourceStatusLines(const SourceStatus& s) {
  SourceStatusLines out;
  for (const SourceProgress& p : s.progress) out.progress.push_back("read " + describeProgress(p));
  if (s.terrainTilesPending > 0)
    out.streaming.push_back(count(s.terrainTilesPending, "terrain tile", "terrain tiles") + " being read");
  if (s.buildingTilesPending > 0)
    out.streaming.push_back(count(s.buildingTilesPending, "building tile", "building tiles") + " being read");
  if (s.buildingTilesRetrying > 0)
    out.streaming.push_back(count(s.buildingTilesRetrying, "building tile", "building tiles") +
                            " failed, to be read again");
  if (s.imagesWaiting > 0)
    out.streaming.push_back(count(s.imagesWaiting, "photograph", "photographs") + " decoding or waiting");
  for (const MissingSource& m : s.missing) out.missing.push_back("missing " + m.kind + ": " + describeMissing(m));
  return out;
}

}  // namespace hv::viewer
