// Per-configuration shade programs (shaders/ibr_shade.frag under HV_CONFIG; docs/design.md,
// "Picture quality"). llvmpipe runs both sides of every `if` under an execution mask and only
// loops branch (docs/performance.md), so the code of an option that is off costs as much as when
// it is on. A program linked per configuration makes the weighting, K, the transient filter,
// mipmaps, feathering, layered photographs and the lens models in the frame compile-time
// constants: the code of what is off is not there, and the geometry weights keep their per-pixel
// lists at constant indices (registers, not memory). Programs are cached per key (the defines).
#pragma once

#include "hv/render/frame.h"

#include <string>
#include <vector>

namespace hv::render::gl {

// The defines of frame `f`'s shade program; `candidates` is the longest candidate list a pixel
// walks (the frame's longest tile list, or every image without culling). The geometry weights'
// ranking length is it rounded up to a multiple of 4, at most ibr::kMaxGeometryRank, so a
// pixel ranks exactly the candidates the generic program would. `maxAnisotropy`: the context's
// (gpu::GlLimits; 0 without the extension).
std::vector<std::string> shadeConfigDefines(const Frame& f, int candidates, float maxAnisotropy);

// One key for the cache: the defines joined.
std::string shadeConfigKey(const std::vector<std::string>& defines);

// On by default; off, every frame uses the one generic program (the build before per-
// configuration programs; render_bench --quality compares the two in one process).
void setShadeSpecialisation(bool on);
bool shadeSpecialisation();

}  // namespace hv::render::gl
