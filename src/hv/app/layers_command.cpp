#include "hv/app/layers_command.h"

#include "hv/gpu/context.h"
#include "hv/gpu/gl.h"
#include "hv/io/native/scene_loader.h"
#include "hv/layers/native/layer_export.h"
#include "hv/layers/native/layer_import.h"
#include "hv/layers/native/openraster.h"
#include "hv/render/layer_peeling.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"

#include <CLI/CLI.hpp>

#include <iomanip>
#include <iostream>
#include <memory>
#include <sstream>

namespace hv::app {

namespace {

struct LayersExportOptions {
  std::string scene;
  std::string image;
  std::string out;
  std::string size;
  bool noPrefill = false;
  double terrainTile = 50.0;
  std::string peeling = "auto";
};

int runLayersExport(const LayersExportOptions& o) {
  Diagnostics diag;
  Scene scene;
  try {
    scene = loadScene(o.scene, diag);
  } catch (const InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitNoScene;
  }
  std::size_t index = scene.photos.size();
  for (std::size_t i = 0; i < scene.photos.size(); ++i)
    if (scene.photos[i].camera.id == o.image) index = i;
  if (index == scene.photos.size()) {
    std::cerr << "error: " << o.scene << ": --image: no photograph with id '" << o.image << "' (the scene has "
              << scene.photos.size() << " photographs; `histoview cameras` lists them)\n";
    return kExitNoScene;
  }
  layers::LayerExportSettings settings;
  settings.prefill = !o.noPrefill;
  settings.terrainTileMetres = o.terrainTile;
  if (!o.size.empty()) {
    try {
      const glm::ivec2 s = parseSize(o.size);
      settings.width = s.x;
      settings.height = s.y;
    } catch (const std::invalid_argument& e) {
      std::cerr << "error: --size: " << e.what() << "\n";
      return kExitNotProduced;
    }
  }
  // Visibility layers: on the GPU (render/layer_peeling.h) when a GL context can be made, the CPU
  // reference finishing from the first cycle; on the CPU alone with --peeling cpu.
  std::unique_ptr<gpu::Context> context;
  std::string peelingNote = "CPU (per-pixel hit lists of the ray casts)";
  if (o.peeling != "cpu") {
    try {
      context = gpu::createHeadlessContext();
      context->makeCurrent();
    } catch (const std::runtime_error& e) {
      if (o.peeling == "gpu") {
        std::cerr << "error: --peeling gpu: no GL context: " << e.what() << "\n";
        return kExitNotProduced;
      }
      peelingNote = std::string("CPU (no GL context for the GPU pass: ") + e.what() + ")";
    }
  }
  // auto: on a software rasteriser (Mesa's llvmpipe or softpipe, SwiftShader) the GL pass was
  // measured 15-21x slower than the CPU reference (docs/performance.md, "Layers"), so the CPU peels.
  if (context && o.peeling == "auto") {
    const std::string renderer = gpu::queryLimits().renderer;
    for (const char* software : {"llvmpipe", "softpipe", "SwiftShader"})
      if (renderer.find(software) != std::string::npos) {
        peelingNote = "CPU (the GL context is a software renderer, " + renderer +
                      ", where the CPU reference is faster; --peeling gpu uses the GL pass)";
        context.reset();
        break;
      }
  }
  render::GpuObjectLayers gpuLayers;
  if (context)
    settings.objectLayers = [&gpuLayers](const Camera& camera, const layers::SceneObjects& objects) {
      gpuLayers = render::peelObjectLayersGl(camera, objects.geometry, objects.objectOfTriangle,
                                             objects.terrainTriangle, objects.objects.size());
      return gpuLayers.layerOfObject;
    };
  layers::LayerExport ex;
  try {
    ex = layers::exportLayers(scene, index, settings, diag);
  } catch (const InputError& e) {
    std::cerr << "error: camera '" << o.image << "': " << e.what() << "\n";
    return kExitNotProduced;
  } catch (const std::runtime_error& e) {  // the GL pass
    std::cerr << "error: camera '" << o.image << "': " << e.what() << "\n";
    return kExitNotProduced;
  }
  if (context) {
    std::ostringstream n;
    n << "GPU (item buffer, " << gpuLayers.queries << " occlusion queries; " << context->description()
      << "): " << gpuLayers.layers << " whole-object layers of " << gpuLayers.objectsSeen << " objects seen";
    if (gpuLayers.stoppedAtCycle) n << ", then a cycle: the layers from there by the CPU reference";
    peelingNote = n.str();
  }
  try {
    layers::writeOpenRaster(o.out, ex.document);
  } catch (const std::runtime_error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitNotProduced;
  }
  for (const auto& w : diag.warnings) std::cerr << "warning: " << w << "\n";
  for (const auto& e : diag.errors) std::cerr << "error: " << e << "\n";
  // The cycles met (docs/layers.md, "Cycles"): split into faces or triangles, which orders them;
  // those triangles cannot order are broken at pixel level, a warning (the exit status stays).
  for (std::size_t i = 0; i < ex.visibility.splits.size(); ++i) {
    const layers::CycleSplit& c = ex.visibility.splits[i];
    const char* what = c.into == layers::CycleSplit::Into::Faces       ? "split into faces"
                       : c.into == layers::CycleSplit::Into::Triangles ? "split into triangles"
                                                                       : "broken at pixel level";
    std::cerr << (c.into == layers::CycleSplit::Into::Pixels ? "warning: camera '" + o.image + "': " : "note: ")
              << "visibility cycle before layer " << c.beforeLayer
              << " (each hides part of the next): " << ex.cycleNames[i] << "; " << c.items << " "
              << (c.into == layers::CycleSplit::Into::Faces       ? "objects"
                  : c.into == layers::CycleSplit::Into::Triangles ? "faces"
                                                                  : "triangles (or objects without faces)")
              << " " << what << " (docs/layers.md)\n";
  }
  std::ostringstream m;
  m << std::fixed << std::setprecision(2);
  m << "layers: camera '" << o.image << "' at " << ex.camera.width << "x" << ex.camera.height << ": "
    << ex.visibility.layers.size() << " visibility layers, " << ex.imageLayers.size() << " image layers, "
    << ex.objects.objects.size() << " objects in the scene, " << ex.visibility.splits.size() << " cycles ("
    << ex.visibility.splitObjects.size() << " objects split into faces, " << ex.visibility.splitFaces.size()
    << " faces into triangles, " << ex.visibility.cycles.size() << " broken at pixel level); " << ex.hits.hits.size()
    << " surfaces on " << ex.hits.pixelCount() << " rays (cast " << ex.castSeconds << " s, peel " << ex.peelSeconds
    << " s, fill " << ex.fillSeconds << " s, " << ex.prefillPhotos << " photographs for the pre-fill)\n";
  std::vector<int> layerOf;
  std::vector<glm::ivec2> sizes;
  for (const auto& l : ex.imageLayers) {
    layerOf.push_back(l.visibilityLayer);
    sizes.push_back({l.box.width(), l.box.height()});
  }
  const layers::LayerTextureMemory mem = layers::layerTextureMemory(layerOf, sizes, ex.camera.width, ex.camera.height);
  m << "texture memory (power-of-two textures): " << mem.subImages << " sub-images " << mem.subImageTexels
    << " texels against " << mem.wholeImageTexels << " for one whole texture per visibility layer ("
    << std::setprecision(1)
    << (mem.wholeImageTexels > 0 ? 100.0 * double(mem.subImageTexels) / double(mem.wholeImageTexels) : 0.0) << " %)\n"
    << std::setprecision(2);
  m << "peeling: " << peelingNote << "\n";
  for (const auto& l : ex.imageLayers)
    m << "  " << l.name << ": " << l.box.width() << "x" << l.box.height() << " at (" << l.box.x0 << ", " << l.box.y0
      << "), " << l.photoPixels << " seen, " << l.prefilledPixels << " pre-filled, " << l.emptyPixels
      << " left empty\n";
  std::cout << m.str() << "wrote " << o.out << "\n";
  return exitStatus(diag);
}

}  // namespace

void addLayersCommand(CLI::App& app, int& exitCode) {
  auto* layers = app.add_subcommand(
      "layers", "layered projective texture maps: a photograph's visibility layers as image-editing layers");
  layers->require_subcommand(1);
  auto* cmd = layers->add_subcommand(
      "export",
      "write a photograph's visibility layers as an OpenRaster file (.ora: GIMP, Krita, MyPaint), the hidden "
      "parts pre-filled from the other photographs");
  cmd->footer(exitStatusHelp());
  auto o = std::make_shared<LayersExportOptions>();
  cmd->add_option("scene", o->scene, "scene.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("out", o->out, "the .ora file to write")->required();
  cmd->add_option("--image", o->image, "the photograph's camera id")->required();
  cmd->add_option("--size", o->size, "the layers' size WxH (the photograph's aspect ratio; default its own size)");
  cmd->add_flag("--no-prefill", o->noPrefill, "leave the hidden parts transparent");
  cmd->add_option("--terrain-tile", o->terrainTile, "side of the terrain's objects (tiles), metres")
      ->check(CLI::Range(1.0, 1e6))
      ->capture_default_str();
  cmd->add_option("--peeling", o->peeling,
                  "visibility layers: gpu (the GL pass: item buffer, occlusion queries; the CPU finishes from the "
                  "first cycle), cpu (the reference, from the ray casts), auto (gpu when a GL context can be made on "
                  "hardware; on a software renderer such as llvmpipe, cpu)")
      ->check(CLI::IsMember({"auto", "gpu", "cpu"}))
      ->capture_default_str();
  setAction(*cmd, exitCode, [o] { return runLayersExport(*o); });
}

}  // namespace hv::app
