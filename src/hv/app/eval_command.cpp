#include "hv/app/eval_command.h"

#include "hv/eval/evaluate.h"
#include "hv/eval/metrics.h"
#include "hv/eval/seams.h"
#include "hv/image/image.h"
#include "hv/io/native/scene_loader.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace hv::app {

namespace {

struct EvalCommandOptions {
  ViewOptions view;
  std::string truth;
  std::vector<std::string> methods{"blend"};
  std::string json;
  bool leaveOneOut = false;
  bool borderSeams = false;
  std::string flicker;             // a directory of fly frames
  std::vector<std::string> seams;  // panorama ids: the photographs whose id ends with one form its rig
  std::vector<double> seamRadii{10.0, 30.0, 1000.0};
};

// eval --seams: the misalignment between overlapping cameras of each panorama on the background
// sphere (hv/eval/seams.h), on the CPU; no renderer.
int runSeams(const EvalCommandOptions& o) {
  Diagnostics diag;
  const Scene scene = loadScene(o.view.scenePath, diag);
  std::vector<eval::SeamResult> all;
  for (const std::string& pano : o.seams) {
    std::vector<const Photo*> rig;
    for (const Photo& p : scene.photos)
      if (p.camera.id.ends_with(pano)) rig.push_back(&p);
    if (rig.size() < 2)
      throw std::invalid_argument("eval --seams " + pano + ": " + std::to_string(rig.size()) + " photograph(s) of " +
                                  o.view.scenePath + " have an id ending with it; a panorama needs 2 or more");
    std::vector<ImageF> greys;
    glm::dvec3 centre(0.0);
    for (const Photo* p : rig) {
      greys.push_back(eval::greyImage(readImage(p->imagePath, 3)));
      centre += p->camera.center;
    }
    centre /= double(rig.size());  // the rig's centre stands for the panorama's position
    std::vector<eval::SeamPhoto> photos;
    for (size_t i = 0; i < rig.size(); ++i) photos.push_back({&rig[i]->camera, &greys[i]});
    for (double radius : o.seamRadii) {
      eval::SeamSettings settings;
      settings.sphereRadius = radius;
      const std::vector<eval::SeamResult> r = eval::measureRigSeams(photos, centre, settings);
      all.insert(all.end(), r.begin(), r.end());
    }
  }
  std::cout << eval::formatSeamTable(all);
  return exitStatus(diag, all.empty() ? 1 : 0);
}

// eval --flicker DIR: the temporal flicker of the frames `fly` wrote to DIR (f00000.png, ...), in
// their order: the mean absolute luma difference of consecutive frames (hv/eval/metrics.h).
int runFlicker(const EvalCommandOptions& o) {
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(o.flicker)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name.size() > 5 && name[0] == 'f' && name.ends_with(".png")) files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  if (files.size() < 2)
    throw std::invalid_argument("eval --flicker " + o.flicker + ": " + std::to_string(files.size()) +
                                " frame(s) f*.png there; fly --out writes them, and flicker needs 2 or more");
  std::vector<Image8> frames;
  for (const auto& f : files) frames.push_back(readImage(f.string(), 3));
  const double d = eval::meanFrameDifference(frames);
  std::cout << "flicker  " << d << " luma levels (0-255): mean absolute difference of " << frames.size() - 1
            << " consecutive frame pairs in " << o.flicker << "\n";
  return 0;
}

