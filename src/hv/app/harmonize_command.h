// `histoview harmonize SCENE -o corrections.json`: each photograph's colour correction, estimated
// from the overlaps between the photographs (hv/ibr/colour_correction.h; docs/design.md,
// "Photographs that agree in colour"), written as the file scene.json may name ("colour").
#pragma once

#include "hv/ibr/colour_correction.h"
#include "hv/io/colour_corrections_json.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <functional>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hv::app {

struct HarmonizeRun {
  std::vector<ColourCorrectionEntry> entries;  // one per photograph, in the scene's order
  ibr::HarmonizeResult result;
  std::size_t pairs = 0;
  int photosUsed = 0;  // decoded and sampled
};

// Decodes every photograph (with its mask) at most `sliceSide` pixels on its longer side, casts
// the rays against the scene's terrain, buildings and mesh, and solves the corrections. A
// photograph that cannot be decoded is reported in `diag` and keeps the identity. `pairsCsv`, when
// given, receives every overlap pair (for study).
HarmonizeRun harmonizeScene(const Scene& scene, const ibr::HarmonizeSettings& settings, int sliceSide,
                            Diagnostics& diag, const std::function<void(const std::string&)>& progress = {},
                            const std::string& pairsCsv = {});

void addHarmonizeCommand(CLI::App& app, int& exitCode);

}  // namespace hv::app
