#include "hv/io/web_scene.h"

#include "hv/io/cameras_json.h"
#include "hv/io/geojson_cameras.h"
#include "hv/io/geojson_footprints.h"
#include "hv/io/web_scene_frame.h"
#include "hv/scene/chunks.h"
#include "hv/scene/point_normals.h"
#include "hv/traffic/trajectories.h"
#include "hv/traffic/vehicle_model.h"
#include "hv/util/input_file.h"
#include "hv/util/log.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace hv {

namespace fs = std::filesystem;
using json = nlohmann::json;

static_assert(std::endian::native == std::endian::little, "the web mesh files are little-endian");

namespace {

json vec3Json(const glm::dvec3& v) { return json::array({v.x, v.y, v.z}); }

glm::dvec3 vec3Of(const json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw InputError(where + ": expected an array of 3 numbers");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

template <typename T>
void appendRaw(std::string& out, const std::vector<T>& v) {
  if (v.empty()) return;  // data() may be null
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

void writeFile(const fs::path& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), std::streamsize(bytes.size()));
  if (!f) throw std::runtime_error(path.string() + ": cannot write");
}

// One read of the whole file: streaming it through an ostringstream (operator<< of rdbuf) took
// 0.57 s for the demo's 7.5 MB points.bin in the browser build (Emscripten's file system), this 10 ms.
std::string readFileBytes(const fs::path& path) {
  requireRegularFile(path.string(), "", kMaxBinaryBytes);
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) throw InputError(path.string() + ": cannot open file");
  const std::streamoff size = f.tellg();
  if (size < 0) throw InputError(path.string() + ": cannot tell the file's size");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  f.seekg(0);
  f.read(bytes.data(), size);
  if (!f) throw InputError(path.string() + ": cannot read " + std::to_string(size) + " bytes");
  return bytes;
}

// traffic.csv (web_scene.h): every sample, the vehicle's centre in the scene frame.
std::string webTrafficCsv(const Trajectories& traffic) {
  // Ids and types are written as they are; a comma or line break in one (which the CSV reader
  // would split) becomes '_'.
  auto clean = [](std::string s) {
    std::replace_if(
        s.begin(), s.end(), [](char c) { return c == ',' || c == '\n' || c == '\r'; }, '_');
    return s;
  };
  std::string out = "t,id,x,y,angle,type\n";
  char buf[128];
  for (const Trajectory& v : traffic.vehicles) {
    const std::string id = clean(v.id), type = clean(v.type);
    for (const TrajectorySample& s : v.samples) {
      std::snprintf(buf, sizeof buf, "%.9g,", s.t);
      out += buf;
      out += id;
      std::snprintf(buf, sizeof buf, ",%.4f,%.4f,%.6f,", s.xy.x, s.xy.y, s.angleDeg);
      out += buf;
      out += type;
      out += '\n';
    }
  }
  return out;
}

// vehicles.json (web_scene.h): the models of the classes that have one.
json webVehicleModels(const VehicleModels& models) {
  json out = json::object();
  for (int c = 0; c < kVehicleClasses; ++c) {
    const auto& m = models.byClass[std::size_t(c)];
    if (!m) continue;
    std::vector<float> v;
    v.reserve(m->vertices.size() * 10);
    for (const ModelVertex& x : m->vertices)
      for (float f : {x.local.x, x.local.y, x.local.z, x.normal.x, x.normal.y, x.normal.z, x.colour.r, x.colour.g,
                      x.colour.b, x.paint})
        v.push_back(f);
    out[vehicleClassName(VehicleClass(c))] = {{"source", fs::path(m->source).filename().string()}, {"vertices", v}};
  }
  return out;
}

