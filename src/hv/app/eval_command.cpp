#include "hv/app/eval_command.h"

#include "hv/app/common.h"
#include "hv/eval/evaluate.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

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
};

int runEval(const EvalCommandOptions& o) {
  Diagnostics diag;
  if (o.leaveOneOut == !o.view.viewsPath.empty())
    throw std::invalid_argument("eval: give either --views (with --truth) or --leave-one-out");
  if (!o.leaveOneOut && o.truth.empty()) throw std::invalid_argument("eval: --views needs --truth");
  eval::EvalOptions opt;
  opt.truthDir = o.truth;
  opt.leaveOneOut = o.leaveOneOut;
  if (!o.view.size.empty()) opt.size = parseSize(o.view.size);
  opt.methods.clear();
  for (const auto& m : o.methods) opt.methods.push_back(eval::parseMethod(m));
  std::unique_ptr<Session> s = openSession(o.view, diag);
  // Leave-one-out: each photograph is a view, rendered from the others.
  const std::vector<Photo>& views = o.leaveOneOut ? s->scene.photos : s->views;
  const eval::EvalReport report =
      eval::evaluate(*s->renderer, views, opt, diag, [](const std::string& l) { std::cerr << l << "\n"; });
  std::cout << eval::formatTable(report);
  if (!o.json.empty()) {
    std::ofstream f(o.json);
    if (!f) throw std::runtime_error(o.json + ": cannot write");
    f << eval::toJson(report).dump(2) << "\n";
    std::cout << "wrote " << o.json << "\n";
  }
  if (report.rows.empty()) return 2;
  return diag.ok() ? 0 : 1;
}

}  // namespace

void addEvalCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("eval", "render views and score them (PSNR, SSIM) against ground-truth images");
  auto o = std::make_shared<EvalCommandOptions>();
  addViewOptions(*cmd, o->view, false);
  cmd->add_option("--views", o->view.viewsPath, "cameras to render and score (cameras.json schema)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--truth", o->truth, "directory of ground-truth images <id>.png|jpg (+ <id>.coverage.png)")
      ->check(CLI::ExistingDirectory);
  cmd->add_flag("--leave-one-out", o->leaveOneOut,
                "score each photograph rendered from the other photographs (instead of --views/--truth)");
  cmd->add_option("--method", o->methods, "blend, nearest, no-occlusion (comma separated to compare)")
      ->delimiter(',');
  cmd->add_option("--json", o->json, "also write the report as JSON");
  setAction(*cmd, exitCode, [o] { return runEval(*o); });
}

}  // namespace hv::app
