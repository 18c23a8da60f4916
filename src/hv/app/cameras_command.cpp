#include "hv/app/cameras_command.h"

#include "hv/session/session.h"
#include "hv/session/outputs.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"

#include <CLI/CLI.hpp>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace hv::app {

namespace fs = std::filesystem;

namespace {

struct ConvertOptions {
  std::string scene;
  std::string out;
};

int runConvert(const ConvertOptions& o) {
  Diagnostics diag;
  const Scene scene = loadScene(o.scene, diag);  // InputError: printed by setAction, exit code 2
  if (scene.photos.empty()) {
    std::cerr << "error: " << o.scene << ": no camera loaded\n";
    return kExitNoScene;
  }
  const fs::path out = fs::absolute(o.out);
  if (out.has_parent_path()) fs::create_directories(out.parent_path());
  // Image paths relative to the new file, as the native format reads them.
  // A camera whose id or file names are not UTF-8 (a MicMac or COLMAP block named on another
  // system) cannot be written as JSON: it alone is left out, named.
  std::vector<Photo> photos;
  for (Photo p : scene.photos) {
    if (!validUtf8(p.camera.id) || !validUtf8(p.imagePath) || !validUtf8(p.maskPath)) {
      diag.error(o.scene + ": camera '" + safeFileStem(p.camera.id) + "' (image '" + safeFileStem(p.imagePath) +
                 "'): a name that is not valid UTF-8 cannot be written to JSON (left out)");
      continue;
    }
    if (!p.imagePath.empty()) p.imagePath = fs::absolute(p.imagePath).lexically_normal().string();
    if (!p.maskPath.empty()) p.maskPath = fs::absolute(p.maskPath).lexically_normal().string();
    photos.push_back(std::move(p));
  }
  if (photos.empty()) {
    std::cerr << "error: " << o.scene << ": no camera can be written\n";
    return kExitNotProduced;
  }
  std::ofstream f(out, std::ios::binary | std::ios::trunc);
  f << cameraJson(photos, out.parent_path().string()) << "\n";
  f.close();
  if (!f) {
    std::cerr << "error: " << out.string() << ": cannot write\n";
    return kExitNotProduced;
  }
  std::cout << "wrote " << photos.size() << " camera(s) to " << out.string() << " (frame: "
            << (scene.crs.empty() ? std::string("the scene's own") : scene.crs + ", metres") << ")\n";
  return exitStatus(diag);
}

}  // namespace

void addCamerasCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("cameras", "camera collections");
  cmd->require_subcommand(1);
  auto* convert = cmd->add_subcommand(
      "convert", "write a scene's cameras (any format, any CRS) in the scene frame as a native cameras.json");
  auto o = std::make_shared<ConvertOptions>();
  convert->add_option("scene", o->scene, "scene.json")->required()->check(CLI::ExistingFile);
  convert->add_option("-o,--out", o->out, "the cameras.json to write")->required();
  setAction(*convert, exitCode, [o] { return runConvert(*o); });
}

}  // namespace hv::app
