#include "hv/app/web_export_command.h"
#include "hv/app/web_export_extras.h"

#include "hv/scene/point_normals.h"
#include "hv/session/session.h"
#include "hv/session/checks.h"
#include "hv/session/outputs.h"
#include "hv/image/image.h"
#include "hv/image/native/png_write.h"
#include "hv/io/cameras_json.h"
#include "hv/io/native/scene_loader.h"
#include "hv/io/web_scene.h"
#include "hv/scene/chunks.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <sstream>

#ifndef HV_SOURCE_DIR
#define HV_SOURCE_DIR ""
#endif

namespace hv::app {

namespace fs = std::filesystem;

namespace {

std::string indexName(size_t i) {
  std::ostringstream s;
  s << std::setw(4) << std::setfill('0') << i;
  return s.str();
}

// Copies the page's files (those present) from `from` into `to`; returns how many.
int copyPageFiles(const fs::path& from, const fs::path& to, const std::vector<std::string>& names) {
  int n = 0;
  for (const auto& name : names) {
    if (!fs::exists(from / name)) continue;
    fs::copy_file(from / name, to / name, fs::copy_options::overwrite_existing);
    ++n;
  }
  return n;
}

}  // namespace

int runWebExport(const WebExportOptions& o) {
  Diagnostics diag;
  Scene scene = loadScene(o.scenePath, diag);
  const std::size_t sourcePoints = scene.points.size();
  if (o.maxPoints > 0 && scene.points.size() > o.maxPoints) scene.points = subsampleChunks(scene.points, o.maxPoints);
  const fs::path out(o.out);
  fs::create_directories(out / "images");
  std::vector<Photo> photos;
  bool anyMask = false;
  // Only what was decoded is published: every photograph and mask is decoded under the
  // renderer's loader cap (a small file can decode to gigabytes) and re-encoded, so neither a file
  // that is not an image (a mask path naming /etc/passwd) nor one too large ever reaches the folder.
  const std::size_t cap = render::RenderSettings{}.decodeMemoryBytes;
  for (size_t i = 0; i < scene.photos.size(); ++i) {
    Photo p = scene.photos[i];
    const fs::path image = out / "images" / (indexName(i) + ".jpg");
    const fs::path mask = out / "masks" / (indexName(i) + ".png");
    try {
      for (const std::string* text : {&p.camera.id, &p.imagePath, &p.maskPath})
        if (!validUtf8(*text))
          throw InputError("'" + safeFileStem(*text) + "': not valid UTF-8 (the export's JSON cannot name it)");
      const Image8 colour = decodeImageCapped(p.imagePath, cap, 3);
      Image8 alpha;
      if (!p.maskPath.empty()) {
        alpha = decodeImageCapped(p.maskPath, cap, 1);
        const double aspect = double(colour.width) / colour.height;
        if (std::abs(double(alpha.width) / alpha.height - aspect) > 0.01 * aspect)
          throw InputError(inputMessage(p.maskPath, "mask",
                                        "is " + std::to_string(alpha.width) + "x" + std::to_string(alpha.height) +
                                            ", expected the photograph's aspect ratio (" +
                                            std::to_string(colour.width) + "x" + std::to_string(colour.height) +
                                            ")"));
      }
      writeJpeg(image.string(), colour, o.jpegQuality);
      p.imagePath = image.string();
      if (!alpha.empty()) {
        // Masks stay lossless.
        if (!anyMask) fs::create_directories(out / "masks");
        anyMask = true;
        writePng(mask.string(), alpha);
        p.maskPath = mask.string();
      }
      photos.push_back(std::move(p));
    } catch (const std::exception& e) {
      std::error_code ec;  // nothing half-written stays behind
      fs::remove(image, ec);
      fs::remove(mask, ec);
      const std::string id = validUtf8(p.camera.id) ? p.camera.id : safeFileStem(p.camera.id);
      diag.error("camera '" + id + "': " + e.what() + " (left out of the export)");
    }
  }
  writeWebScene(scene, photos, out.string());
  writeWebSceneExtras(scene, (out / kWebSceneManifest).string(), diag);
  if (!o.viewsPath.empty()) {
    CameraFileOptions viewOpts;
    viewOpts.requireImages = false;
    viewOpts.checkImageFiles = false;
    std::vector<Photo> views;
    for (Photo& v : readCameraFile(o.viewsPath, viewOpts, diag)) {
      if (!validUtf8(v.camera.id)) {
        diag.error(o.viewsPath + ": view '" + safeFileStem(v.camera.id) + "': id is not valid UTF-8 (left out)");
        continue;
      }
      v.imagePath.clear(), v.maskPath.clear();
      views.push_back(std::move(v));
    }
    std::ofstream(out / "views.json") << cameraJson(views, out.string());
  }

  const fs::path source(HV_SOURCE_DIR);
  const fs::path pageDir = o.pageDir.empty() ? source / "web" : fs::path(o.pageDir);
  const fs::path wasmDir = o.wasmDir.empty() ? source / "build-web" / "dist" : fs::path(o.wasmDir);
  const int page = copyPageFiles(pageDir, out,
                                 {"index.html", "histoview.js", "services.js", "services_cameras.js",
                                  "services_layers.js", "services_frame.js", "services_progress.js", "histoview.css", "map.js", "pose.js"});
  const int wasm = copyPageFiles(wasmDir, out, {"histoview_web.js", "histoview_web.wasm", "proj4.js"});

  size_t triangles = scene.terrain.triangles.size() + scene.buildings.triangles.size() + scene.mesh.triangles.size();
  std::cout << "web export in " << out.string() << ": " << triangles << " triangles, ";
  if (sourcePoints > 0) {
    std::cout << scene.points.size();
    if (scene.points.size() < sourcePoints) std::cout << " of " << sourcePoints;
    PointFields fields = scene.points.fields();
    fields.normals = hasNormals(scene.points);
    std::cout << " points (" << fields.describe() << "), ";
  }
  std::cout << photos.size() << " photographs" << (anyMask ? " with masks" : "") << "\n";
  if (page == 0) std::cout << "note: no page copied (no index.html in " << pageDir.string() << ")\n";
  if (wasm < 2)
    std::cout << "note: the WebAssembly build is missing (" << wasmDir.string()
              << "): build it with tools/web-build.sh, then export again\n";
  for (const auto& w : diag.warnings) std::cerr << "warning: " << w << "\n";
  for (const auto& e : diag.errors) std::cerr << "error: " << e << "\n";
  return exitStatus(diag);
}

void addWebExportCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand(
      "web-export",
      "write a static folder for the browser: triangulated meshes, points, cameras, JPEG photographs, the page");
  auto o = std::make_shared<WebExportOptions>();
  cmd->add_option("scene", o->scenePath, "scene.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("out", o->out, "output directory (created)")->required();
  cmd->add_option("--views", o->viewsPath, "view cameras to export as views.json (the page's ?camera= names them)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--page", o->pageDir, "the page's sources (default: the source tree's web/)");
  cmd->add_option("--wasm", o->wasmDir, "the Emscripten build's output (default: the source tree's build-web/dist)");
  cmd->add_option("--jpeg-quality", o->jpegQuality, "JPEG quality for photographs that are not JPEG (default 90)")
      ->check(CLI::Range(1, 100));
  cmd->add_option("--max-points", o->maxPoints,
                  "export at most N points of the scene's cloud, a uniform subsample (default: all)")
      ->check(CLI::PositiveNumber);
  setAction(*cmd, exitCode, [o] { return runWebExport(*o); });
}

}  // namespace hv::app