std::shared_ptr<const VehicleModels> readWebVehicleModels(const json& j, const std::string& name) {
  if (!j.is_object()) throw InputError(name + ": expected an object of vehicle classes");
  auto models = std::make_shared<VehicleModels>();
  for (int c = 0; c < kVehicleClasses; ++c) {
    const char* cls = vehicleClassName(VehicleClass(c));
    if (!j.contains(cls)) continue;
    const json& m = j[cls];
    if (!m.is_object() || !m.contains("vertices") || !m["vertices"].is_array())
      throw InputError(name + ": " + cls + ": expected {\"vertices\": [10 numbers per vertex]}");
    const json& a = m["vertices"];
    if (a.size() % 30 != 0)
      throw InputError(name + ": " + cls + ": vertices: " + std::to_string(a.size()) +
                       " numbers, expected 10 per vertex and 3 vertices per triangle");
    auto model = std::make_shared<VehicleModel>();
    model->source = name + ": " + cls;
    for (std::size_t i = 0; i < a.size(); i += 10) {
      float f[10];
      for (std::size_t k = 0; k < 10; ++k) {
        if (!a[i + k].is_number() || !std::isfinite(a[i + k].get<double>()))
          throw InputError(name + ": " + cls + ": vertices: element " + std::to_string(i + k) +
                           ": expected a finite number");
        f[k] = a[i + k].get<float>();
      }
      model->vertices.push_back({{f[0], f[1], f[2]}, {f[3], f[4], f[5]}, {f[6], f[7], f[8]}, f[9]});
    }
    models->byClass[std::size_t(c)] = std::move(model);
  }
  return models;
}

Mesh* meshByName(Scene& scene, const std::string& name) {
  if (name == "terrain") return &scene.terrain;
  if (name == "buildings") return &scene.buildings;
  if (name == "mesh") return &scene.mesh;
  return nullptr;
}

Mesh readMesh(const fs::path& path, const glm::dvec3& origin, std::size_t vertices, std::size_t triangles, bool tags) {
  const std::string bytes = readFileBytes(path);
  const std::size_t want = vertices * 12 + triangles * 12 + (tags ? triangles * 4 : 0);
  if (bytes.size() != want)
    throw InputError(path.string() + ": " + std::to_string(bytes.size()) + " bytes, expected " + std::to_string(want) +
                     " (" + std::to_string(vertices) + " vertices, " + std::to_string(triangles) + " triangles)");
  Mesh m;
  std::vector<float> pos(vertices * 3);
  std::memcpy(pos.data(), bytes.data(), vertices * 12);
  m.positions.resize(vertices);
  for (std::size_t i = 0; i < vertices; ++i)
    m.positions[i] = origin + glm::dvec3(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
  m.triangles.resize(triangles);
  std::memcpy(m.triangles.data(), bytes.data() + vertices * 12, triangles * 12);
  for (const auto& t : m.triangles)
    if (t.x >= vertices || t.y >= vertices || t.z >= vertices)
      throw InputError(path.string() + ": triangle index out of range (" + std::to_string(vertices) + " vertices)");
  if (tags) {
    m.triangleTags.resize(triangles);
    std::memcpy(m.triangleTags.data(), bytes.data() + vertices * 12 + triangles * 12, triangles * 4);
  }
  return m;
}

// points.bin (web_scene.h).
constexpr char kPointsMagic[8] = {'H', 'V', 'P', 'O', 'I', 'N', 'T', 'S'};
constexpr std::uint32_t kPointsVersion = 1;
constexpr std::size_t kPointsHeaderBytes = 24;
constexpr std::uint32_t kNormals = 1, kIntensity = 2, kRgb = 4, kClassification = 8;  // the fields' bits
constexpr std::uint32_t kKnownPointFields = kNormals | kIntensity | kRgb | kClassification;

std::uint32_t pointFieldBits(const PointFields& f) {
  return (f.normals ? kNormals : 0) | (f.intensity ? kIntensity : 0) | (f.rgb ? kRgb : 0) |
         (f.classification ? kClassification : 0);
}

// Bytes per point of the fields in `bits`, position included.
std::size_t pointStride(std::uint32_t bits) {
  return 12 + (bits & kNormals ? 6 : 0) + (bits & kIntensity ? 2 : 0) + (bits & kRgb ? 3 : 0) +
         (bits & kClassification ? 1 : 0);
}

template <typename T>
void appendValue(std::string& out, T v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(T));
}

std::int16_t snorm16(float v) { return std::int16_t(std::lround(std::clamp(v, -1.0f, 1.0f) * 32767.0f)); }

