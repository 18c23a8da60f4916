// Seam misalignment between the cameras of a panorama rig, seen on the background sphere.
//
// A panorama is rendered by projecting each rig photograph onto a sphere around the viewer (iTowns'
// backgroundDistance; render::RenderSettings::backgroundSphere). Where two photographs overlap, the
// same content appears twice unless the calibration and the sphere radius are right, and the seam
// shows a jump. This module measures that jump on the CPU, from the cameras (Camera::project, lens
// distortion included) and the photographs, with no renderer:
//
// 1. Overlap. Directions d of a Fibonacci lattice on the unit sphere (González, "Measurement of
//    areas on a sphere using Fibonacci and latitude-longitude lattices", Math. Geosci. 42, 2010,
//    eq. 4), points P = centre + radius d; the pair overlaps where both photographs see some P
//    inside their image.
// 2. A common parametrisation, the *seam patch*: a pinhole camera at the sphere's centre looking at
//    the mean overlap direction, its x axis across the seam (from a's optical axis towards b's), y
//    along it, and a focal length for which one patch pixel covers as much of the sphere as one
//    pixel of the photographs does there (the geometric mean of both photographs' local scales).
//    Each patch pixel's ray meets the sphere at P; P is projected into each photograph, sampled
//    bilinearly (texel centres at i + 0.5, hv/camera/camera.h), giving two grey images of the same
//    place, each with the mask of where its photograph sees.
// 3. Displacement. Templates of a's patch image, centred on a grid over the overlap, are searched in
//    b's over +-searchPx in both directions by normalised cross-correlation (NCC; Lewis, "Fast
//    normalized cross-correlation", Vision Interface 1995, eq. 2), restricted to the pixels both
//    masks keep: the overlaps of a rig are only a few tens of pixels wide, so a window often hangs
//    over the edge of one photograph. The search runs at half resolution over the full range, then
//    at full resolution around the coarse peak; the peak is refined to sub-pixel by a parabola
//    through it and its two neighbours, in x and in y separately.
// 4. A match is *confident* when its peak NCC reaches minNcc, the peak lies inside the searched
//    range (not on its border), no distant peak comes within peakMargin of it (repeated façade
//    elements: windows, balconies), and b's window at the match, searched in a the same way, leads
//    back to the template (the left-right consistency check of stereo matching; Fua, "A parallel
//    stereo algorithm that produces dense depth maps and preserves image features", Machine Vision
//    and Applications 6, 1993).
//
// Sign and units: `shift` is where b's patch shows the content minus where a's shows it, in patch
// pixels (x across the seam, positive from a towards b; y along it). Patch pixels match the
// photographs' resolution at the overlap's centre; `shiftPhotoPx` is the shift's length in pixels of
// photograph a (raw, distorted), through the local Jacobian of patch -> photograph a.
//
// Misalignment has two sources: parallax, because the rig's cameras are not at the sphere's centre
// and the scene is not on the sphere (it vanishes when the sphere radius is the scene's depth), and
// calibration errors. Parallax moves content only along the epipolar direction: the way b's view
// of the content under a template moves when that content is taken nearer or farther along a's ray
// (Hartley & Zisserman, "Multiple View Geometry", 2nd ed., section 9.1). So the part of the shift
// across that direction, `offEpipolarPhotoPx`, does not depend on the scene's depth nor (to first
// order) on the sphere's radius: it is the calibration's own error.
#pragma once

#include "hv/camera/camera.h"
#include "hv/image/image.h"

#include <glm/glm.hpp>

#include <string>
#include <vector>

