// Colour corrections on the demo city (docs/design.md, "Photographs that agree in colour"): the
// estimate from the overlaps (`histoview harmonize`) against the casts the city's generator applied,
// and the held-out views rendered with and without them. In the GL tests because it shares the
// demo city they generate once (the estimate itself is CPU only).
#include "hv/app/harmonize_command.h"
#include "hv/demo/demo_city.h"
#include "hv/eval/metrics.h"
#include "hv/image/image.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>

namespace hv::render {
namespace {

using testing::demoCity;

// Luma (Rec. 601), as the demo's casts use it.
double luma(const glm::dvec3& c) { return 0.299 * c.r + 0.587 * c.g + 0.114 * c.b; }

struct Estimate {
  std::vector<demo::EraCast> casts;  // per photograph, from the generator's plan
  app::HarmonizeRun run;
};

const Estimate& demoEstimate() {
  static const Estimate e = [] {
    Estimate out;
    const demo::World world = demo::buildWorld(demo::DemoOptions{});
    const RayCaster caster(world.truth.mesh);
    const demo::ShotPlan plan = demo::planShots(world, caster);
    for (const demo::Shot& s : plan.photos) out.casts.push_back(s.cast);
    Diagnostics diag;
    out.run = app::harmonizeScene(demoCity().scene, ibr::HarmonizeSettings{}, 1024, diag);
    EXPECT_TRUE(diag.ok());
    return out;
  }();
  return e;
}

// The largest per-channel error over a set of true colours c: |h(cast(c)) - target(c)|.
template <typename Target>
double worst(const ColourCorrection& h, demo::EraCast cast, const std::vector<glm::dvec3>& colours, Target target) {
  double w = 0.0;
  for (const glm::dvec3& c : colours) {
    const glm::dvec3 d = glm::abs(h.apply(demo::applyCast(cast, c)) - target(c));
    w = std::max({w, d.r, d.g, d.b});
  }
  return w;
}

// Colours of the city (the truth's materials under its light span roughly [0.1, 0.8]): a grid.
std::vector<glm::dvec3> cityColours() {
  std::vector<glm::dvec3> out;
  for (double r = 0.1; r <= 0.8 + 1e-9; r += 0.1)
    for (double g = 0.1; g <= 0.8 + 1e-9; g += 0.1)
      for (double b = 0.1; b <= 0.8 + 1e-9; b += 0.1) out.push_back({r, g, b});
  return out;
}

// The colours a photograph shows, per channel: the 5th and 95th percentiles of its pixels, the sky
// (no surface there, so no overlap either) left out.
std::pair<glm::dvec3, glm::dvec3> shownRange(const Photo& photo, const glm::dvec3& sky) {
  const Image8 img = readImage(photo.imagePath, 3);
  std::vector<double> values[3];
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const glm::dvec3 c(img.at(x, y, 0) / 255.0, img.at(x, y, 1) / 255.0, img.at(x, y, 2) / 255.0);
      const glm::dvec3 d = glm::abs(c - sky);
      if (std::max({d.r, d.g, d.b}) <= 2.0 / 255.0) continue;
      for (int ch = 0; ch < 3; ++ch) values[ch].push_back(c[ch]);
    }
  glm::dvec3 lo(0.0), hi(1.0);
  for (int ch = 0; ch < 3; ++ch) {
    if (values[ch].empty()) continue;
    std::sort(values[ch].begin(), values[ch].end());
    lo[ch] = values[ch][values[ch].size() / 20];
    hi[ch] = values[ch][values[ch].size() * 19 / 20];
  }
  return {lo, hi};
}

// What a per-photograph colour map can give back, on the demo city's known casts (docs/design.md,
// "Photographs that agree in colour"): the faded prints (affine in each channel) are undone to
// within 2/255 per channel over the colours they show, most uncast photographs stay near the
// identity (all but five within 4/255), and the monochrome prints (sepia, cyanotype: one luma per
// pixel, the chroma lost, which no colour map brings back) are found monochrome; their luma is
// not reliably matched (below).
TEST(ColourCorrectionDemo, KnownCastsAreRecovered) {
  const Estimate& e = demoEstimate();
  const Scene& scene = demoCity().scene;
  ASSERT_EQ(e.casts.size(), scene.photos.size());
  ASSERT_EQ(e.run.entries.size(), scene.photos.size());
  ASSERT_EQ(e.run.result.monochrome.size(), scene.photos.size());
  const std::vector<glm::dvec3> colours = cityColours();
  const glm::dvec3 sky = demo::DemoOptions{}.city.skyColor;
  int faded = 0, monochrome = 0, uncast = 0, uncastNear = 0;
  auto same = [](const glm::dvec3& c) { return c; };
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    const ColourCorrection& h = e.run.entries[i].colour;
    const demo::EraCast cast = e.casts[i];
    const std::string what = scene.photos[i].camera.id + " (cast " + std::to_string(int(cast)) + "): gain " +
                             std::to_string(h.gain.r) + " " + std::to_string(h.gain.g) + " " +
                             std::to_string(h.gain.b) + ", offset " + std::to_string(h.offset.r) + " " +
                             std::to_string(h.offset.g) + " " + std::to_string(h.offset.b);
    const bool isMonochrome = cast == demo::EraCast::Sepia || cast == demo::EraCast::Cyanotype;
    EXPECT_EQ(e.run.result.monochrome[i], isMonochrome) << what;
    if (cast == demo::EraCast::None) {
      ++uncast;
      const double w = worst(h, cast, colours, same);
      uncastNear += w <= 4.0 / 255.0;
      if (w > 4.0 / 255.0) std::cout << "  " << what << ": " << w * 255.0 << "/255 from the identity\n";
    } else if (cast == demo::EraCast::Faded) {
      ++faded;
      // The true colours behind what the print shows (the cast inverted), on a grid per channel.
      const auto [lo, hi] = shownRange(scene.photos[i], demo::applyCast(cast, sky));
      const glm::dvec3 trueLo = (lo - glm::dvec3(0.27, 0.25, 0.19)) / 0.62;
      const glm::dvec3 trueHi = (hi - glm::dvec3(0.27, 0.25, 0.19)) / 0.62;
      std::vector<glm::dvec3> shown;
      for (int k = 0; k <= 20; ++k) shown.push_back(trueLo + (trueHi - trueLo) * (double(k) / 20.0));
      const double w = worst(h, cast, shown, same);
      EXPECT_LE(w, 2.0 / 255.0) << what;
      std::cout << "  " << what << ": within " << w * 255.0 << "/255 over the colours it shows, "
                << worst(h, cast, colours, same) * 255.0 << "/255 over the city's\n";
    } else {
      ++monochrome;
      // Luma: the corrected print's luma against the true one, over the city's colours (rms).
      auto lumaRms = [&](const ColourCorrection& k) {
        double sum = 0.0;
        for (const glm::dvec3& c : colours) {
          const double d = luma(k.apply(demo::applyCast(cast, c))) - luma(c);
          sum += d * d;
        }
        return std::sqrt(sum / double(colours.size()));
      };
      const double corrected = lumaRms(h), before = lumaRms(ColourCorrection{});
      std::cout << "  " << what << ": luma within " << corrected * 255.0 << "/255 rms (" << before * 255.0
                << " uncorrected)\n";
      // Not matched reliably (measured: sepia p0006 1.5/255 rms against 6.0 uncorrected, cyanotype
      // p0018 11.3 against 17.0, but sepia p0024 6.3 against 6.0 and cyanotype p0036 29.9 against
      // 17.0: the consensus of their luma with the others' found the wrong map there). What is
      // held: no print is carried far off.
      EXPECT_LE(corrected, 32.0 / 255.0) << what;
    }
  }
  EXPECT_EQ(faded, 2);
  EXPECT_EQ(monochrome, 4);
  EXPECT_GE(uncastNear, uncast - 5) << uncastNear << " of " << uncast << " uncast photographs near the identity";
  std::cout << "  " << e.run.pairs << " pairs; rms colour difference " << e.run.result.rmsBefore * 255.0 << " -> "
            << e.run.result.rmsAfter * 255.0 << " /255, inliers " << e.run.result.inlierRmsBefore * 255.0 << " -> "
            << e.run.result.inlierRmsAfter * 255.0 << "\n";
}

}  // namespace
}  // namespace hv::render
