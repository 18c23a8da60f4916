// The `histoview eval` report: per-view, per-method scores, their means, and how they are printed
// (a terminal table) and saved (`--json FILE`).
//
// Conventions:
// - coverage and scoredFraction are fractions in [0, 1] (printed as percentages; saved as fractions).
// - PSNR is +infinity for a view a method reproduces exactly (metrics.h). A mean cannot absorb it, so
//   the mean PSNR is over the finite values and the infinite ones are counted beside; JSON has no
//   infinity, so it is written as the string "inf". When *every* view of a method is infinite, the
//   mean is +infinity too.
// - PSNR/SSIM are NaN for a view where nothing was scored (no common coverage). Such views are left
//   out of the PSNR and SSIM means (counted as `unscored`), printed as "n/a", and saved as null.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace hv::eval {

struct ViewScore {
  std::string view;
  std::string method;
  double psnr = 0.0, ssim = 0.0;
  double coverage = 0.0;        // fraction of the view's pixels this method covers
  double scoredFraction = 0.0;  // fraction scored (covered by every compared method and by the truth)
  // eval --border-seams: mean luma step across photograph borders, render minus truth (metrics.h,
  // borderSeams); NaN when not measured or when the view has no border.
  double seam = std::numeric_limits<double>::quiet_NaN();
};

struct EvalReport {
  std::vector<std::string> methods;  // display order; methods only found in `rows` follow, in order met
  std::vector<ViewScore> rows;       // printed in this order
};

struct MethodMean {
  double psnr = 0.0;      // mean of the finite per-view PSNRs (see the file comment)
  double ssim = 0.0;      // mean of the per-view SSIMs
  double coverage = 0.0;  // mean over all the method's views
  double scored = 0.0;    // mean scored fraction over all the method's views
  double seam = 0.0;      // mean of the finite per-view seams; NaN when none was measured
  std::size_t views = 0;         // rows of this method
  std::size_t infinitePsnr = 0;  // views left out of the PSNR mean because identical
  std::size_t unscored = 0;      // views with nothing scored, left out of the PSNR and SSIM means
};

// Methods in display order: `report.methods`, then any other method of `report.rows`.
std::vector<std::string> orderedMethods(const EvalReport& report);

std::map<std::string, MethodMean> methodMeans(const EvalReport& report);
std::map<std::string, double> meanPsnr(const EvalReport& report);  // per method, as methodMeans().psnr

// One line per row (PSNR in dB with 2 decimals, SSIM with 4, coverage and scored in %, and the seam
// with 2 when some row has one), then a "mean" line per method, and a note per method with infinite or unscored views. Columns aligned; ends with '\n'.
std::string formatTable(const EvalReport& report);

// {"methods": [...],
//  "views": [{"view", "method", "psnr", "ssim", "coverage", "scored", "seam"}, ...],
//  "mean": {method: {"psnr", "ssim", "coverage", "scored", "seam", "views", "infinite_psnr", "unscored"}}}
// with PSNR +infinity as "inf" and NaN as null.
nlohmann::json toJson(const EvalReport& report);

}  // namespace hv::eval