namespace hv::eval {

struct SeamSettings {
  double sphereRadius = 30.0;  // scene units (metres), around `centre`
  // Template size in patch pixels (odd), narrow across the seam because the overlap is narrow.
  int windowAcross = 15;
  int windowAlong = 41;
  int searchPx = 64;     // displacements searched, +- in x and in y (patch pixels)
  int stepAcross = 12;   // template grid spacing (patch pixels)
  int stepAlong = 32;
  // A template is matched when at least this fraction of its window is seen by a, and a shift is
  // scored when at least this fraction of the window is seen by both.
  double minSupport = 0.6;
  double minContrast = 6.0;  // grey-level standard deviation (0..255) of a template, else skipped (sky)
  double minNcc = 0.8;       // confident match: peak NCC at least this
  double peakMargin = 0.05;  // ... and every peak farther than peakExclusionPx is at least this lower
  int peakExclusionPx = 6;
  double maxRoundTripPx = 1.0;  // ... and b's window there, searched back in a, returns within this
  int latticePoints = 200000;  // Fibonacci directions for the overlap test (~0.45 deg apart)
  int minOverlapPoints = 8;    // fewer lattice points seen by both: no overlap
  int maxPatchPx = 4096;       // the patch's largest side
};

// A grey photograph (1 channel, 0..255) with its camera; the image has the camera's size.
struct SeamPhoto {
  const Camera* camera = nullptr;
  const ImageF* grey = nullptr;
};

struct SeamMatch {
  glm::dvec2 patchPx{0.0};  // template centre in the seam patch
  glm::dvec2 shift{0.0};    // patch pixels: b's position of the content minus a's (x across, y along)
  double shiftPhotoPx = 0.0;  // |shift| in pixels of photograph a
  // The shift's part across the epipolar direction, in pixels of photograph a (|shift| when the two
  // cameras share a centre: no parallax then).
  double offEpipolarPhotoPx = 0.0;
  double ncc = 0.0;
};

// The two photographs resampled into the seam patch (step 2 of the file comment).
struct SeamPatch {
  Camera camera;           // the patch: pinhole at the sphere's centre, no distortion
  ImageF a, b;             // grey, 0 where the photograph does not see
  Image8 maskA, maskB;     // 255 where it does
  int overlapPoints = 0;   // lattice points seen by both photographs
};

struct SeamResult {
  std::string a, b;  // camera ids
  double sphereRadius = 0.0;
  bool overlaps = false;
  double overlapWidthPx = 0.0;  // median over patch rows of the pixels both photographs see
  int templates = 0;            // templates with enough texture and support
  std::vector<SeamMatch> matches;  // the confident ones
  // Over `matches`; NaN when there are none.
  double medianPx = 0.0, maxPx = 0.0;  // |shift| in pixels of photograph a
  double medianOffEpipolarPx = 0.0;    // offEpipolarPhotoPx
  glm::dvec2 medianShift{0.0};         // per component, patch pixels (across, along)
};

// Rec. 601 luma of an RGB(A) or grey image as a 1-channel float image (0..255).
ImageF greyImage(const Image8& image);

// Steps 1-2 for the pair (a, b) on the sphere of settings.sphereRadius around `centre`. When the
// photographs do not overlap, `overlapPoints` is below settings.minOverlapPoints and the images are
// empty. Throws std::invalid_argument (naming the camera) when an image is missing, not 1-channel or
// not the camera's size.
SeamPatch seamPatch(const SeamPhoto& a, const SeamPhoto& b, const glm::dvec3& centre, const SeamSettings& settings);

// Steps 1-4 for one pair.
SeamResult measureSeam(const SeamPhoto& a, const SeamPhoto& b, const glm::dvec3& centre,
                       const SeamSettings& settings);

// Every pair (i < j) of a rig whose photographs overlap, in index order.
std::vector<SeamResult> measureRigSeams(const std::vector<SeamPhoto>& rig, const glm::dvec3& centre,
                                        const SeamSettings& settings);

// One line per result (ids, radius, overlap width, templates, confident, median and max in
// photograph pixels, median off the epipolar direction, median shift across/along), then, per radius,
// the median and 90th percentile over every confident match of |shift| and of its off-epipolar part,
// and the radius with the least median |shift|. Ends with '\n'.
std::string formatSeamTable(const std::vector<SeamResult>& results);

}  // namespace hv::eval
