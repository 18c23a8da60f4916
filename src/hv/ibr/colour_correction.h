// Photographs that agree in colour (docs/design.md, "Photographs that agree in colour"): one
// correction per photograph (hv::ColourCorrection, a gain and an offset per channel) estimated from
// the overlaps between photographs. Where two photographs see the same surface point, their
// corrected colours should be equal; the corrections are solved by least squares over such pixel
// pairs, robustly (Huber, by iteratively reweighted least squares), with
// one gauge per connected set of photographs: the median photograph keeps its colours.
//
// The pairs: rays cast from a grid of pixels of each photograph (through its lens model) to the
// scene's surfaces; each hit point projected into every other photograph, kept where that
// photograph sees it (a ray cast back from its centre reaches the point: the exact depth test),
// neither sees it at a grazing angle, and both have it fully inside their masks.
//
// Related work: the seam levelling of texrecon (Waechter, Moehrle and Goesele 2014, "Let There Be
// Color!"), which solves per-vertex additive colour adjustments on a texture-atlas mesh; here, one
// global affine correction per photograph, since projective texturing blends whole photographs.
#pragma once

#include "hv/camera/camera.h"
#include "hv/image/image.h"
#include "hv/scene/ray_query.h"
#include "hv/scene/scene.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <vector>

namespace hv::ibr {

struct HarmonizeSettings {
  int samplesPerImage = 6000;        // rays cast from each photograph (a regular grid of its pixels)
  double minCosine = 0.25;           // a point seen at more than ~75 degrees from its normal is left out
  double minAlpha = 0.99;            // both texels fully inside their masks (alpha: bilinear mask)
  double saturated = 254.0 / 255.0;  // a pair with a channel at or above it is left out (clipped)
  // The depth test: the ray back from the other photograph's centre may stop this much short of
  // the point (relative to its distance, plus 1 cm) without the point counting as hidden.
  double occlusionTolerance = 1e-3;
  // A ridge towards the identity, relative to a photograph's pair weight (the gauge is fixed
  // apart, see solveColourCorrections). 0.1 holds a photograph whose overlaps disagree through an
  // inexact proxy (LOD1 walls, a coarse DTM, unmasked cars) near its own colours, where a tiny one
  // lets the solve squeeze its colours towards a constant; on exact overlaps it undoes a cast only
  // in part, which 1e-6 (just enough to keep the equations definite) undoes entirely. Measured in
  // docs/design.md, "Photographs that agree in colour".
  double prior = 0.1;
  double huber = 0.05;  // colour units: pair residuals beyond it are down-weighted
  int iterations = 10;  // reweighting iterations
  // The refinement (refineScale 0: none, the least-squares solve above is the result). It
  // replaces that solve: it starts from each photograph's map onto the others that most of its pairs agree with, within
  // `consensusTolerance` (colour units), found by random sampling (RANSAC) in a few sweeps: two
  // nearby points seen through an inexact proxy rarely agree, so they do not dilute the gains as
  // they do in least squares. `refineIterations` joint reweightings by Tukey's biweight of scale
  // `refineScale` with `refinePrior` may follow; measured on the demo city they let the set drift
  // (docs/design.md), so none by default (and none for the monochrome photographs, on their luma).
  double refineScale = 0.02;
  double refinePrior = 1e-3;
  int refineIterations = 0;
  double consensusTolerance = 3.0 / 255.0;
  // Pairs on texture weigh less: a pair's weight is 1 / (1 + (t / textureScale)^2), t the larger
  // local colour gradient (per texel of the sampled photograph, per channel) of its two colours;
  // a misregistered pair on a flat patch still agrees. 0: every pair weighs the same.
  double textureScale = 0.02;
  // A photograph whose colours lie on a line (rms distance to it at most this, colour units) is
  // monochrome (sepia, cyanotype): no colour map gives its chroma back, so it takes no part in
  // the others' solve (its pairs would pull their colours towards its line) and is solved after,
  // alone, against the others' corrected colours. 0: none is.
  double monochromeSpread = 1.5 / 255.0;
};

// One photograph as the estimation samples it.
struct OverlapImage {
  Camera camera;                   // world frame
  const Image8* texels = nullptr;  // premultiplied RGBA8, mask in alpha (makeSliceImage); null: left out
  glm::dvec2 uvScale{1.0};         // texture uv = pxDistorted * uvScale (sliceLayout)
};

// Two photographs' straight colours, in [0, 1], at one surface point.
struct ColourPair {
  int a = -1, b = -1;
  glm::dvec3 ca{0.0}, cb{0.0};
  // The larger of the two photographs' local colour gradients there (colour per texel of the
  // sampled photograph), per channel: 0 on a flat patch.
  glm::dvec3 texture{0.0};
};

// Every pair of the overlaps (see above). `geometry` answers in the cameras' (world) frame.
std::vector<ColourPair> collectColourPairs(const std::vector<OverlapImage>& images, const RayQuery& geometry,
                                           const HarmonizeSettings& settings);

struct HarmonizeResult {
  std::vector<ColourCorrection> corrections;  // one per photograph (identity without pairs)
  std::vector<int> pairsPerPhoto;             // pairs each photograph is part of
  // Root mean square over the pairs and channels of the colour difference, before and after the
  // corrections, and the same over the pairs the last reweighting kept as inliers (|r| <= huber).
  double rmsBefore = 0.0, rmsAfter = 0.0;
  double inlierRmsBefore = 0.0, inlierRmsAfter = 0.0;
  std::vector<bool> monochrome;  // per photograph: its colours lie on a line (solved after the others)
};

// Minimises, per channel, sum over pairs rho(g_a c_a + o_a - g_b c_b - o_b), rho Huber's (by
// iteratively reweighted least squares), plus a ridge towards the identity; or, by default, the
// refinement that replaces it (HarmonizeSettings::refineScale: each photograph's map that most of
// its pairs agree with). Monochrome photographs are left out of that solve and each solved after,
// alone, against the others. The overlaps fix
// the corrections only up to one common affine map per connected set of photographs (the gauge):
// while solving, the set's mean gain is held at 1 and its mean offset at 0; then the common map
// that brings its median gain to 1 and median offset to 0 is applied, so that the photographs that
// agree keep their colours and the cast ones are brought to them. A photograph without pairs keeps
// the identity.
HarmonizeResult solveColourCorrections(size_t photos, const std::vector<ColourPair>& pairs,
                                       const HarmonizeSettings& settings);

}  // namespace hv::ibr
