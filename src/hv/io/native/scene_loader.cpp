#include "hv/io/native/scene_loader.h"

#include "hv/io/colour_corrections_json.h"

#include "hv/io/cameras_json.h"
#include "hv/io/iiif.h"
#include "hv/io/json_input.h"
#include "hv/io/native/camera_catalog.h"
#include "hv/io/native/cityjson.h"
#include "hv/io/native/colmap_cameras.h"
#include "hv/io/native/footprints.h"
#include "hv/io/native/georef.h"
#include "hv/io/native/gltf_model.h"
#include "hv/io/native/itowns_cameras.h"
#include "hv/io/native/las_reader.h"
#include "hv/io/native/mesh_reader.h"
#include "hv/io/native/micmac_cameras.h"
#include "hv/io/native/orthophoto_reader.h"
#include "hv/io/native/ply_points.h"
#include "hv/io/native/points_tiles.h"
#include "hv/io/native/raster.h"
#include "hv/io/native/remote.h"
#include "hv/io/native/scene_missing.h"
#include "hv/io/native/sumo_fcd.h"
#include "hv/io/native/terrain_raster.h"
#include "hv/scene/chunks.h"
#include "hv/scene/native/lod1.h"
#include "hv/scene/orthophoto.h"
#include "hv/scene/point_normals.h"
#include "hv/scene/robust_extent.h"
#include "hv/scene/scene_frame.h"
#include "hv/scene/scene_scale.h"
#include "hv/scene/terrain_quadtree.h"
#include "hv/util/diagnostics.h"
#include "hv/util/image_sizes.h"
#include "hv/util/input_file.h"
#include "hv/util/log.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <numbers>
#include <sstream>
#include <thread>

namespace hv {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Photographs from IIIF image services (docs/services.md): each camera whose image is a service's
// info.json is given the URL of the whole image at the camera's size (never larger than the
// service's image), and its sizes are registered for the renderer (a preview first, then the
// slice's width; hv/util/image_sizes.h). A description that cannot be read, or whose image has another aspect ratio
// than the camera's, leaves that photograph out, named. The descriptions are fetched a few at a time (through the
// response cache).
void resolveIiifImages(std::vector<Photo>& photos, MissingSources& missing, Diagnostics& diag) {
  std::vector<std::size_t> pending;
  for (std::size_t i = 0; i < photos.size(); ++i)
    if (isIiifInfoUrl(photos[i].imagePath)) pending.push_back(i);
  if (pending.empty()) return;
  std::vector<std::string> errors(photos.size());
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t k; (k = next++) < pending.size();) {
      Photo& p = photos[pending[k]];
      const std::string url = p.imagePath;
      try {
        const IiifImageInfo info = parseIiifInfo(readRemote(url, kMaxJsonBytes, "", RemoteCache::Yes), url);
        if (const std::string why = iiifSizeMismatch(info, p.camera.width, p.camera.height); !why.empty())
          throw InputError(inputMessage(url, "", why));
        const IiifRequest request = iiifRequest(info, p.camera.width);
        // The preview: fitted in 256 x 256, or in a quarter of the camera's longer side when that
        // is smaller (a preview near the full size would save nothing).
        const int box = std::min(kIiifPreviewBox, std::max(1, std::max(p.camera.width, p.camera.height) / 4));
        const IiifRequest preview = iiifPreviewRequest(info, box);
        log::debug("camera '" + p.camera.id + "': IIIF " + std::to_string(info.version) + " " +
                   std::to_string(info.width) + "x" + std::to_string(info.height) + ": " + request.url + " (preview " +
                   std::to_string(preview.width) + "x" + std::to_string(preview.height) + ")");
        p.imagePath = request.url;
        // The renderer's image loader fetches the preview first, then the image at its slice's
        // width (hv/util/image_sizes.h); the other readers take imagePath, at the camera's size.
        ImageSizes sizes;
        if (preview.width < request.width) sizes.preview = {preview.url, preview.width, preview.height};
        sizes.atWidth = [info](int width) {
          const IiifRequest r = iiifRequest(info, width);
          return SizedImageUrl{r.url, r.width, r.height};
        };
        registerImageSizes(request.url, std::move(sizes));
      } catch (const std::exception& e) {
        errors[pending[k]] = inputMessage("camera '" + p.camera.id + "'", "image", e.what()) + " (photograph left out)";
        missing.add({"photograph", url, e.what()});
      }
    }
  };
  const std::size_t threads = std::min<std::size_t>(pending.size(), 4);
  std::vector<std::thread> pool;
  for (std::size_t t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (std::thread& t : pool) t.join();
  std::vector<Photo> kept;
  kept.reserve(photos.size());
  for (std::size_t i = 0; i < photos.size(); ++i) {
    if (errors[i].empty())
      kept.push_back(std::move(photos[i]));
    else
      diag.error(errors[i]);
  }
  photos = std::move(kept);
}

std::string sourcePath(const json& doc, const char* key, const std::string& dir, const std::string& file) {
  const json& s = doc.at(key);
  if (!s.is_object() || !s.contains("path") || !s["path"].is_string())
    throw InputError(file + ": " + key + ".path: expected a string path");
  // A local path (relative to scene.json's folder), else a GDAL connection string or URL handed on
  // as it is (docs/services.md, "Paths").
  return resolveSourcePath(s["path"].get<std::string>(), dir);
}

std::optional<std::string> optionalString(const json& obj, const char* key, const std::string& where) {
  if (!obj.contains(key) || obj[key].is_null()) return std::nullopt;
  if (!obj[key].is_string()) throw InputError(where + "." + key + ": expected an attribute name (string) or null");
  return obj[key].get<std::string>();
}

