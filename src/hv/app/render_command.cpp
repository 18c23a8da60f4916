#include "hv/app/render_command.h"

#include "hv/app/check_command.h"
#include "hv/gpu/gl.h"
#include "hv/image/colormap.h"
#include "hv/image/native/png_write.h"
#include "hv/io/native/crs_proj_string.h"
#include "hv/io/native/georef.h"
#include "hv/io/native/orthophoto_reader.h"
#include "hv/io/native/points_tiles.h"
#include "hv/io/native/scene_loader.h"
#include "hv/render/frame.h"
#include "hv/render/settings.h"
#include "hv/scene/orthophoto.h"
#include "hv/scene/point_normals.h"
#include "hv/scene/scene_scale.h"
#include "hv/scene/terrain_quadtree.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"
#include "hv/util/image_sizes.h"
#include "hv/util/log.h"
#include "hv/viewer/navigation.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <new>
#include <optional>
#include <sstream>

namespace hv::app {

namespace fs = std::filesystem;

namespace {

std::string vec3String(const glm::dvec3& v) {
  std::ostringstream s;
  s << std::fixed << std::setprecision(3) << "(" << v.x << ", " << v.y << ", " << v.z << ")";
  return s.str();
}

void printPoints(const PointCloud& points, const Scene::PointTilesInfo& pointTiles) {
  std::cout << "points     " << points.size();
  if (points.empty()) {
    std::cout << "\n";
    return;
  }
  PointFields fields = points.fields();
  fields.normals = hasNormals(points);  // estimated ones too, though deferred (not made here)
  std::cout << " (" << fields.describe() << "; " << points.chunks.size() << " chunks)\n";
  if (const Scene::PointTilesInfo& t = pointTiles; t.tilesInTileset > 0)
    std::cout << "  3d tiles " << t.tilesRead << " tiles read of " << t.tilesInTileset << " in the tileset, "
              << t.tilesKept << " kept, " << t.tilesFailed << " failed, " << t.bytes << " bytes fetched"
              << (t.budgetLimited ? " (point budget reached)" : "") << "\n";
  const Aabb b = points.bounds();
  std::cout << "  bounds   " << vec3String(b.lo) << " .. " << vec3String(b.hi) << "\n";
  std::string crs = points.crs.empty() ? "(none declared)" : points.crs;
  if (crs.size() > 100) crs = crs.substr(0, 97) + "...";
  std::cout << "  crs      " << crs << "\n";
  if (points.fields().classification) {
    const auto h = points.classHistogram();
    std::cout << "  classes ";
    for (int c = 0; c < 256; ++c)
      if (h[size_t(c)]) std::cout << " " << c << ":" << h[size_t(c)];
    std::cout << "\n";
  }
}

std::string mib(std::size_t bytes) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(1) << double(bytes) / (1024.0 * 1024.0) << " MiB";
  return o.str();
}

// The geometry tiles and the memory the renderer will take with the default settings, one line
// each (estimates: the frame builder's buffers and slot arrays, hv/render/frame_builder.cpp).
void printTilesAndMemory(const Scene& scene) {
  std::cout << "tiles      terrain ";
  if (scene.terrainTiles) {
    std::vector<Camera> cameras;
    for (const Photo& p : scene.photos) cameras.push_back(p.camera);
    const TerrainSelection sel = scene.terrainTiles->select(cameras, kTerrainTolerancePx, kTerrainTriangleBudget);
    std::map<int, int> byLevel;
    for (const TerrainNodeId n : sel.nodes) ++byLevel[TerrainQuadtree::levelOf(n)];
    std::cout << sel.nodes.size() << " (by level:";
    for (const auto& [level, n] : byLevel) std::cout << " " << level << ":" << n;
    std::cout << ")";
  } else {
    std::cout << (scene.terrain.empty() ? "none" : "meshed whole");
  }
  const Scene::BuildingTilesInfo& b = scene.buildingTilesInfo;
  std::cout << "; buildings ";
  if (b.total)
    std::cout << b.loaded << " of " << b.total << " loaded (" << std::setprecision(4) << b.tileSize << " units a side; "
              << b.selection << ")";
  else
    std::cout << "none";
  if (b.streamed) std::cout << "; the renderer streams all " << b.streamed << " per view";
  std::cout << "\n";
  if (!b.note.empty()) std::cout << "  note: buildings: " << b.note << "\n";

  const Mesh* meshes[] = {&scene.terrain, &scene.buildings, &scene.mesh};
  std::size_t vertices = 0, triangles = 0, cpu = 0;
  for (const Mesh* m : meshes) {
    vertices += m->positions.size();
    triangles += m->triangles.size();
    cpu += m->positions.size() * sizeof(glm::dvec3) + m->triangles.size() * sizeof(glm::uvec3) +
           m->triangleTags.size() * sizeof(std::uint32_t);
  }
  const std::size_t gpu =
      vertices * render::GeometryBuffers::kStride * sizeof(float) + triangles * 3 * sizeof(std::uint32_t);
  std::cout << "memory     geometry: " << triangles << " triangles, CPU " << mib(cpu) << ", GPU " << mib(gpu) << "\n";
  // The slot arrays as FrameBuilder::allocateSlots sizes them (default settings; the GL limits
  // apart, printed below).
  const render::RenderSettings settings;
  int w = 1, h = 1;
  for (const Photo& p : scene.photos) w = std::max(w, p.camera.width), h = std::max(h, p.camera.height);
  const int cap = settings.maxSliceSize;
  if (w > cap || h > cap) {
    const double s = std::min(double(cap) / w, double(cap) / h);
    w = std::max(1, int(std::floor(w * s)));
    h = std::max(1, int(std::floor(h * s)));
  }
  const int depth = settings.depthSize;  // one size for every photograph
  const std::size_t image = std::size_t(w) * h * 4, depthBytes = std::size_t(depth) * depth * 4;
  const int slots = std::max(
      1, std::min({settings.maxSlices, int(std::max<std::size_t>(1, settings.memoryBudgetBytes / (image + depthBytes))),
                   std::max(1, int(scene.photos.size()))}));
  std::cout << "memory     images: " << slots << " slots of " << w << "x" << h << " RGBA, GPU " << mib(image * slots)
            << "\n";
  std::cout << "memory     depth maps: " << slots << " of " << depth << "x" << depth << " float, GPU "
            << mib(depthBytes * slots) << " (--depth-size, the same for every photograph)\n";
}

int printInfo(const std::string& scenePath, const Scene& scene, const CheckReport& report);

int runInfo(const std::string& scenePath) {
  // The checks of `histoview check` first (headers only), so a broken photograph is named before
  // the summary; then the summary. An exception anywhere (a file system error on a symlink loop or
  // a name too long, memory) becomes a message naming what was being read, never an abort.
  Scene scene;
  CheckReport report;
  const int loaded = runChecks(scenePath, CheckOptions{}, scene, report, std::cerr);
  if (loaded == kExitNoScene) return kExitNoScene;
  try {
    return printInfo(scenePath, scene, report);
  } catch (const std::filesystem::filesystem_error& e) {
    std::cerr << "error: " << scenePath << ": while reading " << e.path1().string() << ": " << e.code().message()
              << "\n";
  } catch (const std::bad_alloc&) {
    std::cerr << "error: " << scenePath << ": out of memory while summarising the scene\n";
  } catch (const std::exception& e) {
    std::cerr << "error: " << scenePath << ": " << e.what() << "\n";
  }
  return kExitNotProduced;
}

// scene.json's `terrain.height` (a ground plane instead of a DTM), when it has one.
std::optional<double> groundPlaneHeight(const std::string& scenePath) {
  std::ifstream in(scenePath);
  const nlohmann::json doc = nlohmann::json::parse(in, nullptr, false);
  if (doc.is_object() && doc.contains("terrain") && doc["terrain"].is_object() && doc["terrain"].contains("height") &&
      doc["terrain"]["height"].is_number())
    return doc["terrain"]["height"].get<double>();
  return std::nullopt;
}

int printInfo(const std::string& scenePath, const Scene& scene, const CheckReport& report) {
  std::cout << report.text();
  std::cout << "scene      " << scenePath << "\n";
  auto crsText = [](const std::string& crs) {
    try {
      return describeCrs(crs).summary();
    } catch (const InputError& e) {
      return crs + " (" + e.what() + ")";
    }
  };
  std::cout << "crs        " << (scene.crs.empty() ? "(none given)" : crsText(scene.crs) + "; scene frame in metres")
            << "\n";
  if (!scene.crs.empty()) {
    try {  // for a service description's "projection" (docs/services.md, "In the browser")
      if (const std::string p = crsProjString(scene.crs); !p.empty()) std::cout << "  proj4    " << p << "\n";
    } catch (const InputError&) {
    }
  }
  for (const Scene::SourceCrs& s : scene.sourceCrs)
    std::cout << "  " << s.source << (s.transformed ? " from " : " in ") << crsText(s.crs)
              << (s.transformed ? "" : " (taken as it is: the scene declares no crs)") << "\n";
  std::cout << "origin     " << vec3String(scene.origin) << " (render frame = world - origin)\n";
  std::cout << "up         " << vec3String(scene.up) << "  " << upOrigin(scene) << "\n";
  const Aabb b = scene.bounds();
  if (!b.empty()) std::cout << "extent     " << vec3String(b.lo) << " .. " << vec3String(b.hi) << "\n";
  std::cout << "terrain    " << scene.terrain.positions.size() << " vertices, " << scene.terrain.triangles.size()
            << " triangles\n";
  if (scene.terrainTiles) {
    const Scene::TerrainTilesInfo& t = scene.terrainTilesInfo;
    std::cout << "  multi-resolution: " << t.tiles << " tiles of " << t.tileCells << " x " << t.tileCells
              << " cells, levels " << t.coarsestLevel << ".." << t.finestLevel << " of 0.." << t.maxLevel
              << " (screen-space error <= " << t.tolerancePx << " px from the photographs' cameras, budget "
              << t.triangleBudget << " triangles" << (t.budgetLimited ? ", reached" : "") << "); levels read from "
              << t.reads << "\n";
    const render::RenderSettings defaults;
    std::cout << "  streamed per view when rendering: each camera's own cut (screen-space error <= "
              << defaults.geometryTolerancePx << " px, --geometry-tolerance), tiles read by "
              << defaults.geometryThreads << " threads (--geometry-threads) within "
              << (defaults.geometryMemoryBytes >> 20) << " MiB (--geometry-memory), least recently used evicted\n";
  }
  const std::optional<double> ground = groundPlaneHeight(scenePath);
  if (ground) std::cout << "  a ground plane at height " << *ground << " (terrain.height), no DTM\n";
  {
    Diagnostics orthoDiag;
    if (const std::shared_ptr<const Orthophoto> o = loadOrthophoto(scene, orthoDiag))
      std::cout << "  orthophoto " << o->width << " x " << o->height << " px, " << std::setprecision(4)
                << o->metresPerPixelX() << " m per pixel, " << o->bytes() << " bytes (RGBA): " << o->path << "\n";
    for (const std::string& w : orthoDiag.warnings) std::cout << "  orthophoto: " << w << "\n";
  }
  std::cout << "buildings  " << scene.buildings.triangles.size() << " triangles\n";
  printTilesAndMemory(scene);
  std::cout << "mesh       " << scene.mesh.positions.size() << " vertices, " << scene.mesh.triangles.size()
            << " triangles\n";
  printPoints(scene.points, scene.pointTilesInfo);
  std::cout << "photos     " << scene.photos.size() << " (camera spacing " << std::setprecision(4)
            << scene.cameraSpacing() << ")\n";
  const SceneScale scale = sceneScale(scene);
  const viewer::ScaleDefaults defaults = viewer::scaleDefaults(scale.scale);
  std::cout << "scale      " << std::setprecision(4) << scale.scale << " (" << scale.source << "; surface distance "
            << scale.surfaceDistance << ", spacing " << scale.spacing << ", extent " << scale.extent
            << "): viewer speed " << defaults.speed << "/s, step back " << defaults.stepBack << "\n";
  for (const std::string& w : scale.warnings) std::cout << "  outlying " << w << "\n";
  std::map<std::string, int> sizes;
  int distorted = 0, masked = 0, dated = 0;
  for (const auto& p : scene.photos) {
    ++sizes[std::to_string(p.camera.width) + "x" + std::to_string(p.camera.height)];
    distorted += p.camera.distortion && !p.camera.distortion->isIdentity();
    masked += !p.maskPath.empty();
    dated += !p.date.empty();
  }
  for (const auto& [s, n] : sizes) std::cout << "  " << std::setw(5) << n << " x " << s << "\n";
  std::cout << "  distorted " << distorted << ", masked " << masked << ", dated " << dated << "\n";
  int sized = 0, previewed = 0;
  std::string example;
  for (const auto& p : scene.photos)
    if (const auto z = imageSizes(p.imagePath)) {
      ++sized;
      if (z->preview.url.empty()) continue;
      ++previewed;
      if (example.empty())
        example = " (camera '" + p.camera.id + "': " + std::to_string(z->preview.width) + "x" +
                  std::to_string(z->preview.height) + " of " + std::to_string(p.camera.width) + "x" +
                  std::to_string(p.camera.height) + ")";
    }
  if (sized > 0)
    std::cout << "  " << sized << " from IIIF image services, " << previewed << " with a preview fetched first"
              << example << ", then the size the image slot needs\n";
  if (!scene.photos.empty() && scene.buildings.empty() && scene.mesh.empty() && scene.points.empty())
    std::cout << "hint       no buildings, mesh or points: the photographs are projected onto "
              << (scene.terrain.empty() ? "nothing but the sky"
                  : ground              ? "the ground plane"
                                        : "the terrain")
              << " alone, so every facade smears across the ground. Building footprints (scene.json \"buildings\": "
                 "outlines with heights, GeoJSON or any OGR format, or CityJSON) would improve the result a lot"
              << (scene.terrain.empty() ? "; without them, \"terrain\": {\"height\": H} gives a ground plane" : "")
              << "\n";
  try {
    auto ctx = gpu::createHeadlessContext();
    const auto l = gpu::queryLimits();
    std::cout << "GL         " << l.vendor << " | " << l.renderer << " | " << l.version << "\n";
    std::cout << "  MAX_TEXTURE_SIZE " << l.maxTextureSize << ", MAX_ARRAY_TEXTURE_LAYERS " << l.maxArrayTextureLayers
              << ", MAX_TEXTURE_IMAGE_UNITS " << l.maxTextureImageUnits << "\n";
    std::cout << "  MAX_UNIFORM_BLOCK_SIZE " << l.maxUniformBlockSize << ", MAX_VARYING_COMPONENTS "
              << l.maxVaryingComponents << ", MAX_FRAGMENT_UNIFORM_VECTORS " << l.maxFragmentUniformVectors << "\n";
  } catch (const std::exception& e) {
    std::cout << "GL         unavailable: " << e.what() << "\n";
  }
  std::cout << fetchedSummary();
  // What was asked for and could not be read (hv/scene/missing_sources.h), the orthophoto's included.
  for (const std::string& line : scene.missing->lines()) std::cout << "missing    " << line << "\n";
  if (report.problems()) std::cout << report.problems() << " item(s) left out, listed above\n";
  return report.problems() ? kExitLeftOut : kExitOk;
}

struct RenderOptions {
  ViewOptions view;  // view.debug: --debug
  std::string out;
  bool coverage = false;
  std::string method = "blend";
};

// --debug weight:ID / depth:ID: the view rendered again as that debug view (batch: every image
// and depth map already current, only the shading runs again), written as <base>.<name>.png
// (raw 16-bit values) and <base>.<name>-preview.png (the coloured picture).
void writeDebugView(render::Renderer& renderer, const render::DebugSettings& debug, const Camera& cam,
                    const std::string& base) {
  const render::DebugSettings saved = renderer.settings().debug;
  renderer.settings().debug = debug;
  const render::RenderOutput out = renderer.render(cam);
  renderer.settings().debug = saved;
  const std::string name = debug.view == render::DebugView::Weight ? "weight" : "depth";
  writePng16(base + "." + name + ".png", out.debugValues);
  writePng(base + "." + name + "-preview.png", rgbOf(out.rgba));
}

int runRender(const RenderOptions& o) {
  if (o.view.viewsPath.empty() && !o.view.viewpoint.any())
    throw std::invalid_argument(
        "render: give the views to render: --views FILE, --camera ID or --eye X,Y,Z "
        "--look-at X,Y,Z");
  Diagnostics diag;
  const std::unique_ptr<Session> s = openSession(o.view, diag);
  if (o.method == "nearest") s->renderer->settings().blend.method = ibr::BlendMethod::Nearest;
  if (o.method == "no-occlusion") s->renderer->settings().blend.occlusion = false;
  render::DebugSettings debug = s->renderer->settings().debug;
  applyDebugOption(o.view.debug, s->scene, debug);
  const bool counts = debug.view == render::DebugView::Counts;  // the count and loop-length outputs
  fs::create_directories(o.out);
  const int maxTextureSize = gpu::queryLimits().maxTextureSize;
  OutputNames names;  // file names are ours: a view id never names a path (docs/reliability.md)
  int failed = 0;
  for (size_t i = 0; i < s->views.size(); ++i) {
    const Photo& v = s->views[i];
    try {
      const Camera cam = sizeView(v.camera, o.view.size, o.view.viewpoint.fit);
      if (const std::string problem = viewSizeProblem(cam, maxTextureSize); !problem.empty())
        throw std::invalid_argument(problem);
      std::string note;
      const std::string base = (fs::path(o.out) / names.stem(v.camera.id, &note)).string();
      if (!note.empty()) std::cerr << "note: view " << note << "\n";
      const auto result = s->renderer->render(cam, counts);
      const Image8 rgb = rgbOf(result.rgba);
      const Image8 cov = alphaMask(result.rgba);
      writePng(base + ".png", rgb);
      if (o.coverage) writePng(base + ".coverage.png", cov);
      if (counts) {
        writePng16(base + ".count.png", result.counts);
        writePng(base + ".count-preview.png", colorMapCounts(result.counts));
        writePng16(base + ".loop.png", result.loopLengths);
        writePng(base + ".loop-preview.png", colorMapCounts(result.loopLengths));
      }
      if (debug.view == render::DebugView::Weight || debug.view == render::DebugView::DepthMap)
        writeDebugView(*s->renderer, debug, cam, base);
      std::cout << "[" << (i + 1) << "/" << s->views.size() << "] " << base << ".png  (" << cam.width << "x"
                << cam.height << ", " << s->renderer->lastPlan().images.size() << " images, " << std::fixed
                << std::setprecision(0) << s->renderer->stats().lastFrameMs << " ms)\n";
    } catch (const std::bad_alloc&) {
      std::cerr << "error: view '" << v.camera.id << "': out of memory (not written)\n";
      ++failed;
    } catch (const std::exception& e) {
      std::cerr << "error: view '" << v.camera.id << "': " << e.what() << " (not written)\n";
      ++failed;
    }
  }
  std::cout << "wrote " << (s->views.size() - size_t(failed)) << " view(s) to " << o.out << "\n";
  std::cout << fetchedSummary();
  if (const std::string missing = s->scene.missing->summary(); !missing.empty()) std::cout << missing << "\n";
  return exitStatus(diag, size_t(failed));
}

}  // namespace

void addInfoCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("info", "print what a scene contains and the GL limits of the context");
  auto path = std::make_shared<std::string>();
  cmd->add_option("scene", *path, "scene.json")->required()->check(CLI::ExistingFile);
  cmd->footer(exitStatusHelp());
  cmd->callback([path, &exitCode] { exitCode = runInfo(*path); });
}

void addRenderCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("render",
                                 "render views to PNG: every camera of a views file, or the "
                                 "viewpoints given by --camera, --eye/--look-at");
  auto o = std::make_shared<RenderOptions>();
  addViewOptions(*cmd, o->view, false);
  cmd->add_option("--views", o->view.viewsPath, "cameras to render (cameras.json schema; image optional)")
      ->check(CLI::ExistingFile);
  addViewpointOptions(*cmd, o->view.viewpoint);
  cmd->add_option("--out", o->out, "output directory")->required();
  cmd->add_flag("--coverage", o->coverage, "also write <id>.coverage.png (255 where some image contributed)");
  cmd->add_option("--debug", o->view.debug,
                  "count: write <id>.count.png (contributing images) and <id>.loop.png (images the shading loop "
                  "visited), 16-bit raw counts; weight:ID: <id>.weight.png, photograph ID's share of each pixel "
                  "(x 65535); depth:ID: <id>.depth.png, photograph ID's depth map letterboxed (stored depth x "
                  "65535); each with a colour <name>-preview.png")
      ->check(debugValue());
  cmd->add_option("--method", o->method, "blend (default), nearest or no-occlusion")
      ->check(CLI::IsMember({"blend", "nearest", "no-occlusion"}));
  setAction(*cmd, exitCode, [o] { return runRender(*o); });
}

}  // namespace hv::app
