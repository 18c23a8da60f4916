#include "hv/eval/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace hv::eval {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string fixed(double v, int decimals) {
  if (std::isnan(v)) return "n/a";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

std::string percent(double fraction) {
  if (std::isnan(fraction)) return "n/a";
  return fixed(100.0 * fraction, 1) + " %";
}

// JSON has neither infinity nor NaN: the first becomes a string the reader can test for, the second
// (nothing scored) null.
nlohmann::json number(double v) {
  if (std::isnan(v)) return nullptr;
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

std::string padRight(const std::string& s, std::size_t width) {
  return s.size() >= width ? s : s + std::string(width - s.size(), ' ');
}

std::string padLeft(const std::string& s, std::size_t width) {
  return s.size() >= width ? s : std::string(width - s.size(), ' ') + s;
}

}  // namespace

std::vector<std::string> orderedMethods(const EvalReport& report) {
  std::vector<std::string> out;
  auto add = [&](const std::string& m) {
    if (std::find(out.begin(), out.end(), m) == out.end()) out.push_back(m);
  };
  for (const auto& m : report.methods) add(m);
  for (const auto& r : report.rows) add(r.method);
  return out;
}

std::map<std::string, MethodMean> methodMeans(const EvalReport& report) {
  struct Sums {
    double psnr = 0, ssim = 0, coverage = 0, scored = 0, seam = 0;
    std::size_t finitePsnr = 0, ssimCount = 0, seamCount = 0;
  };
  std::map<std::string, MethodMean> means;
  std::map<std::string, Sums> sums;
  for (const auto& m : orderedMethods(report)) {
    means[m];
    sums[m];
  }
  for (const auto& r : report.rows) {
    MethodMean& mm = means[r.method];
    Sums& s = sums[r.method];
    ++mm.views;
    s.coverage += r.coverage;
    s.scored += r.scoredFraction;
    if (std::isfinite(r.seam)) {
      s.seam += r.seam;
      ++s.seamCount;
    }
    if (std::isnan(r.psnr) || std::isnan(r.ssim)) {
      ++mm.unscored;
      continue;
    }
    if (std::isinf(r.psnr))
      ++mm.infinitePsnr;
    else {
      s.psnr += r.psnr;
      ++s.finitePsnr;
    }
    s.ssim += r.ssim;
    ++s.ssimCount;
  }
  for (auto& [name, mm] : means) {
    const Sums& s = sums[name];
    if (s.finitePsnr > 0)
      mm.psnr = s.psnr / double(s.finitePsnr);
    else  // every scored view reproduced exactly: the mean of infinities is infinite
      mm.psnr = mm.infinitePsnr > 0 ? std::numeric_limits<double>::infinity() : kNaN;
    mm.ssim = s.ssimCount > 0 ? s.ssim / double(s.ssimCount) : kNaN;
    mm.coverage = mm.views > 0 ? s.coverage / double(mm.views) : kNaN;
    mm.scored = mm.views > 0 ? s.scored / double(mm.views) : kNaN;
    mm.seam = s.seamCount > 0 ? s.seam / double(s.seamCount) : kNaN;
  }
  return means;
}

std::map<std::string, double> meanPsnr(const EvalReport& report) {
  std::map<std::string, double> out;
  for (const auto& [name, mm] : methodMeans(report)) out[name] = mm.psnr;
  return out;
}