// The manifest's "cameras" as a camera layer (web_scene.h): GeoJSON pages fetched from a WFS or
// OGC API – Features layer of camera points, each named in messages by the URL it came from.
// Relative image and mask paths are relative to the service description, whose folder the page
// mirrors here; http(s) URLs stay (the page puts what it fetched where the remote reader looks).
std::vector<Photo> readServiceCameras(const json& c, const fs::path& dir, Diagnostics& diag) {
  if (!c.contains("geojson") || !c["geojson"].is_array())
    throw InputError("expected {\"geojson\": [\"page.json\", ...], \"urls\": [\"http://...\", ...]}");
  const json urls = c.value("urls", json::array());
  std::vector<Photo> photos;
  const auto resolve = [&](std::string& path) {
    if (!path.empty() && !isHttpUrl(path) && !fs::path(path).is_absolute()) path = (dir / path).lexically_normal().string();
  };
  for (std::size_t k = 0; k < c["geojson"].size(); ++k) {
    const json& page = c["geojson"][k];
    if (!page.is_string()) throw InputError("geojson: expected the names of files");
    const fs::path file = dir / page.get<std::string>();
    const std::string name = k < urls.size() && urls[k].is_string() ? urls[k].get<std::string>() : file.string();
    GeoJsonCameraPage got;
    try {
      got = parseGeoJsonCameras(readTextFile(file.string(), kMaxJsonBytes, "cameras"), name, diag);
    } catch (const InputError& e) {
      diag.error(std::string(e.what()) + " (the page's cameras left out)");
      continue;
    }
    for (Photo& p : got.photos) {
      resolve(p.imagePath);
      resolve(p.maskPath);
      if (p.imagePath.empty()) {
        diag.error(name + ": camera '" + p.camera.id + "': image: missing (expected the photograph's path or URL; "
                   "camera skipped)");
        continue;
      }
      photos.push_back(std::move(p));
    }
  }
  log::debug("cameras: " + std::to_string(photos.size()) + " from " + std::to_string(c["geojson"].size()) +
             " GeoJSON pages");
  return photos;
}

// The manifest's "buildings" (web_scene.h): GeoJSON pages fetched from a service, extruded here
// as the native loader extrudes footprints (hv/scene/footprint.h), on the DTM fetched beside them.
void readServiceBuildings(const json& b, const fs::path& dir, Scene& scene, Diagnostics& diag) {
  if (!b.is_object() || !b.contains("geojson") || !b["geojson"].is_array())
    throw InputError("expected {\"geojson\": [\"page.json\", ...], \"height\": \"height\", \"dtm\": \"dtm.asc\"}");
  GeoJsonFootprintFields fields;
  auto text = [&](const char* key) -> std::optional<std::string> {
    if (!b.contains(key)) return std::nullopt;
    if (!b[key].is_string()) throw InputError(std::string(key) + ": expected the name of an attribute");
    return b[key].get<std::string>();
  };
  if (auto h = text("height")) fields.height = *h;
  fields.base = text("base");
  fields.top = text("top");
  fields.validFrom = text("validFrom");
  fields.validTo = text("validTo");
  Heightfield dtm;
  if (b.contains("dtm")) {
    if (!b["dtm"].is_string()) throw InputError("dtm: expected the name of a file (an ESRI ASCII grid)");
    const fs::path file = dir / b["dtm"].get<std::string>();
    dtm = parseAaiGrid(readFileBytes(file), file.string());
  }
  std::vector<Footprint> footprints;
  std::string source;
  for (const json& page : b["geojson"]) {
    if (!page.is_string()) throw InputError("geojson: expected the names of files");
    const fs::path file = dir / page.get<std::string>();
    if (source.empty()) source = file.string();
    GeoJsonFootprintPage p = parseGeoJsonFootprints(readFileBytes(file), fields, file.string(), diag);
    for (Footprint& f : p.footprints) footprints.push_back(std::move(f));
  }
  scene.buildings = buildLod1With(footprints, dtm.empty() ? nullptr : &dtm, diag, extrudeLod1EarClip);
  scene.buildingValidity = footprintValidity(footprints, fields.validFrom.value_or("valid_from"),
                                             fields.validTo.value_or("valid_to"), source, diag);
  log::debug("buildings: " + std::to_string(footprints.size()) + " footprints from " +
             std::to_string(b["geojson"].size()) + " GeoJSON pages, " +
             std::to_string(scene.buildings.triangles.size()) + " triangles" +
             (dtm.empty() ? std::string()
                          : ", bases on a " + std::to_string(dtm.cols) + "x" + std::to_string(dtm.rows) + " DTM"));
}

}  // namespace