int runEval(const EvalCommandOptions& o) {
  if (!o.flicker.empty()) {
    if (o.leaveOneOut || !o.view.viewsPath.empty() || !o.seams.empty())
      throw std::invalid_argument("eval: --flicker takes neither --views, --leave-one-out nor --seams");
    return runFlicker(o);
  }
  if (!o.seams.empty()) {
    if (o.leaveOneOut || !o.view.viewsPath.empty())
      throw std::invalid_argument("eval: --seams takes neither --views nor --leave-one-out");
    return runSeams(o);
  }
  Diagnostics diag;
  const ViewpointOptions& vp = o.view.viewpoint;
  const bool given = !o.view.viewsPath.empty() || vp.any();
  if (o.leaveOneOut && (!o.view.viewsPath.empty() || !vp.eye.empty()))
    throw std::invalid_argument(
        "eval: --leave-one-out scores the photographs (pick some with --camera); it "
        "takes neither --views nor --eye");
  if (!o.leaveOneOut && !given)
    throw std::invalid_argument(
        "eval: give either --views or --camera/--eye (with --truth), --leave-one-out or "
        "--seams");
  if (!o.leaveOneOut && o.truth.empty()) throw std::invalid_argument("eval: --views needs --truth");
  eval::EvalOptions opt;
  opt.truthDir = o.truth;
  opt.leaveOneOut = o.leaveOneOut;
  opt.borderSeams = o.borderSeams;
  // The truth images are named as `render` names its outputs.
  auto names = std::make_shared<OutputNames>();
  opt.truthStem = [names](const std::string& id) { return names->stem(id); };
  if (!o.view.size.empty()) opt.size = parseSize(o.view.size);
  opt.methods.clear();
  for (const auto& m : o.methods) opt.methods.push_back(eval::parseMethod(m));
  std::unique_ptr<Session> s = openSession(o.view, diag);
  // Leave-one-out: each photograph is a view, rendered from the others.
  // --camera with --leave-one-out: only those photographs (openSession made them the views).
  const std::vector<Photo>& views = o.leaveOneOut && !vp.any() ? s->scene.photos : s->views;
  // Views that could not be scored are outputs not produced; what the loaders left out before is
  // left out (docs/reliability.md).
  const size_t leftOutBefore = diag.errors.size();
  const eval::EvalReport report =
      eval::evaluate(*s->renderer, views, opt, diag, [](const std::string& l) { std::cerr << l << "\n"; });
  const size_t notScored = diag.errors.size() - leftOutBefore;
  std::cout << eval::formatTable(report);
  if (!o.json.empty()) {
    std::ofstream f(o.json);
    if (!f) throw std::runtime_error(o.json + ": cannot write");
    f << eval::toJson(report).dump(2) << "\n";
    std::cout << "wrote " << o.json << "\n";
  }
  std::cout << fetchedSummary();
  return exitStatus(diag, report.rows.empty() ? std::max<size_t>(notScored, 1) : notScored);
}

}  // namespace

void addEvalCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("eval", "render views and score them (PSNR, SSIM) against ground-truth images");
  auto o = std::make_shared<EvalCommandOptions>();
  addViewOptions(*cmd, o->view, false);
  cmd->add_option("--views", o->view.viewsPath, "cameras to render and score (cameras.json schema)")
      ->check(CLI::ExistingFile);
  addViewpointOptions(*cmd, o->view.viewpoint);
  cmd->add_option("--truth", o->truth, "directory of ground-truth images <id>.png|jpg (+ <id>.coverage.png)")
      ->check(CLI::ExistingDirectory);
  cmd->add_flag("--leave-one-out", o->leaveOneOut,
                "score each photograph rendered from the other photographs (instead of --views/--truth)");
  cmd->add_flag("--border-seams", o->borderSeams,
                "also measure the seams at photograph borders: the mean luma step across them, render minus "
                "truth (one more render per view, without feathering, finds the borders)");
  cmd->add_option("--flicker", o->flicker,
                  "instead of rendering, measure the temporal flicker of the frames fly wrote to this directory "
                  "(mean absolute luma difference of consecutive frames)")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--seams", o->seams,
                  "measure the seams between the overlapping cameras of these panoramas (photographs whose id "
                  "ends with a given id; comma separated) on the background sphere, instead of rendering")
      ->delimiter(',');
  cmd->add_option("--seam-radii", o->seamRadii, "--seams: background sphere radii, scene units (default 10,30,1000)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  cmd->add_option("--method", o->methods, "blend, nearest, no-occlusion (comma separated to compare)")->delimiter(',');
  cmd->add_option("--json", o->json, "also write the report as JSON");
  setAction(*cmd, exitCode, [o] { return runEval(*o); });
}

}  // namespace hv::app
