#include "hv/app/catalog_command.h"

#include "hv/io/cameras_json.h"
#include "hv/io/json_input.h"
#include "hv/io/native/camera_catalog.h"
#include "hv/io/native/scene_loader.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"
#include "hv/util/input_file.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

namespace hv::app {

namespace fs = std::filesystem;

namespace {

struct LoadOptions {
  std::string source;
  std::string connection;
  std::string table = kDefaultCatalogTable;
};

// A native cameras.json has a "cameras" array; a scene.json a "cameras" object naming its source.
bool isNativeCameraFile(const std::string& path) {
  Diagnostics ignored;
  try {
    const nlohmann::json doc = readJsonInput(path, "cameras", ignored);
    return doc.is_object() && doc.contains("cameras") && doc["cameras"].is_array();
  } catch (const std::exception&) {
    return false;  // loadScene below says what is wrong with it
  }
}

int runLoad(const LoadOptions& o) {
  Diagnostics diag;
  checkCatalogTableName(o.table, "--table");
  catalogConnection(o.connection);  // refuses a file path given for the database, before reading anything
  std::vector<Photo> photos;
  std::string crs;
  if (isNativeCameraFile(o.source)) {
    photos = readCameraFile(o.source, CameraFileOptions{}, diag);
  } else {
    SceneLoadOptions camerasOnly;
    camerasOnly.camerasOnly = true;
    Scene scene = loadScene(o.source, diag, camerasOnly);  // InputError: printed by setAction, exit code 2
    photos = std::move(scene.photos);
    crs = scene.crs;
  }
  for (const std::string& w : diag.warnings) std::cerr << "warning: " << w << "\n";
  for (const std::string& e : diag.errors) std::cerr << "error: " << e << "\n";
  if (photos.empty()) {
    std::cerr << "error: " << o.source << ": no camera loaded\n";
    return kExitNoScene;
  }
  // Absolute image paths: the catalog is read from anywhere.
  for (Photo& p : photos) {
    if (!p.imagePath.empty() && !isHttpUrl(p.imagePath))
      p.imagePath = fs::absolute(p.imagePath).lexically_normal().string();
    if (!p.maskPath.empty() && !isHttpUrl(p.maskPath))
      p.maskPath = fs::absolute(p.maskPath).lexically_normal().string();
  }
  const auto t0 = std::chrono::steady_clock::now();
  CatalogWriteResult written;
  try {
    written = writeCameraCatalog(photos, crs, o.connection, o.table);
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitNotProduced;
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::cout << "wrote " << written.rows << " camera(s) to " << redactConnection(o.connection) << " table " << o.table
            << " (SRID " << written.srid << (crs.empty() ? ", no CRS" : ", " + crs) << ") in " << s << " s\n";
  return exitStatus(diag);
}

}  // namespace

void addCatalogCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("catalog", "the camera catalog in PostgreSQL/PostGIS (docs/catalog.md)");
  cmd->require_subcommand(1);
  auto* load = cmd->add_subcommand(
      "load",
      "write a camera collection (a scene.json's cameras in any format, or a cameras.json) into a PostGIS table");
  auto o = std::make_shared<LoadOptions>();
  load->add_option("source", o->source, "scene.json (its cameras) or a native cameras.json")
      ->required()
      ->check(CLI::ExistingFile);
  load->add_option("connection", o->connection, "postgresql://user@host:port/database (or PG:...)")->required();
  load->add_option("--table", o->table, "the table to write (replaced when it exists): name or schema.name")
      ->capture_default_str();
  setAction(*load, exitCode, [o] { return runLoad(*o); });
}

}  // namespace hv::app
