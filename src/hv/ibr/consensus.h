// Transient filtering at the blend (docs/design.md, step 5, "Consensus"): where the photographs
// that texture a pixel disagree, the ones far from the others' common colour lose their weight, so
// a car or a pedestrian that one photograph shows on an empty street is not smeared over it.
// After the photo-consistency check of Waechter, Moehrle & Goesele 2014 ("Let there be color!"),
// which keeps the views around the largest mode of their colours, here per pixel and soft.
#pragma once

#include <glm/vec3.hpp>

#include <span>

namespace hv::ibr {

// The most samples the filter looks at in one pixel (the shader's arrays; the first ones in
// visiting order).
inline constexpr int kMaxConsensusSamples = 16;

// Colours `colour` (straight, RGB in [0, 1]) with blend weights `weight` (> 0 contribute). With at
// least three contributing samples: start from their component-wise median (unweighted, so that a
// majority wins whatever the weights), take three mean-shift steps with the Gaussian kernel
// g(c) = exp(-|c - m|^2 / (2 spread^2)) weighted by the blend weights, and multiply each weight by
// g(colour_i) / max_j g(colour_j). Fewer samples, or spread <= 0: unchanged.
void consensusWeights(std::span<const glm::dvec3> colour, std::span<double> weight, double spread);

}  // namespace hv::ibr