glm::dvec3 vec3Field(const json& doc, const char* key, const std::string& file) {
  const json& v = doc.at(key);
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw InputError(file + ": " + key + ": expected [x, y, z]");
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

// points.normals: "auto" (the file's, else estimated), "estimate" (always), "facing" (the file's,
// else camera-facing sprites). Estimated normals (hv/scene/point_normals.h) are deferred: made when
// first needed (the point pass, an export), not at load. Called after organizeChunks: the estimate
// does not depend on the points' order, and the positions do not change after.
void estimatePointNormals(PointCloud& cloud, const json& entry, const std::string& path) {
  const json mode = entry.contains("normals") ? entry["normals"] : json("auto");
  if (!mode.is_string() || (mode != "auto" && mode != "estimate" && mode != "facing"))
    throw InputError(path + ": points.normals: expected \"auto\", \"estimate\" or \"facing\"");
  if (mode == "estimate" || (mode == "auto" && !cloud.fields().normals)) {
    deferNormals(cloud);
    log::debug("points: normals of " + std::to_string(cloud.size()) + " points to be estimated when first needed");
  }
}

// scene.json `<key>.crs`: the CRS a source is given in, overriding what its file declares; the
// scene CRS it goes into (empty: none, the source is taken as it is).
SourceGeoref sourceGeoref(const json& doc, const char* key, const std::string& sceneCrs, const std::string& file) {
  SourceGeoref g;
  g.sceneCrs = sceneCrs;
  g.field = file + ": " + key + ".crs";
  const json& s = doc.at(key);
  if (s.is_object() && s.contains("crs") && !s["crs"].is_null()) {
    if (!s["crs"].is_string() || s["crs"].get<std::string>().empty())
      throw InputError(g.field + ": expected a CRS string (e.g. \"EPSG:2154\", WKT, a PROJ string) or null");
    g.crs = s["crs"].get<std::string>();
  }
  return g;
}

// For `histoview info`: the CRS a source was given in, if any; transformed when the scene has one.
void recordSource(Scene& scene, const char* name, const std::string& crs) {
  if (!crs.empty()) scene.sourceCrs.push_back({name, crs, !scene.crs.empty()});
}

// Without a scene CRS nothing is transformed: sources that declare different CRSs then do not
// line up, which the user should hear once rather than discover in the render.
void warnUnrelatedFrames(const Scene& scene, bool crsDeclared, const std::string& path, Diagnostics& diag) {
  if (crsDeclared || scene.sourceCrs.size() < 2) return;
  bool differ = false;
  for (const Scene::SourceCrs& s : scene.sourceCrs) differ = differ || !equivalentCrs(s.crs, scene.sourceCrs[0].crs);
  if (!differ) return;
  std::string list;
  for (const Scene::SourceCrs& s : scene.sourceCrs) {
    std::string crs = s.crs.size() > 40 ? s.crs.substr(0, 37) + "..." : s.crs;
    list += (list.empty() ? "" : ", ") + s.source + " " + crs;
  }
  diag.warn(inputMessage(path, "crs",
                         "none declared, so the sources are taken as they are, yet they declare different CRSs (" +
                             list + "); declare the scene's crs to bring them into one frame"));
}

// Brings the photographs' cameras from `cameraCrs` into the scene frame; a camera PROJ cannot
// transform is reported and left out. A geocentric scene frame (MicMac's ECEF without a scene CRS)
// gets the local vertical at the cameras as its `up` unless scene.json declares one.
void georeferenceCameras(Scene& scene, const std::string& cameraCrs, bool upDeclared, const std::string& path,
                         Diagnostics& diag) {
  std::optional<GeoTransform> made;
  try {
    made.emplace(cameraCrs, scene.crs, diag);
  } catch (const InputError&) {
    scene.photos.clear();  // cameras in an unknown frame are no cameras at all
    throw;
  }
  const GeoTransform& transform = *made;
  std::vector<Photo> kept;
  double worstDefect = 0.0;
  for (Photo& p : scene.photos) {
    try {
      double defect = 0.0;
      p.camera = transform.camera(p.camera, &defect);
      worstDefect = std::max(worstDefect, defect);
      kept.push_back(std::move(p));
    } catch (const InputError& e) {
      diag.error(path + ": cameras: camera '" + p.camera.id + "': " + e.what() + " (camera skipped)");
    }
  }
  scene.photos = std::move(kept);
  log::debug("cameras: " + transform.source().summary() + " -> " + transform.scene().summary() +
             ", largest non-orthogonality of the local Jacobian " + std::to_string(worstDefect));
  if (transform.scene().geocentric && !upDeclared && !scene.photos.empty()) {
    glm::dvec3 mean(0.0);
    for (const Photo& p : scene.photos) mean += p.camera.center / double(scene.photos.size());
    scene.up = ecefUp(mean);
  }
}

// Brings a point cloud into the scene frame (hv/io/georef.h): from its own CRS (the file's, or
// points.crs) or, when it declares none, from the scene CRS, whose units still become metres
// (the Autzen sample is in international feet). Normals turn with the local Jacobian at the
// cloud's centre.
void georeferencePoints(PointCloud& cloud, const SourceGeoref& georef, const std::string& file, Diagnostics& diag) {
  if (cloud.empty()) return;
  const GeoTransform transform = sourceTransform(georef, sourceCrsOf(georef, cloud.crs), file, diag);
  if (transform.isIdentity()) return;
  const glm::dvec3 centre = cloud.bounds().center();
  glm::dmat3 turn = transform.jacobian(centre);
  transform.points(cloud.positions);
  if (!cloud.normals.empty()) {
    turn = glm::inverse(glm::transpose(turn));  // normals transform by J^-T
    for (glm::vec3& n : cloud.normals) {
      const glm::dvec3 m = turn * glm::dvec3(n);
      const double len = glm::length(m);
      if (len > 0.0) n = glm::vec3(m / len);
    }
  }
  log::debug("points: " + file + ": " + transform.source().summary() + " -> " + transform.scene().summary());
}

// A point cloud by its extension: LAS (.las; .laz is refused with advice) or PLY.
PointCloud readPointFile(const std::string& p) {
  std::string ext = fs::path(p).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".las" || ext == ".laz") return readLas(p);
  if (ext == ".ply") return readPlyPoints(p);
  throw InputError(inputMessage(p, "points.path", "expected a .las or .ply file"));
}

// scene.json "points" naming a 3D Tiles tileset (hv/io/native/points_tiles.h): `tileset`, or a
// `path` ending in tileset.json; `tolerance` (pixels) and `budget` (points) only with a tileset.
std::optional<PointTilesetRequest> pointTilesetRequest(const json& doc, const std::string& dir,
                                                       const std::string& sceneCrs, const std::string& path) {
  const json& e = doc.at("points");
  if (!e.is_object()) return std::nullopt;  // refused as a point file's entry, below
  const bool tileset = e.contains("tileset");
  if (tileset && e.contains("path"))
    throw InputError(path + ": points: expected either a path (a point file) or a tileset (3D Tiles), not both");
  if (tileset && !e["tileset"].is_string())
    throw InputError(path + ": points.tileset: expected the URL or path of a 3D Tiles tileset.json (string)");
  const std::string url = tileset                                       ? e["tileset"].get<std::string>()
                          : e.contains("path") && e["path"].is_string() ? e["path"].get<std::string>()
                                                                        : std::string();
  if (!tileset && !isTilesetPath(url)) {
    for (const char* key : {"tolerance", "budget"})
      if (e.contains(key))
        throw InputError(path + ": points." + key + ": only with a 3D Tiles tileset (points.tileset)");
    return std::nullopt;
  }
  PointTilesetRequest r;
  r.url = resolveSourcePath(url, dir);
  r.georef = sourceGeoref(doc, "points", sceneCrs, path);
  if (e.contains("tolerance")) {
    if (!e["tolerance"].is_number() || !std::isfinite(e["tolerance"].get<double>()) || e["tolerance"].get<double>() < 0)
      throw InputError(path + ": points.tolerance: expected a screen-space error in pixels (a number >= 0), got " +
                       e["tolerance"].dump());
    r.tolerancePx = e["tolerance"].get<double>();
  }
  if (e.contains("budget")) {
    if (!e["budget"].is_number_unsigned() || e["budget"].get<std::uint64_t>() == 0)
      throw InputError(path + ": points.budget: expected the most points to read (an integer > 0), got " +
                       e["budget"].dump());
    r.budget = std::size_t(e["budget"].get<std::uint64_t>());
  }
  return r;
}

