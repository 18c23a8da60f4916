#include "hv/io/web_scene.h"

#include "hv/io/cameras_json.h"

#include <nlohmann/json.hpp>

#include <bit>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
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
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

void writeFile(const fs::path& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), std::streamsize(bytes.size()));
  if (!f) throw std::runtime_error(path.string() + ": cannot write");
}

std::string readFileBytes(const fs::path& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path.string() + ": cannot open file");
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
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

}  // namespace

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
    scene.origin = vec3Of(j.at("origin"), manifestPath + ": origin");
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
  CameraFileOptions camOptions;
  camOptions.checkImageFiles = options.checkImageFiles;
  const std::string cameras = j.value("cameras", std::string("cameras.json"));
  try {
    scene.photos = readCameraFile((dir / cameras).string(), camOptions, diag);
  } catch (const InputError& e) {
    diag.error(e.what());
  }
  return scene;
}

}  // namespace hv