std::string formatTable(const EvalReport& report) {
  const std::vector<std::string> methods = orderedMethods(report);
  const auto means = methodMeans(report);

  // The seam column only when some row was measured (eval --border-seams).
  const bool seams = std::any_of(report.rows.begin(), report.rows.end(),
                                 [](const ViewScore& r) { return !std::isnan(r.seam); });
  struct Line {
    std::string view, method, psnr, ssim, coverage, scored, seam;
  };
  std::vector<Line> lines;
  for (const auto& r : report.rows)
    lines.push_back({r.view, r.method, fixed(r.psnr, 2), fixed(r.ssim, 4), percent(r.coverage),
                     percent(r.scoredFraction), fixed(r.seam, 2)});
  const std::size_t viewLines = lines.size();
  for (const auto& m : methods) {
    const MethodMean& mm = means.at(m);
    lines.push_back({"mean", m, fixed(mm.psnr, 2), fixed(mm.ssim, 4), percent(mm.coverage), percent(mm.scored),
                     fixed(mm.seam, 2)});
  }

  const Line header{"view", "method", "PSNR dB", "SSIM", "coverage", "scored", "seam"};
  std::size_t w[7] = {header.view.size(),     header.method.size(), header.psnr.size(), header.ssim.size(),
                      header.coverage.size(), header.scored.size(), header.seam.size()};
  for (const auto& l : lines) {
    w[0] = std::max(w[0], l.view.size());
    w[1] = std::max(w[1], l.method.size());
    w[2] = std::max(w[2], l.psnr.size());
    w[3] = std::max(w[3], l.ssim.size());
    w[4] = std::max(w[4], l.coverage.size());
    w[5] = std::max(w[5], l.scored.size());
    w[6] = std::max(w[6], l.seam.size());
  }
  // Names left-aligned, numbers right-aligned (decimal points line up), two spaces between columns.
  auto render = [&](const Line& l) {
    std::string s = padRight(l.view, w[0]) + "  " + padRight(l.method, w[1]) + "  " + padLeft(l.psnr, w[2]) +
                    "  " + padLeft(l.ssim, w[3]) + "  " + padLeft(l.coverage, w[4]) + "  " +
                    padLeft(l.scored, w[5]);
    if (seams) s += "  " + padLeft(l.seam, w[6]);
    s.erase(s.find_last_not_of(' ') + 1);
    return s + "\n";
  };
  const std::size_t total = w[0] + w[1] + w[2] + w[3] + w[4] + w[5] + 10 + (seams ? w[6] + 2 : 0);

  std::string out = render(header) + std::string(total, '-') + "\n";
  for (std::size_t i = 0; i < viewLines; ++i) out += render(lines[i]);
  if (viewLines > 0) out += std::string(total, '-') + "\n";
  for (std::size_t i = viewLines; i < lines.size(); ++i) out += render(lines[i]);

  for (const auto& m : methods) {
    const MethodMean& mm = means.at(m);
    if (mm.infinitePsnr > 0)
      out += m + ": " + std::to_string(mm.infinitePsnr) + " of " + std::to_string(mm.views) +
             " views with infinite PSNR (identical to the truth), left out of the mean PSNR\n";
    if (mm.unscored > 0)
      out += m + ": " + std::to_string(mm.unscored) + " of " + std::to_string(mm.views) +
             " views with no scored pixel, left out of the mean PSNR and SSIM\n";
  }
  return out;
}

nlohmann::json toJson(const EvalReport& report) {
  nlohmann::json j;
  const std::vector<std::string> methods = orderedMethods(report);
  j["methods"] = methods;
  j["views"] = nlohmann::json::array();
  for (const auto& r : report.rows)
    j["views"].push_back({{"view", r.view},
                          {"method", r.method},
                          {"psnr", number(r.psnr)},
                          {"ssim", number(r.ssim)},
                          {"coverage", number(r.coverage)},
                          {"scored", number(r.scoredFraction)},
                          {"seam", number(r.seam)}});
  j["mean"] = nlohmann::json::object();
  for (const auto& [name, mm] : methodMeans(report))
    j["mean"][name] = {{"psnr", number(mm.psnr)},
                       {"ssim", number(mm.ssim)},
                       {"coverage", number(mm.coverage)},
                       {"scored", number(mm.scored)},
                       {"seam", number(mm.seam)},
                       {"views", mm.views},
                       {"infinite_psnr", mm.infinitePsnr},
                       {"unscored", mm.unscored}};
  return j;
}

}  // namespace hv::eval