// Points from a 3D Tiles tileset, once the cameras are known (their screen-space error chooses
// the tiles), then as a point file's: georeferenced, normals, chunks.
void loadPointTilesetIntoScene(Scene& scene, const PointTilesetRequest& request, const json& entry,
                               const std::string& path, Diagnostics& diag) {
  try {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<Camera> cameras;
    for (const Photo& p : scene.photos) cameras.push_back(p.camera);
    scene.points = loadPointTileset(request, cameras, diag, &scene.pointTilesInfo);
    for (const auto& [url, message] : scene.pointTilesInfo.failed) noteMissing(scene, "point tile", url, message);
    if (!scene.crs.empty()) georeferencePoints(scene.points, request.georef, request.url, diag);
    recordSource(scene, "points", scene.points.crs);
    organizeChunks(scene.points);
    estimatePointNormals(scene.points, entry, path);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    log::debug("points: " + request.url + ": " + std::to_string(scene.points.size()) + " points, " +
               std::to_string(scene.points.chunks.size()) + " chunks, " + std::to_string(s) + " s");
  } catch (const InputError& e) {
    scene.points = PointCloud{};
    diag.error(std::string(e.what()) + " (points left out)");
    noteMissing(scene, "points", request.url, e.what());
  }
}

// The keys of scene.json (docs/formats.md). A key this version does not read is most often a
// misspelt one ("terain"): the scene would load without what it names, so it is refused instead,
// with the nearest known key. "layers" is read by hv/layers/native/layer_import.h (readLayerFiles).
void refuseUnknownKeys(const json& doc, const std::string& path) {
  static const std::vector<std::string> kTop = {"crs",    "origin",  "up",     "terrain", "buildings", "mesh",
                                                "points", "cameras", "colour", "layers",  "traffic",   "orthophoto"};
  static const std::vector<std::pair<std::string, std::vector<std::string>>> kSources = {
      {"terrain", {"path", "crs", "height"}},
      {"buildings", {"path", "crs", "height", "base", "top", "valid_from", "valid_to"}},
      {"mesh", {"path", "crs"}},
      {"points", {"path", "tileset", "crs", "normals", "tolerance", "budget"}},
      {"cameras", {"path", "format", "crs", "images", "orientations", "calibration", "postgis", "table", "layer"}},
      {"traffic", {"fcd", "csv", "crs", "offset", "models"}},
      {"orthophoto", {"path", "resolution", "crs"}}};
  std::vector<std::string> bad;
  for (const std::string& m : unknownKeys(doc, kTop)) bad.push_back(m);
  for (const auto& [source, keys] : kSources)
    if (doc.contains(source))
      for (const std::string& m : unknownKeys(doc[source], keys)) bad.push_back(source + ": " + m);
  if (bad.empty()) return;
  std::string list;
  for (const std::string& b : bad) list += (list.empty() ? "" : "; ") + b;
  throw InputError(path + ": " + list +
                   " (this version reads only the keys of docs/formats.md; the scene is not loaded)");
}

// scene.json "traffic.models" (docs/traffic.md): a glTF file per vehicle class, {"car": "car.gltf",
// "bus": ...}. A file that cannot be read is reported, naming it and what was expected, and its
// class is drawn as the built-in box with wheels; a malformed entry throws (the traffic left out).
std::shared_ptr<const VehicleModels> loadVehicleModels(const json& m, const std::string& dir, const std::string& path,
                                                       Diagnostics& diag) {
  std::string classes;
  for (int c = 0; c < kVehicleClasses; ++c) classes += std::string(c ? ", " : "") + vehicleClassName(VehicleClass(c));
  if (!m.is_object())
    throw InputError(path + ": traffic.models: expected an object of glTF paths by vehicle class (" + classes + ")");
  auto models = std::make_shared<VehicleModels>();
  for (const auto& [key, value] : m.items()) {
    int cls = -1;
    for (int c = 0; c < kVehicleClasses; ++c)
      if (key == vehicleClassName(VehicleClass(c))) cls = c;
    if (cls < 0) throw InputError(path + ": traffic.models." + key + ": expected one of the classes " + classes);
    if (!value.is_string() || value.get<std::string>().empty())
      throw InputError(path + ": traffic.models." + key + ": expected a string path to a glTF file");
    const fs::path rel = value.get<std::string>();
    const std::string file = (rel.is_absolute() ? rel : fs::path(dir) / rel).lexically_normal().string();
    try {
      models->byClass[std::size_t(cls)] = std::make_shared<const VehicleModel>(readGltfVehicle(file));
      log::debug("traffic: " + key + ": " + file + ": " +
                 std::to_string(models->byClass[std::size_t(cls)]->vertices.size() / 3) + " triangles");
    } catch (const InputError& e) {
      diag.error("traffic.models." + key + ": " + e.what() + " (the " + key +
                 " class drawn as the built-in box with wheels)");
    }
  }
  return models;
}

// scene.json "orthophoto" (docs/formats.md): read over the terrain's extent. Throws InputError
// naming the path and the field; the caller leaves it out.
std::shared_ptr<const Orthophoto> readSceneOrthophoto(const Scene& scene, const json& doc, const std::string& dir,
                                                      const std::string& path, Diagnostics& diag) {
  const json& o = doc["orthophoto"];
  OrthophotoRequest r;
  r.path = sourcePath(doc, "orthophoto", dir, path);
  r.field = "orthophoto.path";
  if (o.contains("resolution")) {
    if (!o["resolution"].is_number() || !(o["resolution"].get<double>() > 0.0) ||
        !std::isfinite(o["resolution"].get<double>()))
      throw InputError(path + ": orthophoto.resolution: expected metres per pixel (a number > 0), got " +
                       o["resolution"].dump());
    r.resolution = o["resolution"].get<double>();
  }
  if (o.contains("crs")) {
    if (!o["crs"].is_string() || o["crs"].get<std::string>().empty())
      throw InputError(path + ": orthophoto.crs: expected a CRS string (\"EPSG:2154\", WKT, a PROJ string), got " +
                       o["crs"].dump());
    r.crs = o["crs"].get<std::string>();
  }
  r.sceneCrs = scene.crs;
  const Aabb extent =
      scene.terrainTiles ? scene.terrainTiles->tile(TerrainQuadtree::root()).bounds : scene.terrain.bounds();
  if (extent.empty())
    throw InputError(inputMessage(r.path, "orthophoto", "no terrain to drape it on (expected a terrain source)"));
  r.minX = extent.lo.x, r.minY = extent.lo.y, r.maxX = extent.hi.x, r.maxY = extent.hi.y;
  const auto t0 = std::chrono::steady_clock::now();
  auto ortho = std::make_shared<Orthophoto>(readOrthophoto(r, diag));
  ortho->path = o["path"].get<std::string>();
  log::debug("orthophoto: " + r.path + ": " +
             std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()) + " s");
  return ortho;
}