std::string webPointBytes(const PointCloud& cloud, const glm::dvec3& origin) {
  PointFields f = cloud.fields();
  f.normals = hasNormals(cloud);  // deferred ones estimated now (hv/scene/point_normals.h)
  const std::uint32_t bits = pointFieldBits(f);
  const std::size_t n = cloud.size();
  std::string out;
  out.reserve(kPointsHeaderBytes + n * pointStride(bits));
  out.append(kPointsMagic, sizeof(kPointsMagic));
  appendValue(out, kPointsVersion);
  appendValue(out, bits);
  appendValue(out, std::uint64_t(n));
  std::vector<float> pos;
  pos.reserve(3 * n);
  for (const glm::dvec3& p : cloud.positions) {
    const glm::dvec3 r = p - origin;  // the render frame, as the meshes and the point pass
    pos.insert(pos.end(), {float(r.x), float(r.y), float(r.z)});
  }
  appendRaw(out, pos);
  if (f.normals) {
    std::vector<std::int16_t> normals;
    normals.reserve(3 * n);
    for (const glm::vec3& v : pointNormals(cloud)) normals.insert(normals.end(), {snorm16(v.x), snorm16(v.y), snorm16(v.z)});
    appendRaw(out, normals);
  }
  if (f.intensity) appendRaw(out, cloud.intensity);
  if (f.rgb) {
    std::vector<std::uint8_t> rgb;
    rgb.reserve(3 * n);
    for (const glm::u16vec3& c : cloud.rgb)
      rgb.insert(rgb.end(), {std::uint8_t(c.r / 257), std::uint8_t(c.g / 257), std::uint8_t(c.b / 257)});
    appendRaw(out, rgb);
  }
  if (f.classification) appendRaw(out, cloud.classification);
  return out;
}

