#include "hv/app/cameras_command.h"

#include "hv/io/cameras_json.h"
#include "hv/io/native/camera_catalog.h"
#include "hv/io/native/scene_loader.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"
#include "hv/util/input_file.h"

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
    if (!p.imagePath.empty() && !isHttpUrl(p.imagePath))
      p.imagePath = fs::absolute(p.imagePath).lexically_normal().string();
    if (!p.maskPath.empty() && !isHttpUrl(p.maskPath))
      p.maskPath = fs::absolute(p.maskPath).lexically_normal().string();
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
  std::cout << "wrote " << photos.size() << " camera(s) to " << out.string()
            << " (frame: " << (scene.crs.empty() ? std::string("the scene's own") : scene.crs + ", metres") << ")\n";
  return exitStatus(diag);
}

struct ExportOptions {
  std::string scene;
  std::string out;
  std::string layer = kDefaultCatalogTable;
};

// A scene's cameras as an OGR point layer (docs/formats.md), for any WFS server to publish.
int runExport(const ExportOptions& o) {
  Diagnostics diag;
  SceneLoadOptions camerasOnly;
  camerasOnly.camerasOnly = true;
  const Scene scene = loadScene(o.scene, diag, camerasOnly);  // InputError: printed by setAction, exit code 2
  for (const std::string& w : diag.warnings) std::cerr << "warning: " << w << "\n";
  for (const std::string& e : diag.errors) std::cerr << "error: " << e << "\n";
  if (scene.photos.empty()) {
    std::cerr << "error: " << o.scene << ": no camera loaded\n";
    return kExitNoScene;
  }
  const fs::path out = fs::absolute(o.out);
  if (out.has_parent_path()) fs::create_directories(out.parent_path());
  // Image paths relative to the layer's folder (read back relative to scene.json's, kept beside it).
  std::vector<Photo> photos = scene.photos;
  auto relative = [&](std::string& image) {
    if (!image.empty() && image.find("://") == std::string::npos)
      image = fs::absolute(image).lexically_normal().lexically_relative(out.parent_path()).string();
  };
  for (Photo& p : photos) relative(p.imagePath), relative(p.maskPath);
  std::size_t written = 0;
  try {
    written = writeOgrCameras(photos, scene.crs, out.string(), o.layer);
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitNotProduced;
  }
  std::cout << "wrote " << written << " camera(s) to " << out.string() << " layer " << o.layer << " ("
            << (scene.crs.empty() ? std::string("no CRS") : scene.crs) << ")\n";
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
  auto* exp = cmd->add_subcommand(
      "export", "write a scene's cameras as a point layer (GeoPackage or GeoJSON) for a WFS server (docs/formats.md)");
  auto e = std::make_shared<ExportOptions>();
  exp->add_option("scene", e->scene, "scene.json")->required()->check(CLI::ExistingFile);
  exp->add_option("--ogr", e->out, "the .gpkg or .geojson file to write (replaced when it exists)")->required();
  exp->add_option("--layer", e->layer, "the layer's name")->capture_default_str();
  setAction(*exp, exitCode, [e] { return runExport(*e); });
}

}  // namespace hv::app