// scene.json "traffic" (docs/traffic.md): SUMO FCD (`fcd`) or CSV (`csv`) trajectories; `offset`
// [dx, dy] added to the file's x, y (SUMO's network coordinates are the projected ones plus the
// network's netOffset: give minus it), then `crs` (default: the scene frame as it is, like a mesh)
// through PROJ. Headings turn with the CRS: each vehicle's by the Jacobian at its first sample.
void loadTraffic(Scene& scene, const json& doc, const std::string& dir, const std::string& path, Diagnostics& diag) {
  const json& t = doc["traffic"];
  if (!t.is_object()) throw InputError(path + ": traffic: expected an object with \"fcd\" or \"csv\"");
  const bool fcd = t.contains("fcd"), csv = t.contains("csv");
  if (fcd == csv)
    throw InputError(path +
                     ": traffic: expected exactly one of \"fcd\" (SUMO floating car data) and \"csv\" "
                     "(t,id,x,y,angle,type trajectories)");
  const char* key = fcd ? "fcd" : "csv";
  if (!t[key].is_string() || t[key].get<std::string>().empty())
    throw InputError(path + ": traffic." + key + ": expected a string path");
  const fs::path rel = t[key].get<std::string>();
  const std::string file = (rel.is_absolute() ? rel : fs::path(dir) / rel).lexically_normal().string();
  glm::dvec2 offset(0.0);
  if (t.contains("offset")) {
    const json& o = t["offset"];
    if (!o.is_array() || o.size() != 2 || !o[0].is_number() || !o[1].is_number())
      throw InputError(path + ": traffic.offset: expected [dx, dy] in metres, got " + o.dump());
    offset = {o[0].get<double>(), o[1].get<double>()};
  }
  const SourceGeoref georef = sourceGeoref(doc, "traffic", scene.crs, path);
  Trajectories traj = fcd ? readSumoFcd(file, diag) : readTrajectoriesCsv(file, diag);
  for (Trajectory& v : traj.vehicles)
    for (TrajectorySample& s : v.samples) s.xy += offset;
  if (!georef.crs.empty() && !scene.crs.empty()) {
    const GeoTransform transform = sourceTransform(georef, georef.crs, file, diag);
    if (!transform.isIdentity())
      for (Trajectory& v : traj.vehicles) {
        const glm::dvec3 first(v.samples.front().xy, 0.0);
        glm::dmat3 J = transform.jacobian(first);
        // Degrees of longitude and latitude are not the same length: the angle is measured on the
        // ground, so each axis's image counts by its direction only.
        if (transform.source().geographic)
          for (int axis = 0; axis < 2; ++axis) J[axis] = glm::normalize(J[axis]);
        for (TrajectorySample& s : v.samples) {
          const glm::dvec2 f = forwardFromSumoAngle(s.angleDeg);
          const glm::dvec3 g = J * glm::dvec3(f, 0.0);
          s.angleDeg = std::atan2(g.x, g.y) * 180.0 / std::numbers::pi;
          s.xy = glm::dvec2(transform.point(glm::dvec3(s.xy, 0.0)));
        }
      }
    recordSource(scene, "traffic", georef.crs);
  }
  log::debug("traffic: " + file + ": " + std::to_string(traj.vehicles.size()) + " vehicles, " +
             std::to_string(traj.samples()) + " samples, t in [" + std::to_string(traj.tBegin) + ", " +
             std::to_string(traj.tEnd) + "] s");
  if (t.contains("models")) traj.models = loadVehicleModels(t["models"], dir, path, diag);
  scene.trafficPath = file;
  scene.traffic = std::make_shared<const Trajectories>(std::move(traj));
}

// The buildings' base heights on a DTM read as tiles: the finest level within
// kTerrainPyramidCells samples, read whole (from the pyramid or an overview, never the full
// resolution of a large raster).
Heightfield buildingBaseHeights(const TerrainQuadtree& tree) {
  const TerrainGrid& g = tree.grid();
  int level = tree.maxLevel();
  auto samples = [&](int l) {
    const std::uint64_t s = std::uint64_t(tree.step(l));
    return (std::uint64_t(g.cols - 1) / s + 1) * (std::uint64_t(g.rows - 1) / s + 1);
  };
  while (level > 0 && samples(level) > kTerrainPyramidCells) --level;
  return tree.levelHeightfield(level);
}

struct PendingBuildings {
  std::string path;
  FootprintFields fields;
  SourceGeoref georef;
  std::size_t sourceCrsAt = 0;  // where in Scene::sourceCrs the buildings' CRS goes (the order of scene.json)
};

// Whether a photograph may see anything of `box` (world) closer than `reach`: conservative (a
// plane test on the box's corners against the pinhole frustum's sides; a distorted lens only by
// distance, a fish-eye may see behind its axis).
bool cameraMaySee(const Camera& camera, const Aabb& box, double reach) {
  const glm::dvec3 nearest = glm::clamp(camera.center, box.lo, box.hi);
  if (glm::length(nearest - camera.center) > reach) return false;
  if (camera.distortion && !camera.distortion->isIdentity()) return true;
  glm::dvec3 corners[8];
  for (int c = 0; c < 8; ++c)
    corners[c] = camera.camFromWorld *
                 (glm::dvec3(c & 1 ? box.hi.x : box.lo.x, c & 2 ? box.hi.y : box.lo.y, c & 4 ? box.hi.z : box.lo.z) -
                  camera.center);
  const glm::dmat3 k = camera.camFromPix();
  const glm::dvec3 rays[4] = {k * glm::dvec3(0.0, 0.0, 1.0), k * glm::dvec3(camera.width, 0.0, 1.0),
                              k * glm::dvec3(camera.width, camera.height, 1.0),
                              k * glm::dvec3(0.0, camera.height, 1.0)};
  const glm::dvec3 axis = k * glm::dvec3(0.5 * camera.width, 0.5 * camera.height, 1.0);
  std::vector<glm::dvec3> planes = {glm::dvec3(0.0, 0.0, 1.0)};  // in front
  for (int e = 0; e < 4; ++e) {
    glm::dvec3 n = glm::cross(rays[e], rays[(e + 1) % 4]);
    if (glm::dot(n, axis) < 0.0) n = -n;
    planes.push_back(n);
  }
  for (const glm::dvec3& n : planes) {
    bool allOutside = true;
    for (const glm::dvec3& c : corners) allOutside = allOutside && glm::dot(n, c) < 0.0;
    if (allOutside) return false;
  }
  return true;
}