PointCloud parseWebPoints(const std::uint8_t* data, std::size_t size, const glm::dvec3& origin,
                          const std::string& name) {
  if (size < kPointsHeaderBytes)
    throw InputError(name + ": header: " + std::to_string(size) + " bytes, expected at least " +
                     std::to_string(kPointsHeaderBytes));
  if (std::memcmp(data, kPointsMagic, sizeof(kPointsMagic)) != 0)
    throw InputError(name + ": magic: expected \"HVPOINTS\" (a histoview web point file)");
  std::uint32_t version = 0, bits = 0;
  std::uint64_t count = 0;
  std::memcpy(&version, data + 8, 4);
  std::memcpy(&bits, data + 12, 4);
  std::memcpy(&count, data + 16, 8);
  if (version != kPointsVersion)
    throw InputError(name + ": version: " + std::to_string(version) + ", expected " + std::to_string(kPointsVersion));
  if (bits & ~kKnownPointFields)
    throw InputError(name + ": fields: unknown bits " + std::to_string(bits & ~kKnownPointFields) +
                     " (bit 0 normals, 1 intensity, 2 rgb, 3 classification)");
  if (count >= (std::uint64_t(1) << 32))
    throw InputError(name + ": count: " + std::to_string(count) + " points, expected fewer than 2^32");
  const std::size_t n = std::size_t(count);
  // The layout first, before anything is allocated: each array must fit in what is left (n < 2^32
  // and at most 12 bytes a point per array, so the products fit in 64 bits), and nothing may follow.
  const std::pair<const char*, std::size_t> layout[] = {{"positions", 12},
                                                        {"normals", bits & kNormals ? 6 : 0},
                                                        {"intensity", bits & kIntensity ? 2 : 0},
                                                        {"rgb", bits & kRgb ? 3 : 0},
                                                        {"classification", bits & kClassification ? 1 : 0}};
  std::uint64_t end = kPointsHeaderBytes;
  for (const auto& [field, elementBytes] : layout) {
    const std::uint64_t want = std::uint64_t(n) * elementBytes;
    if (want > size - end)
      throw InputError(name + ": " + field + ": " + std::to_string(n) + " points need " + std::to_string(want) +
                       " bytes from byte " + std::to_string(end) + ", the file has " + std::to_string(size) +
                       " (truncated?)");
    end += want;
  }
  if (end != size)
    throw InputError(name + ": trailing bytes: " + std::to_string(size - end) + " after the last field (" +
                     std::to_string(end) + " bytes expected for " + std::to_string(n) + " points with fields " +
                     std::to_string(bits) + ")");
  std::size_t offset = kPointsHeaderBytes;
  auto array = [&](std::size_t elementBytes) {
    const std::uint8_t* at = data + offset;
    offset += n * elementBytes;
    return at;
  };
  PointCloud cloud;
  cloud.sourcePath = name;
  cloud.resize(n, {.intensity = (bits & kIntensity) != 0,
                   .classification = (bits & kClassification) != 0,
                   .rgb = (bits & kRgb) != 0,
                   .normals = (bits & kNormals) != 0});
  if (n == 0) return cloud;  // no array to copy (and memcpy must not see their null data())
  {
    const std::uint8_t* at = array(12);
    std::vector<float> pos(3 * n);
    std::memcpy(pos.data(), at, pos.size() * sizeof(float));
    for (std::size_t i = 0; i < n; ++i) {
      const glm::vec3 r(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
      if (!std::isfinite(r.x) || !std::isfinite(r.y) || !std::isfinite(r.z))
        throw InputError(name + ": positions: point " + std::to_string(i) + " is not finite");
      cloud.positions[i] = origin + glm::dvec3(r);
    }
  }
  if (bits & kNormals) {
    const std::uint8_t* at = array(6);
    std::vector<std::int16_t> v(3 * n);
    std::memcpy(v.data(), at, v.size() * sizeof(std::int16_t));
    auto unorm = [](std::int16_t s) { return std::max(float(s) / 32767.0f, -1.0f); };
    for (std::size_t i = 0; i < n; ++i) cloud.normals[i] = {unorm(v[3 * i]), unorm(v[3 * i + 1]), unorm(v[3 * i + 2])};
  }
  if (bits & kIntensity) std::memcpy(cloud.intensity.data(), array(2), n * 2);
  if (bits & kRgb) {
    const std::uint8_t* at = array(3);
    for (std::size_t i = 0; i < n; ++i)
      cloud.rgb[i] = glm::u16vec3(at[3 * i], at[3 * i + 1], at[3 * i + 2]) * std::uint16_t(257);
  }
  if (bits & kClassification) std::memcpy(cloud.classification.data(), array(1), n);
  return cloud;
}

void writeWebScene(const Scene& scene, const std::vector<Photo>& photos, const std::string& dirPath) {
  const fs::path dir(dirPath);
  json meshes = json::array();
  const std::pair<const char*, const Mesh*> parts[] = {
      {"terrain", &scene.terrain}, {"buildings", &scene.buildings}, {"mesh", &scene.mesh}};
  for (const auto& [name, mesh] : parts) {
    if (mesh->empty()) continue;
    std::vector<float> pos;
    pos.reserve(mesh->positions.size() * 3);
    for (const auto& p : mesh->positions) {
      const glm::dvec3 r = p - scene.origin;
      pos.insert(pos.end(), {float(r.x), float(r.y), float(r.z)});
    }
    const bool tags = mesh->triangleTags.size() == mesh->triangles.size();
    std::string bytes;
    appendRaw(bytes, pos);
    appendRaw(bytes, mesh->triangles);
    if (tags) appendRaw(bytes, mesh->triangleTags);
    const std::string file = std::string(name) + ".bin";
    writeFile(dir / file, bytes);
    meshes.push_back({{"name", name},
                      {"path", file},
                      {"vertices", mesh->positions.size()},
                      {"triangles", mesh->triangles.size()},
                      {"tags", tags}});
  }
  json points;
  if (!scene.points.empty()) {
    const std::string bytes = webPointBytes(scene.points, scene.origin);
    writeFile(dir / kWebPointsFile, bytes);
    points = {{"path", kWebPointsFile}, {"count", scene.points.size()}, {"bytes", bytes.size()}};
  }
  json validity = json::array();
  for (const auto& v : scene.buildingValidity) validity.push_back({v.first, v.last});
  const Aabb b = scene.bounds();
  json manifest = {{"format", "histoview-web"},
                   {"version", 1},
                   {"crs", scene.crs},
                   {"origin", vec3Json(scene.origin)},
                   {"up", vec3Json(scene.up)},
                   {"bounds", {{"lo", vec3Json(b.lo)}, {"hi", vec3Json(b.hi)}}},
                   {"meshes", meshes},
                   {"buildingValidity", validity},
                   {"cameras", "cameras.json"}};
  if (!points.is_null()) manifest["points"] = points;
  if (scene.traffic && !scene.traffic->vehicles.empty()) {
    writeFile(dir / kWebTrafficFile, webTrafficCsv(*scene.traffic));
    json traffic = {{"csv", kWebTrafficFile},
                    {"vehicles", scene.traffic->vehicles.size()},
                    {"begin", scene.traffic->tBegin},
                    {"end", scene.traffic->tEnd}};
    if (scene.traffic->models) {
      writeFile(dir / kWebVehiclesFile, webVehicleModels(*scene.traffic->models).dump());
      traffic["models"] = kWebVehiclesFile;
    }
    manifest["traffic"] = traffic;
  }
  writeFile(dir / "cameras.json", cameraJson(photos, dir.string()));
  writeFile(dir / kWebSceneManifest, manifest.dump(1));
}

Scene readWebScene(const std::string& manifestPath, const WebSceneOptions& options, Diagnostics& diag) {
  const fs::path path(manifestPath);
  const fs::path dir = path.parent_path();
  json j;
  try {
    j = json::parse(readFileBytes(path));
  } catch (const json::exception& e) {
    throw InputError(manifestPath + ": not valid JSON: " + e.what());
  }
  if (!j.is_object() || j.value("format", std::string()) != "histoview-web")
    throw InputError(manifestPath + ": not a histoview web scene (\"format\": \"histoview-web\" expected)");
  Scene scene;
  scene.path = manifestPath;
  try {
    scene.crs = j.value("crs", std::string());
    // Without an origin (a service scene without an export, hv/io/web_scene_frame.h), the native
    // rule places it once everything is read; nothing may then be stored relative to it.
    if (j.contains("origin"))
      scene.origin = vec3Of(j["origin"], manifestPath + ": origin");
    else if (!j.value("meshes", json::array()).empty() || j.contains("points"))
      throw InputError(manifestPath +
                       ": origin: missing (expected [x, y, z]: the meshes and points are stored relative to it)");
    if (j.contains("up")) scene.up = vec3Of(j["up"], manifestPath + ": up");
    if (j.contains("buildingValidity")) {
      for (const auto& v : j["buildingValidity"]) {
        if (!v.is_array() || v.size() != 2) throw InputError(manifestPath + ": buildingValidity: expected [first, last]");
        scene.buildingValidity.push_back({v[0].get<std::int64_t>(), v[1].get<std::int64_t>()});
      }
    }
  } catch (const json::exception& e) {
    throw InputError(manifestPath + ": " + e.what());
  }
  for (const auto& m : j.value("meshes", json::array())) {
    const std::string name = m.value("name", std::string());
    try {
      Mesh* target = meshByName(scene, name);
      if (!target) throw InputError("unknown mesh name '" + name + "' (terrain, buildings or mesh)");
      *target = readMesh(dir / m.at("path").get<std::string>(), scene.origin, m.at("vertices").get<std::size_t>(),
                         m.at("triangles").get<std::size_t>(), m.value("tags", false));
    } catch (const std::exception& e) {
      diag.error(manifestPath + ": mesh '" + name + "': " + e.what());
    }
  }
  if (j.contains("terrain")) {
    try {
      readWebTerrainGrid(j["terrain"], dir.string(), scene);
    } catch (const std::exception& e) {
      diag.error(manifestPath + ": terrain: " + e.what() + " (terrain left out)");
    }
  }
  if (j.contains("buildings")) {
    try {
      readServiceBuildings(j["buildings"], dir, scene, diag);
    } catch (const std::exception& e) {
      diag.error(manifestPath + ": buildings: " + e.what() + " (buildings left out)");
    }
  }
  if (j.contains("points")) {
    try {
      const json& p = j["points"];
      if (!p.is_object() || !p.contains("path") || !p["path"].is_string())
        throw InputError("expected {\"path\": \"points.bin\", \"count\": N}");
      const fs::path file = dir / p["path"].get<std::string>();
      using clock = std::chrono::steady_clock;
      const auto ms = [](clock::time_point a, clock::time_point b) {
        return std::to_string(std::chrono::duration<double, std::milli>(b - a).count());
      };
      const auto t0 = clock::now();
      const std::string bytes = readFileBytes(file);
      const auto t1 = clock::now();
      if (p.contains("bytes") && (!p["bytes"].is_number_unsigned() || p["bytes"].get<std::uint64_t>() != bytes.size()))
        throw InputError(file.string() + ": " + std::to_string(bytes.size()) +
                         " bytes, the manifest's points.bytes says " + p["bytes"].dump() + " (an incomplete download?)");
      PointCloud cloud = parseWebPoints(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size(),
                                        scene.origin, file.string());
      if (p.contains("count") && (!p["count"].is_number_unsigned() || p["count"].get<std::uint64_t>() != cloud.size()))
        throw InputError("count: the manifest says " + p["count"].dump() + ", " + file.string() + " holds " +
                         std::to_string(cloud.size()));
      const auto t2 = clock::now();
      organizeChunks(cloud);
      const auto t3 = clock::now();
      log::debug("points: " + file.string() + ": " + std::to_string(cloud.size()) + " points in " +
                 std::to_string(cloud.chunks.size()) + " chunks: read " + ms(t0, t1) + " ms, parsed " + ms(t1, t2) +
                 " ms, organised " + ms(t2, t3) + " ms");
      scene.points = std::move(cloud);
    } catch (const std::exception& e) {
      diag.error(manifestPath + ": points: " + e.what() + " (points left out)");
    }
  }
  if (j.contains("traffic")) {
    // Trajectories in the scene frame, vehicle centres (the CSV form); models as fractions of the
    // vehicle's size. A broken file leaves the traffic out, named.
    try {
      const json& t = j["traffic"];
      if (!t.is_object() || !t.contains("csv") || !t["csv"].is_string())
        throw InputError("expected {\"csv\": \"traffic.csv\", \"models\": \"vehicles.json\"}");
      const fs::path csv = dir / t["csv"].get<std::string>();
      auto traffic = std::make_shared<Trajectories>(parseTrajectoriesCsv(readFileBytes(csv), csv.string(), diag));
      if (t.contains("models")) {
        if (!t["models"].is_string()) throw InputError("models: expected the name of a file");
        const fs::path file = dir / t["models"].get<std::string>();
        json m;
        try {
          m = json::parse(readFileBytes(file));
        } catch (const json::exception& e) {
          throw InputError(file.string() + ": not valid JSON: " + e.what());
        }
        traffic->models = readWebVehicleModels(m, file.string());
      }
      scene.trafficPath = csv.string();
      scene.traffic = std::move(traffic);
    } catch (const std::exception& e) {
      diag.error(manifestPath + ": traffic: " + e.what() + " (traffic left out)");
    }
  }
  CameraFileOptions camOptions;
  camOptions.checkImageFiles = options.checkImageFiles;
  try {
    if (j.contains("cameras") && j["cameras"].is_object())
      scene.photos = readServiceCameras(j["cameras"], dir, diag);
    else
      scene.photos = readCameraFile((dir / j.value("cameras", std::string("cameras.json"))).string(), camOptions, diag);
  } catch (const InputError& e) {
    diag.error(manifestPath + ": cameras: " + e.what());
  }
  settleWebSceneFrame(scene, j.contains("origin"), j.contains("up"), manifestPath, diag);
  return scene;
}

}  // namespace hv
