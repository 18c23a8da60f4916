#include "hv/app/check_command.h"

#include "hv/session/outputs.h"
#include "hv/io/native/scene_loader.h"
#include "hv/util/log.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <iostream>
#include <memory>
#include <new>

namespace hv::app {

namespace {

struct CheckCommandOptions {
  std::string scene;
  bool deep = false;
  bool json = false;
  int threads = 2;
};

}  // namespace

int runChecks(const std::string& scenePath, const CheckOptions& options, Scene& scene, CheckReport& report,
              std::ostream& err) {
  Diagnostics diag;
  // The report names every finding once: the loader's own log lines would repeat them.
  struct Quiet {
    log::Level saved = log::level();
    Quiet() { log::setLevel(log::Level::Off); }
    ~Quiet() { log::setLevel(saved); }
  } quiet;
  try {
    scene = loadScene(scenePath, diag);
  } catch (const InputError& e) {
    err << "error: " << e.what() << "\n";
    return kExitNoScene;
  } catch (const std::filesystem::filesystem_error& e) {
    err << "error: " << scenePath << ": while reading " << e.path1().string() << ": " << e.code().message() << "\n";
    return kExitNoScene;
  } catch (const std::bad_alloc&) {
    err << "error: " << scenePath << ": out of memory while loading the scene\n";
    return kExitNoScene;
  }
  report = checkScene(scene, diag, options);
  return report.problems() ? kExitNotProduced : kExitOk;
}

void addCheckCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand(
      "check",
      "check a scene without rendering it: every source, camera, photograph and mask; exit 0 when nothing "
      "would be left out, 1 when something would be, 2 when the scene cannot be loaded");
  cmd->footer(exitStatusHelp());
  auto o = std::make_shared<CheckCommandOptions>();
  cmd->add_option("scene", o->scene, "scene.json")->required()->check(CLI::ExistingFile);
  cmd->add_flag("--deep", o->deep, "decode every photograph and mask fully (default: headers only)");
  cmd->add_flag("--json", o->json, "print the report as JSON");
  cmd->add_option("--threads", o->threads, "--deep: decoding threads (default 2)")->check(positiveCount());
  cmd->callback([o, &exitCode] {
    CheckOptions options;
    options.deep = o->deep;
    options.threads = o->threads;
    if (o->deep && !o->json)
      options.progress = [](int done, int total) {
        std::cerr << "\rdecoding " << done << "/" << total << " photographs" << (done == total ? "\n" : "")
                  << std::flush;
      };
    Scene scene;
    CheckReport report;
    exitCode = runChecks(o->scene, options, scene, report, std::cerr);
    if (exitCode == kExitNoScene) return;
    if (o->json)
      std::cout << report.json().dump(2) << "\n";
    else
      std::cout << report.text();
  });
}

}  // namespace hv::app