// Scene::buildings read by tile (hv/io/native/footprints.h) and extruded tile by tile, with the
// LOD1 rules of buildLod1 and the validity dates of the attributes. With photographs, only the
// tiles some photograph may see closer than kBuildingReachMetresPerPixel x its focal length are
// read (docs/design.md, "Building tiles"); without, all of them.
// A source with tiles that no photograph sees is also streamed per view (Scene::buildingTiles,
// hv/render/building_stream.h), so that a view looking past the photographs still shows them.
// `dtm` is taken: the streamed tiles keep it for their bases (shared, not copied).
void loadBuildingTiles(Scene& scene, const PendingBuildings& b, Heightfield&& dtm, Diagnostics& diag) {
  const auto t0 = std::chrono::steady_clock::now();
  FootprintTileOptions options;
  options.perTile = kBuildingsPerTile;
  // The heights the tiles' boxes span: the terrain's and the cameras', with a margin for towers.
  double zlo = INFINITY, zhi = -INFINITY;
  for (float z : dtm.z)
    if (std::isfinite(z)) zlo = std::min(zlo, double(z)), zhi = std::max(zhi, double(z));
  for (const Photo& p : scene.photos) zlo = std::min(zlo, p.camera.center.z), zhi = std::max(zhi, p.camera.center.z);
  if (!std::isfinite(zlo)) zlo = zhi = 0.0;  // neither terrain nor cameras
  zlo -= kBuildingTileMarginMetres;
  zhi += kBuildingTileMarginMetres;
  // The tiles read here, as extruded (the streamed tile set's reader serves them from memory).
  auto read = std::make_shared<std::map<std::uint32_t, BuildingTileData>>();
  std::uint32_t asked = 0;  // readFootprintTiles asks for every tile in index order
  if (!scene.photos.empty()) {
    options.wanted = [&](glm::dvec2 lo, glm::dvec2 hi) {
      const std::uint32_t index = asked++;
      bool wanted = !std::isfinite(lo.x) || !std::isfinite(lo.y) || !std::isfinite(hi.x) || !std::isfinite(hi.y);
      Aabb box;
      box.lo = {lo, zlo};
      box.hi = {hi, zhi};
      for (const Photo& p : scene.photos)
        wanted = wanted || cameraMaySee(p.camera, box,
                                        kBuildingReachMetresPerPixel * std::max(p.camera.focal.x, p.camera.focal.y));
      if (wanted) (*read)[index] = BuildingTileData{};  // empty unless it holds footprints
      return wanted;
    };
  }
  Scene::BuildingTilesInfo& info = scene.buildingTilesInfo;
  // Read through the one dataset in tile order, then extruded on every core (most of the cost) and
  // appended in tile order: the same scene as extruding each tile as it is read.
  std::vector<std::size_t> indices;
  std::vector<std::vector<Footprint>> footprints;
  const FootprintTileSource source = readFootprintTiles(
      b.path, b.fields, b.georef, options,
      [&](FootprintTile& tile) {
        indices.push_back(tile.index);
        footprints.push_back(std::move(tile.footprints));
      },
      diag);
  std::vector<BuildingTileData> extruded =
      extrudeFootprintTiles(footprints, dtm.empty() ? nullptr : &dtm, b.fields, b.path, diag);
  footprints.clear();
  std::uint32_t delivered = 0;  // tiles holding buildings
  for (std::size_t t = 0; t < extruded.size(); ++t) {
    BuildingTileData& data = extruded[t];
    const std::uint32_t first = std::uint32_t(scene.buildingValidity.size());
    if (!scene.photos.empty()) (*read)[std::uint32_t(indices[t])] = data;
    for (std::uint32_t& tag : data.mesh.triangleTags) tag += first;
    scene.buildings.append(data.mesh);
    scene.buildingValidity.insert(scene.buildingValidity.end(), data.validity.begin(), data.validity.end());
    scene.tileOfBuilding.insert(scene.tileOfBuilding.end(), data.validity.size(), delivered);
    ++delivered;
  }
  if (!source.sourceCrs.empty())
    scene.sourceCrs.insert(scene.sourceCrs.begin() + std::ptrdiff_t(std::min(b.sourceCrsAt, scene.sourceCrs.size())),
                           Scene::SourceCrs{"buildings", source.sourceCrs, !scene.crs.empty()});
  info.loaded = source.tilesRead;
  info.total = source.tilesTotal;
  info.tileSize = source.tileSize;
  info.spatialFilter = source.spatialFilter;
  info.note = source.note;
  std::ostringstream how;
  if (scene.photos.empty())
    how << "all (no photographs)";
  else
    how << "those some photograph may see closer than " << kBuildingReachMetresPerPixel << " m per pixel";
  info.selection = how.str();
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  log::debug("buildings: " + b.path + ": " + std::to_string(info.loaded) + " of " + std::to_string(info.total) +
             " tiles read (" + std::to_string(delivered) + " holding buildings), " +
             std::to_string(scene.buildingValidity.size()) + " buildings, " + std::to_string(s) + " s");
  if (info.loaded >= info.total) return;
  try {
    const auto t1 = std::chrono::steady_clock::now();
    FootprintTileSource streamed;
    std::shared_ptr<const Heightfield> base = dtm.empty() ? nullptr : std::make_shared<const Heightfield>(std::move(dtm));
    auto set = std::make_shared<BuildingTileSet>(
        *footprintTileSet(b.path, b.fields, b.georef, options, std::move(base), zlo, zhi, streamed, diag));
    // The tiles read above are not read again: the same grid (the same options), the same indices.
    set->read = [read, fromSource = set->read](std::uint32_t tile) {
      const auto it = read->find(tile);
      return it != read->end() ? it->second : fromSource(tile);
    };
    scene.buildingTiles = std::move(set);
    info.streamed = scene.buildingTiles->boxes.size();
    log::debug("buildings: " + b.path + ": " + std::to_string(info.streamed) + " tiles streamed per view, set up in " +
               std::to_string(std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count()) + " s");
  } catch (const InputError& e) {
    scene.buildingTiles.reset();
    diag.error(std::string(e.what()) + " (buildings not streamed: only those the photographs see are drawn)");
  }
}

// A heightfield of one elevation over any footprint (±1e8 m around the origin): the buildings'
// base on a ground plane, as on a DTM.
Heightfield constantHeightfield(double height) {
  Heightfield h;
  h.cols = h.rows = 2;
  h.originX = -2e8;
  h.originY = 2e8;
  h.cellX = 2e8;
  h.cellY = -2e8;  // samples at ±1e8
  h.z.assign(4, float(height));
  return h;
}

// WGS 84 geodetic (latitude, longitude in radians, ellipsoidal height) to ECEF, and the inverse
// (Bowring's formula, one iteration: well under a millimetre near the surface).
glm::dvec3 ecefFromGeodetic(double lat, double lon, double h) {
  constexpr double a = 6378137.0, f = 1.0 / 298.257223563, e2 = f * (2.0 - f);
  const double n = a / std::sqrt(1.0 - e2 * std::sin(lat) * std::sin(lat));
  return {(n + h) * std::cos(lat) * std::cos(lon), (n + h) * std::cos(lat) * std::sin(lon),
          (n * (1.0 - e2) + h) * std::sin(lat)};
}
glm::dvec2 geodeticLatLon(const glm::dvec3& p) {
  constexpr double a = 6378137.0, f = 1.0 / 298.257223563, b = a * (1.0 - f), e2 = f * (2.0 - f), ep2 = e2 / (1.0 - e2);
  const double r = std::hypot(p.x, p.y), theta = std::atan2(p.z * a, r * b);
  const double lat =
      std::atan2(p.z + ep2 * b * std::pow(std::sin(theta), 3), r - e2 * a * std::pow(std::cos(theta), 3));
  return {lat, std::atan2(p.y, p.x)};
}

