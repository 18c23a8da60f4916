// Image quality metrics for `histoview eval`: PSNR and SSIM restricted to a set of scored pixels.
//
// A rendering only covers part of a view (sky and areas no photograph sees are background), and the
// truth may have its own coverage. Scoring must ignore the uncovered pixels entirely: counting them
// would reward a method for painting the background colour, and letting them into SSIM's local
// statistics would smear background edges into the structure term. So both metrics take a mask,
// one byte per pixel (non-zero = scored), normally the intersection of every method's and the truth's
// coverage so that several methods are compared on the same pixels.
//
// - PSNR: on the RGB channels, peak 255, MSE averaged over the scored pixels and the 3 channels.
// - SSIM: Wang, Bovik, Sheikh, Simoncelli, "Image quality assessment: from error visibility to
//   structural similarity", IEEE TIP 13(4), 2004 — on luma Y = 0.299 R + 0.587 G + 0.114 B in [0, 255],
//   11x11 Gaussian window with sigma 1.5, C1 = (0.01 * 255)^2, C2 = (0.03 * 255)^2, no downsampling.
//   The local statistics are *normalised convolutions* over the scored pixels (window weights times
//   the mask, divided by the sum of those weights), so unscored pixels never enter them; the window is
//   truncated the same way at the image border. Where the whole 11x11 window is scored and inside the
//   image, this is exactly the standard SSIM of that pixel. The map is averaged over scored pixels.
#pragma once

#include "hv/image/image.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hv::eval {

struct Scores {
  // dB. +infinity when the scored pixels are identical (MSE 0); NaN when nothing is scored.
  double psnr = 0.0;
  // Mean SSIM over the scored pixels, in [-1, 1]; NaN when nothing is scored.
  double ssim = 0.0;
  std::size_t scoredPixels = 0;
};

// Scores `b` against `a` (the metrics are symmetric). Both images RGB or RGBA (only the first 3
// channels are used; alpha is ignored) of the same size; `scored` has width * height bytes.
// Throws std::invalid_argument (with the sizes) on a size mismatch or fewer than 3 channels.
Scores compareImages(const Image8& a, const Image8& b, const std::vector<std::uint8_t>& scored);

// PSNR in dB for 8-bit data (peak 255) from a mean squared error; +infinity for mse == 0.
double psnrFromMse(double mse);

// Rec. 601 luma of an RGB(A) image in [0, 255], one value per pixel, row-major, top row first.
std::vector<double> luma(const Image8& image);

// The masked SSIM map of two luma images of width x height (see the file comment): one value per
// pixel, NaN at unscored pixels. Exposed for tests and for debug images; compareImages() averages it.
std::vector<double> ssimMap(const std::vector<double>& lumaA, const std::vector<double>& lumaB, int width,
                            int height, const std::vector<std::uint8_t>& scored);

// Number of non-zero bytes of a mask.
std::size_t countScored(const std::vector<std::uint8_t>& scored);

}  // namespace hv::eval

namespace hv::eval {

// The seam metric: how much sharper the render is than the truth across photograph borders.
// A border is a pair of 4-neighbour pixels, both scored, whose numbers of contributing photographs
// (`counts`, RenderOutput::counts) differ: a photograph's frame, lens domain, mask or occlusion edge
// lies between them. Across each pair, the luma step |L(p) - L(q)| of the render and of the truth;
// `excess` is the mean render step minus the mean truth step, in luma levels (0-255): positive where
// the render shows lines the truth does not have, about 0 when the borders are invisible. Take
// `counts` from one render (e.g. without feathering) to compare settings on the same pixels.
struct BorderSeams {
  double renderStep = 0.0, truthStep = 0.0, excess = 0.0;  // NaN when there is no border pair
  std::size_t pairs = 0;
};
BorderSeams borderSeams(const Image8& render, const Image8& truth, const Image16& counts,
                        const std::vector<std::uint8_t>& scored);

// Temporal flicker of a frame sequence: the mean absolute luma difference (0-255) between
// consecutive frames, over the pixels both frames cover (alpha > 0; RGB frames: every pixel).
// NaN for fewer than two frames or nothing covered. On a static scene with a slowly moving camera,
// the part of it that a setting changes is shimmer (aliasing), the rest is the motion.
double meanFrameDifference(const std::vector<Image8>& frames);

}  // namespace hv::eval
