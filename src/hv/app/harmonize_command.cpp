#include "hv/app/harmonize_command.h"

#include "hv/ibr/slice_image.h"
#include "hv/image/image.h"
#include "hv/io/native/scene_loader.h"
#include "hv/scene/native/raycast.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"
#include "hv/util/input_file.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

namespace hv::app {

HarmonizeRun harmonizeScene(const Scene& scene, const ibr::HarmonizeSettings& settings, int sliceSide,
                            Diagnostics& diag, const std::function<void(const std::string&)>& progress,
                            const std::string& pairsCsv) {
  HarmonizeRun run;
  const size_t n = scene.photos.size();
  std::vector<Image8> slices(n);
  std::vector<ibr::OverlapImage> images(n);
  for (size_t i = 0; i < n; ++i) {
    const Photo& p = scene.photos[i];
    images[i].camera = p.camera;
    try {
      const Image8 rgb = readImage(p.imagePath, 3);
      const Image8 mask = p.maskPath.empty() ? Image8{} : readImage(p.maskPath, 1);
      const ibr::SliceSize side{sliceSide, sliceSide};
      slices[i] = ibr::makeSliceImage(p.camera, rgb, mask, side, "camera '" + p.camera.id + "'");
      images[i].texels = &slices[i];
      images[i].uvScale = ibr::sliceLayout(p.camera, side, 0).uvScale;
      ++run.photosUsed;
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (camera '" + p.camera.id + "' keeps its colours)");
    }
    if (progress && ((i + 1) % 10 == 0 || i + 1 == n))
      progress("decoded " + std::to_string(i + 1) + "/" + std::to_string(n) + " photographs");
  }
  Mesh geometry = scene.terrain;
  geometry.append(scene.buildings);
  geometry.append(scene.mesh);
  std::vector<ColourCorrection> corrections(n);
  if (!geometry.empty()) {
    const RayCaster caster(geometry);
    const std::vector<ibr::ColourPair> pairs = ibr::collectColourPairs(images, caster, settings);
    run.pairs = pairs.size();
    if (!pairsCsv.empty()) {
      std::ofstream csv(pairsCsv);
      csv << "a,b,ra,ga,ba,rb,gb,bb,tr,tg,tb\n" << std::setprecision(6);
      for (const ibr::ColourPair& p : pairs)
        csv << p.a << ',' << p.b << ',' << p.ca.r << ',' << p.ca.g << ',' << p.ca.b << ',' << p.cb.r << ',' << p.cb.g
            << ',' << p.cb.b << ',' << p.texture.r << ',' << p.texture.g << ',' << p.texture.b << '\n';
      if (!csv) diag.error(pairsCsv + ": cannot write the pairs");
    }
    if (progress) progress(std::to_string(pairs.size()) + " overlap pairs");
    run.result = ibr::solveColourCorrections(n, pairs, settings);
  } else {
    diag.warn("the scene has no surfaces: no overlaps between the photographs, every correction is the identity");
    run.result = ibr::solveColourCorrections(n, {}, settings);
  }
  for (size_t i = 0; i < n; ++i)
    run.entries.push_back({scene.photos[i].camera.id, run.result.corrections[i], run.result.pairsPerPhoto[i]});
  return run;
}

namespace {

struct HarmonizeOptions {
  std::string scene;
  std::string out = "corrections.json";
  int sliceSide = 1024;
  std::string pairsCsv;
  ibr::HarmonizeSettings settings;
};

int runHarmonize(const HarmonizeOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  Diagnostics diag;
  Scene scene;
  try {
    scene = loadScene(o.scene, diag);
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitNoScene;
  }
  for (const auto& e : diag.errors) std::cerr << "error: " << e << "\n";
  diag.errors.clear();
  const HarmonizeRun run = harmonizeScene(
      scene, o.settings, o.sliceSide, diag, [](const std::string& line) { std::cerr << line << "\n"; }, o.pairsCsv);
  for (const auto& w : diag.warnings) std::cerr << "warning: " << w << "\n";
  for (const auto& e : diag.errors) std::cerr << "error: " << e << "\n";
  std::ofstream f(o.out);
  f << colourCorrectionsJson(run.entries);
  if (!f) {
    std::cerr << "error: " << o.out << ": cannot write\n";
    return kExitNotProduced;
  }
  std::ostringstream m;
  m << std::fixed << std::setprecision(4);
  m << "harmonize: " << run.photosUsed << "/" << scene.photos.size() << " photographs, " << run.pairs
    << " pairs; colour difference (rms) " << run.result.rmsBefore << " -> " << run.result.rmsAfter
    << ", over the inliers " << run.result.inlierRmsBefore << " -> " << run.result.inlierRmsAfter << " ("
    << std::setprecision(1) << std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() << " s)\n";
  std::string monochrome;
  for (size_t i = 0; i < run.result.monochrome.size(); ++i)
    if (run.result.monochrome[i]) monochrome += (monochrome.empty() ? "" : ", ") + run.entries[i].id;
  if (!monochrome.empty())
    m << "monochrome (chroma lost: matched in luma only, solved after the others): " << monochrome << "\n";
  std::cout << m.str() << "wrote " << o.out << " (name it in scene.json: \"colour\": \"" << o.out << "\")\n";
  return exitStatus(diag);
}

}  // namespace

void addHarmonizeCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand(
      "harmonize",
      "estimate each photograph's colour correction (gain and offset per channel) from the overlaps between "
      "the photographs, and write them for scene.json to name (\"colour\")");
  cmd->footer(exitStatusHelp());
  auto o = std::make_shared<HarmonizeOptions>();
  cmd->add_option("scene", o->scene, "scene.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", o->out, "the corrections file to write")->capture_default_str();
  cmd->add_option("--samples", o->settings.samplesPerImage, "rays cast from each photograph")
      ->check(CLI::Range(1, 10000000))
      ->capture_default_str();
  cmd->add_option(
         "--prior", o->settings.prior,
         "with --refine-scale 0 (the least-squares solve): pull of each correction towards the identity, relative "
         "to its pairs' weight: the default holds photographs whose overlaps disagree through the proxy (LOD1 walls, "
         "unmasked cars) near their colours, at the cost of undoing casts only in part; 1e-6 undoes the casts of "
         "overlaps that agree exactly "
         "(docs/design.md)")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option(
         "--refine-scale", o->settings.refineScale,
         "the refinement, in place of the least-squares solve: each photograph's map that most of its pairs agree "
         "with (RANSAC), then --refine-iterations reweightings by Tukey's biweight of this scale (colour "
         "units) with --refine-prior; 0: the least-squares solve (--prior) instead (docs/design.md)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--refine-prior", o->settings.refinePrior, "the pull towards the identity in the refinement")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--refine-iterations", o->settings.refineIterations,
                  "Tukey reweightings after the consensus (0, the default: the consensus alone; on the demo city "
                  "they let the corrections drift, docs/design.md)")
      ->check(CLI::Range(0, 1000))
      ->capture_default_str();
  cmd->add_option("--texture-scale", o->settings.textureScale,
                  "pairs on texture weigh less: weight 1 / (1 + (gradient / this)^2), the gradient in colour per "
                  "texel; 0: every pair weighs the same")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  cmd->add_option("--monochrome-spread", o->settings.monochromeSpread,
                  "a photograph whose colours lie this close to a line (rms, colour units) is monochrome and solved "
                  "after the others, alone; 0: none is")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  cmd->add_option("--pairs-csv", o->pairsCsv,
                  "also write every overlap pair (photograph indices, both colours, the texture) to this CSV file, "
                  "for study");
  cmd->add_option("--size", o->sliceSide, "photographs are sampled at most this many pixels on their longer side")
      ->check(CLI::Range(16, 16384))
      ->capture_default_str();
  setAction(*cmd, exitCode, [o] { return runHarmonize(*o); });
}

}  // namespace hv::app
