// Colour corrections on the demo city (docs/design.md, "Photographs that agree in colour"): the
// estimate from the overlaps (`histoview harmonize`) against the casts the city's generator applied,
// and the held-out views rendered with and without them. In the GL tests because it shares the
// demo city they generate once (the estimate itself is CPU only).
#include "hv/app/harmonize_command.h"
#include "hv/demo/demo_city.h"
#include "hv/eval/metrics.h"
#include "hv/render/renderer.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

#include <filesystem>

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

// Not yet met, so disabled: on the demo city the overlap pairs (street photographs through LOD1
// walls and a 2 m DTM) disagree by 0.12 rms before any correction, and the solve trades gain
// against offset in photographs whose pairs span few colours (gains of 10 to 300 seen); see
// docs/design.md, "Photographs that agree in colour". Run with --gtest_also_run_disabled_tests.
TEST(ColourCorrectionDemo, DISABLED_KnownCastsAreRecovered) {
  const Estimate& e = demoEstimate();
  const Scene& scene = demoCity().scene;
  ASSERT_EQ(e.casts.size(), scene.photos.size());
  ASSERT_EQ(e.run.entries.size(), scene.photos.size());
  const std::vector<glm::dvec3> colours = cityColours();
  int faded = 0, monochrome = 0;
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    const ColourCorrection& h = e.run.entries[i].colour;
    const demo::EraCast cast = e.casts[i];
    EXPECT_GT(e.run.entries[i].pairs, 500) << scene.photos[i].camera.id;
    const std::string what = scene.photos[i].camera.id + " (cast " + std::to_string(int(cast)) + "): gain " +
                             std::to_string(h.gain.r) + " " + std::to_string(h.gain.g) + " " +
                             std::to_string(h.gain.b) + ", offset " + std::to_string(h.offset.r) + " " +
                             std::to_string(h.offset.g) + " " + std::to_string(h.offset.b);
    auto same = [](const glm::dvec3& c) { return c; };
    if (cast == demo::EraCast::None || cast == demo::EraCast::Faded) {
      // A cast affine in each channel (or none): undone, the goal 2/255 per channel.
      EXPECT_LE(worst(h, cast, colours, same), 2.0 / 255.0) << what;
      faded += cast == demo::EraCast::Faded;
    } else {
      // Sepia and cyanotype keep one luma per pixel: the chroma is gone. What a per-channel map
      // can give back is the neutral tone of the right luma; measured on grey colours.
      std::vector<glm::dvec3> greys;
      for (double v = 0.1; v <= 0.8 + 1e-9; v += 0.05) greys.push_back(glm::dvec3(v));
      const double grey = worst(h, cast, greys, same);
      EXPECT_LE(grey, 12.0 / 255.0) << what;
      // And it is much closer than the cast photograph itself was.
      EXPECT_LT(grey, 0.5 * worst(ColourCorrection{}, cast, greys, same)) << what;
      ++monochrome;
      std::cout << "  " << what << ": on greys within " << grey * 255.0 << "/255; luma of city colours within "
                << worst(h, cast, colours, [](const glm::dvec3& c) { return glm::dvec3(luma(c)); }) * 255.0
                << "/255 of the true luma\n";
    }
  }
  EXPECT_EQ(faded, 2);
  EXPECT_EQ(monochrome, 4);
  std::cout << "  " << e.run.pairs << " pairs; rms colour difference " << e.run.result.rmsBefore * 255.0 << " -> "
            << e.run.result.rmsAfter * 255.0 << " /255, inliers " << e.run.result.inlierRmsBefore * 255.0 << " -> "
            << e.run.result.inlierRmsAfter * 255.0 << "\n";
}

}  // namespace
}  // namespace hv::render