// scene.json `"terrain": {"height": h}`: a flat ground at elevation h instead of a DTM, over the
// cameras and the geometry (their extent without outliers, hv/scene/robust_extent.h) with a margin
// of half the extent's larger side, at least kGroundMinMargin: the photographs look past their
// own cameras. Perpendicular to `up` at `up · p = h`; in a geocentric frame (MicMac's ECEF), the
// plane tangent to the WGS 84 ellipsoid at height h under the cameras' centre. A grid of
// kGroundCells² cells, so that culling and depth precision see tiles, not two huge triangles.
constexpr double kGroundMinMargin = 200.0;
constexpr int kGroundCells = 16;
void makeGroundPlane(Scene& scene, double height, const std::string& path, Diagnostics& diag) {
  const Aabb extent = robustExtent(scene).bounds;
  if (extent.empty()) {
    diag.warn(inputMessage(path, "terrain.height", "no camera and no geometry to place the ground under (no terrain)"));
    return;
  }
  const bool geocentric = !scene.crs.empty() && describeCrs(scene.crs).geocentric;
  glm::dvec3 up = glm::normalize(scene.up), anchor;
  if (geocentric) {
    const glm::dvec2 latLon = geodeticLatLon(extent.center());
    anchor = ecefFromGeodetic(latLon.x, latLon.y, height);
    up = ecefUp(anchor);
  } else {
    anchor = extent.center() + (height - glm::dot(extent.center(), up)) * up;
  }
  // Two axes in the plane; the extent's corners projected on them give its size.
  const glm::dvec3 east = glm::normalize(std::abs(up.z) < 0.9 ? glm::cross(glm::dvec3(0, 0, 1), up)
                                                              : glm::cross(up, glm::dvec3(0, 1, 0)) * -1.0);
  const glm::dvec3 north = glm::cross(up, east);
  glm::dvec2 lo(INFINITY), hi(-INFINITY);
  for (int c = 0; c < 8; ++c) {
    const glm::dvec3 corner((c & 1) ? extent.hi.x : extent.lo.x, (c & 2) ? extent.hi.y : extent.lo.y,
                            (c & 4) ? extent.hi.z : extent.lo.z);
    const glm::dvec2 q(glm::dot(corner - anchor, east), glm::dot(corner - anchor, north));
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  const double margin = std::max(kGroundMinMargin, 0.5 * std::max(hi.x - lo.x, hi.y - lo.y));
  lo -= margin;
  hi += margin;
  Mesh& m = scene.terrain;
  m = Mesh{};
  for (int j = 0; j <= kGroundCells; ++j)
    for (int i = 0; i <= kGroundCells; ++i) {
      const double u = lo.x + (hi.x - lo.x) * i / kGroundCells, v = lo.y + (hi.y - lo.y) * j / kGroundCells;
      m.positions.push_back(anchor + u * east + v * north);
    }
  const auto at = [](int i, int j) { return std::uint32_t(j * (kGroundCells + 1) + i); };
  for (int j = 0; j < kGroundCells; ++j)
    for (int i = 0; i < kGroundCells; ++i) {  // east x north = up: counter-clockwise from above
      m.triangles.emplace_back(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      m.triangles.emplace_back(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  log::debug("terrain: a ground plane at height " + std::to_string(height) + ", " + std::to_string(hi.x - lo.x) +
             " x " + std::to_string(hi.y - lo.y) + " m");
}

}  // namespace

Scene loadScene(const std::string& path, Diagnostics& diag) { return loadScene(path, diag, SceneLoadOptions{}); }

std::shared_ptr<const Orthophoto> loadOrthophoto(const Scene& scene, Diagnostics& diag) {
  if (scene.path.empty()) return nullptr;
  const std::string& path = scene.path;
  const json doc = readJsonInput(path, "scene", diag);
  if (!doc.is_object() || !doc.contains("orthophoto")) return nullptr;
  const std::string dir = fs::path(path).parent_path().empty() ? "." : fs::path(path).parent_path().string();
  try {
    return readSceneOrthophoto(scene, doc, dir, path, diag);
  } catch (const InputError& e) {
    diag.warn(std::string(e.what()) + " (orthophoto left out: untextured terrain shaded)");
    noteMissing(scene, "orthophoto", sourceLocation(doc, "orthophoto", dir), e.what());
    return nullptr;
  }
}

Scene loadScene(const std::string& path, Diagnostics& diag, const SceneLoadOptions& options) {
  enableRemoteReading();
  const json doc = readJsonInput(path, "scene", diag);
  if (!doc.is_object()) throw InputError(path + ": expected a JSON object");
  refuseUnknownKeys(doc, path);

  Scene scene;
  scene.path = path;
  const std::string dir = fs::path(path).parent_path().empty() ? "." : fs::path(path).parent_path().string();
  if (doc.contains("crs") && !doc["crs"].is_null()) {
    // Checked once here: a CRS that PROJ cannot read would otherwise be blamed on every source
    // georeferenced into it; without a scene frame nothing can be placed (docs/reliability.md).
    if (!doc["crs"].is_string() || doc["crs"].get<std::string>().empty())
      throw InputError(path + ": crs: expected a CRS string (\"EPSG:2154\", WKT, a PROJ string), got " +
                       doc["crs"].dump());
    scene.crs = doc["crs"].get<std::string>();
    try {
      describeCrs(scene.crs);
    } catch (const InputError& e) {
      throw InputError(path + ": crs: " + e.what());
    }
  }
  if (doc.contains("up")) {
    scene.up = vec3Field(doc, "up", path);
    if (glm::length(scene.up) == 0.0) throw InputError(path + ": up: expected a non-zero vector");
    scene.up = glm::normalize(scene.up);
  }

  const bool crsDeclared = !scene.crs.empty();

  // Terrain, buildings, mesh and points: each from its own CRS (`<source>.crs`, else the file's)
  // into the scene frame (hv/io/georef.h); without a scene CRS, as they are.
  Heightfield dtm;
  std::string terrainPath;
  std::optional<double> groundHeight;
  const bool geometry = !options.camerasOnly;
  if (geometry && doc.contains("terrain") && doc["terrain"].is_object() && doc["terrain"].contains("height")) {
    const json& t = doc["terrain"];
    if (t.contains("path"))
      throw InputError(path + ": terrain: expected either a path (a DTM) or a height (a ground plane), not both");
    if (!t["height"].is_number() || !std::isfinite(t["height"].get<double>()))
      throw InputError(path + ": terrain.height: expected the ground's elevation in metres, got " + t["height"].dump());
    groundHeight = t["height"].get<double>();
    dtm = constantHeightfield(*groundHeight);
  } else if (geometry && doc.contains("terrain")) {
    try {
      const std::string p = sourcePath(doc, "terrain", dir, path);
      terrainPath = p;
      const SourceGeoref georef = sourceGeoref(doc, "terrain", scene.crs, path);
      const RasterSize size = rasterSize(p);
      if (std::uint64_t(size.cols) * std::uint64_t(size.rows) > kTerrainTilesAboveCells) {
        // Too large to mesh whole: a quadtree of tiles, meshed once the cameras are known (below).
        std::string whyNot;
        if (auto raster = TerrainRaster::open(p, georef, diag, whyNot)) {
          scene.terrainTiles = std::make_shared<TerrainQuadtree>(raster, TerrainTileOptions{kTerrainTileCells});
          if (scene.terrainTiles->tile(TerrainQuadtree::root()).bounds.empty()) {
            scene.terrainTiles.reset();
            throw InputError(inputMessage(p, "band 1", "every sample is no-data: no terrain to make"));
          }
          dtm = buildingBaseHeights(*scene.terrainTiles);
          recordSource(scene, "terrain", raster->sourceCrs());
          Scene::TerrainTilesInfo& info = scene.terrainTilesInfo;
          info.reads = raster->pyramidLevels() ? "a pyramid of averages built in memory (" +
                                                     std::to_string(raster->pyramidLevels()) + " levels)"
                       : raster->gdalOverviews() ? std::to_string(raster->gdalOverviews()) + " GDAL overview(s)"
                                                 : "the full resolution only";
        } else {
          diag.warn(inputMessage(p, "size",
                                 std::to_string(size.cols) + " x " + std::to_string(size.rows) +
                                     " cells, yet not read as tiles: " + whyNot + "; read whole instead"));
        }
      }
      if (!scene.terrainTiles) {
        GeoreferencedHeightfield read = readHeightfield(p, georef, diag);
        dtm = std::move(read.field);
        scene.terrain = dtm.toMesh();  // at most kTerrainTilesAboveCells: whole (hv/scene/scene_frame.h)
        recordSource(scene, "terrain", read.sourceCrs);
      }
      log::debug("terrain: " + p + ": " + std::to_string(size.cols) + "x" + std::to_string(size.rows) +
                 (scene.terrainTiles ? " (tiles)" : ""));
    } catch (const InputError& e) {
      scene.terrainTiles.reset();
      diag.error(std::string(e.what()) + " (terrain left out)");
      noteMissing(scene, "terrain", sourceLocation(doc, "terrain", dir), e.what());
    }
  }
  // Buildings are read once the cameras are known (below): only the tiles the photographs see.
  std::optional<PendingBuildings> buildings;
  if (geometry && doc.contains("buildings")) {
    try {
      const std::string p = sourcePath(doc, "buildings", dir, path);
      const json& b = doc["buildings"];
      if (isCityJsonFile(p)) {
        // 3D buildings as they are (LOD1 or LOD2 with their roofs): no footprint to extrude, so
        // the footprint attributes have nothing to name.
        for (const char* key : {"height", "base", "top", "valid_from", "valid_to"})
          if (b.contains(key))
            diag.warn(inputMessage(path, std::string("buildings.") + key,
                                   "ignored: " + p + " is CityJSON, whose buildings are 3D already"));
        CityJsonBuildings city = readCityJson(p, diag);
        const SourceGeoref georef = sourceGeoref(doc, "buildings", scene.crs, path);
        if (!scene.crs.empty()) {
          const GeoTransform transform = sourceTransform(georef, sourceCrsOf(georef, city.crs), p, diag);
          if (!transform.isIdentity()) transform.points(city.mesh.positions);
        }
        recordSource(scene, "buildings", georef.crs.empty() ? city.crs : georef.crs);
        scene.buildings = std::move(city.mesh);
        scene.buildingValidity.assign(city.ids.size(), DateInterval{});
        log::debug("buildings: " + p + ": " + std::to_string(city.ids.size()) + " CityJSON buildings, " +
                   std::to_string(scene.buildings.triangles.size()) + " triangles");
      } else {
        PendingBuildings pending;
        pending.path = p;
        const json& entry = doc["buildings"];
        if (auto h = optionalString(entry, "height", path + ": buildings")) pending.fields.height = *h;
        pending.fields.base = optionalString(entry, "base", path + ": buildings");
        pending.fields.top = optionalString(entry, "top", path + ": buildings");
        pending.fields.validFrom = optionalString(entry, "valid_from", path + ": buildings");
        pending.fields.validTo = optionalString(entry, "valid_to", path + ": buildings");
        pending.georef = sourceGeoref(doc, "buildings", scene.crs, path);
        pending.sourceCrsAt = scene.sourceCrs.size();
        buildings = std::move(pending);
      }
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (buildings left out)");
      noteMissing(scene, "buildings", sourceLocation(doc, "buildings", dir), e.what());
    }
  }
  if (geometry && doc.contains("mesh")) {
    try {
      const std::string p = sourcePath(doc, "mesh", dir, path);
      const SourceGeoref georef = sourceGeoref(doc, "mesh", scene.crs, path);
      Mesh mesh = readMesh(p);
      // A mesh file seldom declares a CRS: only mesh.crs moves it (like points, vertex by vertex).
      if (!georef.crs.empty() && !scene.crs.empty()) {
        const GeoTransform transform = sourceTransform(georef, georef.crs, p, diag);
        if (!transform.isIdentity()) transform.points(mesh.positions);
      }
      recordSource(scene, "mesh", georef.crs);
      scene.mesh = std::move(mesh);
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (mesh left out)");
      noteMissing(scene, "mesh", sourceLocation(doc, "mesh", dir), e.what());
    }
  }
  // A 3D Tiles tileset is read once the cameras are known (below); a point file now.
  std::optional<PointTilesetRequest> pointTileset;
  bool pointsRefused = false;
  if (geometry && doc.contains("points")) {
    try {
      pointTileset = pointTilesetRequest(doc, dir, scene.crs, path);
    } catch (const InputError& e) {
      pointsRefused = true;
      diag.error(std::string(e.what()) + " (points left out)");
      noteMissing(scene, "points", sourceLocation(doc, "points", dir), e.what());
    }
  }
  if (geometry && doc.contains("points") && !pointTileset && !pointsRefused) {
    try {
      const std::string p = sourcePath(doc, "points", dir, path);
      const auto t0 = std::chrono::steady_clock::now();
      const SourceGeoref georef = sourceGeoref(doc, "points", scene.crs, path);
      scene.points = readPointFile(p);
      if (!georef.crs.empty()) scene.points.crs = georef.crs;  // overrides the file's
      if (!scene.crs.empty()) georeferencePoints(scene.points, georef, p, diag);
      recordSource(scene, "points", scene.crs.empty() ? scene.points.crs : sourceCrsOf(georef, scene.points.crs));
      organizeChunks(scene.points);
      estimatePointNormals(scene.points, doc["points"], path);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      log::debug("points: " + p + ": " + std::to_string(scene.points.size()) + " points, " +
                 std::to_string(scene.points.chunks.size()) + " chunks, " + std::to_string(s) + " s");
    } catch (const InputError& e) {
      scene.points = PointCloud{};
      diag.error(std::string(e.what()) + " (points left out)");
      noteMissing(scene, "points", sourceLocation(doc, "points", dir), e.what());
    }
  }
  if (doc.contains("cameras")) {
    try {
      const json& c = doc["cameras"];
      if (!c.is_object()) throw InputError(path + ": cameras: expected an object");
      if (c.contains("format") && !c["format"].is_string())
        throw InputError(
            path + ": cameras.format: expected a string (\"native\", \"itowns\", \"colmap\", \"micmac\" or \"ogr\")");
      const bool catalog = c.contains("postgis");
      if (catalog) {
        for (const char* key : {"path", "format", "images", "orientations", "calibration"})
          if (c.contains(key))
            throw InputError(path + ": cameras." + key +
                             ": not with cameras.postgis (the cameras come either from files or from a catalog)");
        if (!c["postgis"].is_string())
          throw InputError(path +
                           ": cameras.postgis: expected a PostgreSQL connection string "
                           "(\"postgresql://user@host:port/database\")");
      } else if (c.contains("table")) {
        throw InputError(path + ": cameras.table: only with cameras.postgis (the catalog's table)");
      }
      if (c.contains("layer") && (catalog || c.value("format", "") != "ogr"))
        throw InputError(path + ": cameras.layer: only with \"format\": \"ogr\" (the point layer's name)");
      const std::string format = catalog ? "postgis" : c.value("format", "native");
      std::string catalogCrs;
      auto file = [&](const char* key) {
        if (!c.contains(key) || !c[key].is_string())
          throw InputError(path + ": cameras." + key + ": expected a path string");
        return resolveSourcePath(c[key].get<std::string>(), dir);
      };
      if (catalog) {
        // Every camera of the table at open (docs/catalog.md, mode (a)): the same selection as
        // from files; the table's CRS is the cameras' unless cameras.crs overrides it.
        if (c.contains("table") && !c["table"].is_string())
          throw InputError(path + ": cameras.table: expected a table name (string)");
        const std::string table = c.value("table", std::string(kDefaultCatalogTable));
        checkCatalogTableName(table, path + ": cameras.table");
        CatalogCameras read = readCameraCatalog(c["postgis"].get<std::string>(), table, diag);
        scene.photos = std::move(read.photos);
        catalogCrs = read.crs;
        log::debug("cameras: " + redactConnection(c["postgis"].get<std::string>()) + " table " + table + ": " +
                   std::to_string(scene.photos.size()) + " cameras");
      } else if (format == "ogr") {
        // A point layer in the catalog's layout (docs/formats.md): a GeoPackage, a GeoJSON file, a
        // WFS or an OGC API - Features collection; the layer's CRS unless cameras.crs overrides it.
        if (c.contains("layer") && !c["layer"].is_string())
          throw InputError(path + ": cameras.layer: expected a layer name (string)");
        const std::string source = sourcePath(doc, "cameras", dir, path);
        CatalogCameras read = readOgrCameras(source, c.value("layer", std::string()), diag);
        scene.photos = std::move(read.photos);
        catalogCrs = read.crs;
        // Relative image and mask paths are relative to scene.json; absolute paths and URLs stay.
        auto resolveImage = [&](std::string& image) {
          if (!image.empty() && image.find("://") == std::string::npos && image.rfind("/vsi", 0) != 0)
            image = (fs::path(dir) / image).lexically_normal().string();
        };
        for (Photo& p : scene.photos) resolveImage(p.imagePath), resolveImage(p.maskPath);
        log::debug("cameras: " + source + ": " + std::to_string(scene.photos.size()) + " cameras");
      } else if (format == "native") {
        scene.photos = readCameraFile(sourcePath(doc, "cameras", dir, path), CameraFileOptions{}, diag);
      } else if (format == "itowns") {
        // The image pattern is a path pattern, or a JSON file of per-panorama patterns.
        if (!c.contains("images") || !c["images"].is_string())
          throw InputError(path + ": cameras.images: expected a pattern with {panoId} and {cameraId}");
        std::string images = c["images"].get<std::string>();
        if (fs::path(images).extension() == ".json") images = file("images");
        scene.photos = readITownsCameras({file("orientations"), file("calibration"), images, dir}, diag);
      } else if (format == "colmap") {
        scene.photos = readColmapModel(file("path"), file("images"), diag);
      } else if (format == "micmac") {
        scene.photos = readMicmacCameras(file("orientations"), file("images"), diag);
      } else {
        throw InputError(
            path + ": cameras.format: expected \"native\", \"itowns\", \"colmap\", \"micmac\" or \"ogr\", got \"" +
            format + "\"");
      }
      resolveIiifImages(scene.photos, *scene.missing, diag);
      // Georeferencing: the cameras' CRS (cameras.crs, or the format's own: MicMac's centres are
      // ECEF) into the scene frame; without a scene CRS, the cameras' CRS is the scene's.
      if (c.contains("crs") && !c["crs"].is_string())
        throw InputError(path + ": cameras.crs: expected a CRS string (\"EPSG:4978\", WKT, a PROJ string)");
      const std::string cameraCrs = c.contains("crs")                        ? c["crs"].get<std::string>()
                                    : format == "micmac"                     ? std::string("EPSG:4978")
                                    : format == "postgis" || format == "ogr" ? catalogCrs
                                                                             : std::string();
      if (!cameraCrs.empty()) {
        scene.sourceCrs.push_back({"cameras", cameraCrs, true});
        if (scene.crs.empty()) scene.crs = cameraCrs;
        georeferenceCameras(scene, cameraCrs, doc.contains("up"), path, diag);
      }
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (cameras left out)");
      noteMissing(scene, "cameras", sourceLocation(doc, "cameras", dir), e.what());
    }
  }

  if (pointTileset) loadPointTilesetIntoScene(scene, *pointTileset, doc["points"], path, diag);

  // The photographs' colour corrections (`histoview harmonize`); a broken file or entry leaves the
  // photographs it concerns with their own colours.
  if (doc.contains("colour")) {
    try {
      if (!doc["colour"].is_string() || doc["colour"].get<std::string>().empty())
        throw InputError(path + ": colour: expected the path of a colour corrections file (histoview harmonize)");
      const fs::path p = doc["colour"].get<std::string>();
      scene.colourPath = (p.is_absolute() ? p : fs::path(dir) / p).lexically_normal().string();
      applyColourCorrections(scene.photos, readColourCorrections(scene.colourPath, diag), scene.colourPath, diag);
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (colour corrections left out)");
      noteMissing(scene, "colour corrections", scene.colourPath, e.what());
    }
  }

  if (doc.contains("traffic")) {
    try {
      loadTraffic(scene, doc, dir, path, diag);
    } catch (const InputError& e) {
      scene.traffic.reset();
      diag.error(std::string(e.what()) + " (traffic left out)");
      noteMissing(scene, "traffic", sourceLocation(doc, "traffic", dir), e.what());
    }
  }

  if (scene.terrainTiles) {
    try {
      meshTerrainTiles(scene);
    } catch (const InputError& e) {
      scene.terrainTiles.reset();
      scene.terrain = Mesh{};
      diag.error(std::string(e.what()) + " (terrain left out)");
      noteMissing(scene, "terrain", sourceLocation(doc, "terrain", dir), e.what());
    }
  }

  if (buildings) {
    try {
      loadBuildingTiles(scene, *buildings, std::move(dtm), diag);
    } catch (const InputError& e) {
      scene.buildings = Mesh{};
      scene.buildingValidity.clear();
      scene.tileOfBuilding.clear();
      diag.error(std::string(e.what()) + " (buildings left out)");
      noteMissing(scene, "buildings", sourceLocation(doc, "buildings", dir), e.what());
    }
  }
  if (groundHeight) makeGroundPlane(scene, *groundHeight, path, diag);

  warnUnrelatedFrames(scene, crsDeclared, path, diag);
  settleUp(scene, doc.contains("up"), path, diag);

  if (doc.contains("origin")) {
    scene.origin = vec3Field(doc, "origin", path);
  } else {
    scene.origin = dataOrigin(scene);  // hv/scene/scene_frame.h
  }
  return scene;
}

}  // namespace hv
