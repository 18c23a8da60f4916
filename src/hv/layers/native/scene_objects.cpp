#include "hv/layers/native/scene_objects.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <utility>

namespace hv::layers {

std::vector<std::uint32_t> faceGroups(const Mesh& mesh, const std::vector<std::uint32_t>& objectOfTriangle,
                                      double angleDegrees) {
  const std::size_t n = mesh.triangles.size();
  if (objectOfTriangle.size() != n)
    throw std::invalid_argument("face groups: " + std::to_string(objectOfTriangle.size()) + " object ids for " +
                                std::to_string(n) + " triangles");
  // Vertices welded by position (meshes appended or extruded may repeat a corner).
  std::map<std::tuple<double, double, double>, std::uint32_t> weld;
  std::vector<std::uint32_t> vertex(mesh.positions.size());
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const glm::dvec3& p = mesh.positions[v];
    vertex[v] = weld.try_emplace({p.x, p.y, p.z}, std::uint32_t(weld.size())).first->second;
  }
  std::vector<glm::dvec3> normal(n, glm::dvec3(0.0));
  for (std::size_t t = 0; t < n; ++t) {
    const glm::uvec3& tri = mesh.triangles[t];
    const glm::dvec3 c =
        glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x], mesh.positions[tri.z] - mesh.positions[tri.x]);
    const double len = glm::length(c);
    if (len > 0.0 && std::isfinite(len)) normal[t] = c / len;
  }
  std::vector<std::uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto root = [&](std::uint32_t t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  const double cosMax = std::cos(angleDegrees * 3.14159265358979323846 / 180.0);
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> edgeOf;  // welded edge -> triangles
  for (std::uint32_t t = 0; t < n; ++t) {
    if (normal[t] == glm::dvec3(0.0)) continue;
    const glm::uvec3& tri = mesh.triangles[t];
    const std::uint32_t v[3] = {vertex[tri.x], vertex[tri.y], vertex[tri.z]};
    for (int e = 0; e < 3; ++e) {
      const auto key = std::minmax(v[e], v[(e + 1) % 3]);
      std::vector<std::uint32_t>& sharing = edgeOf[{key.first, key.second}];
      for (std::uint32_t u : sharing)
        if (objectOfTriangle[u] == objectOfTriangle[t] && glm::dot(normal[u], normal[t]) >= cosMax)
          parent[root(u)] = root(t);
      sharing.push_back(t);
    }
  }
  std::vector<std::uint32_t> face(n), number(n, std::numeric_limits<std::uint32_t>::max());
  std::uint32_t faces = 0;
  for (std::uint32_t t = 0; t < n; ++t) {
    const std::uint32_t r = root(t);
    if (number[r] == std::numeric_limits<std::uint32_t>::max()) number[r] = faces++;
    face[t] = number[r];
  }
  return face;
}

SceneObjects collectSceneObjects(const Scene& scene, double terrainTileMetres) {
  SceneObjects out;
  std::map<std::pair<int, std::uint32_t>, std::uint32_t> index;  // (kind, tag) -> object
  auto objectFor = [&](SceneObject::Kind kind, std::uint32_t tag, const std::string& name) {
    const auto key = std::make_pair(int(kind), tag);
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    const auto id = std::uint32_t(out.objects.size());
    out.objects.push_back({kind, tag, name});
    index.emplace(key, id);
    return id;
  };

  const Mesh& terrain = scene.terrain;
  const Aabb tb = terrain.bounds();
  const double side = terrainTileMetres > 0.0 ? terrainTileMetres : 1e30;
  // Tiles are numbered over a grid anchored at the terrain's lower corner, named by column and row.
  const int columns = tb.empty() ? 1 : std::max(1, int(std::ceil((tb.hi.x - tb.lo.x) / side)) + 1);
  for (std::size_t t = 0; t < terrain.triangles.size(); ++t) {
    const glm::uvec3& tri = terrain.triangles[t];
    const glm::dvec3 c = (terrain.positions[tri.x] + terrain.positions[tri.y] + terrain.positions[tri.z]) / 3.0;
    const int i = std::clamp(int(std::floor((c.x - tb.lo.x) / side)), 0, columns - 1);
    const int j = std::max(0, int(std::floor((c.y - tb.lo.y) / side)));
    const auto tile = std::uint32_t(j * columns + i);
    out.objectOfTriangle.push_back(
        objectFor(SceneObject::Kind::Terrain, tile, "terrain " + std::to_string(i) + "," + std::to_string(j)));
  }
  out.geometry.append(terrain);
  const Mesh& b = scene.buildings;
  for (std::size_t t = 0; t < b.triangles.size(); ++t) {
    const std::uint32_t tag = b.triangleTags.size() == b.triangles.size() ? b.triangleTags[t] : 0;
    out.objectOfTriangle.push_back(objectFor(SceneObject::Kind::Building, tag, "building " + std::to_string(tag)));
  }
  out.geometry.append(b);
  const Mesh& m = scene.mesh;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const std::uint32_t tag = m.triangleTags.size() == m.triangles.size() ? m.triangleTags[t] : 0;
    out.objectOfTriangle.push_back(objectFor(SceneObject::Kind::MeshPart, tag, "mesh " + std::to_string(tag)));
  }
  out.geometry.append(m);
  out.terrainTriangle.assign(out.geometry.triangles.size(), false);
  std::fill(out.terrainTriangle.begin(), out.terrainTriangle.begin() + std::ptrdiff_t(terrain.triangles.size()), true);
  out.faceOfTriangle = faceGroups(out.geometry, out.objectOfTriangle);
  return out;
}

std::optional<glm::dvec3> pixelRay(const Camera& camera, int x, int y) {
  const auto ideal = camera.undistort(glm::dvec2(x + 0.5, y + 0.5));
  if (!ideal) return std::nullopt;
  return glm::normalize(camera.rayDirection(*ideal));
}

PixelHits castPixelHits(const Camera& camera, const SceneObjects& objects, const RayQuery& caster,
                        const RayCastSettings& settings) {
  const int w = camera.width, h = camera.height;
  std::vector<std::vector<SurfaceHit>> perPixel(std::size_t(w) * std::size_t(h));
  auto castRow = [&](int y) {
    for (int x = 0; x < w; ++x) {
      const auto dir = pixelRay(camera, x, y);
      if (!dir) continue;
      std::vector<SurfaceHit>& hits = perPixel[std::size_t(y) * std::size_t(w) + std::size_t(x)];
      bool underground = false;
      double tMin = 0.0;
      for (int k = 0; k < settings.maxHitsPerRay; ++k) {
        const auto hit = caster.intersect(camera.center, *dir, tMin);
        if (!hit) break;
        tMin = hit->t + settings.sameSurfaceMetres + settings.sameSurfaceRelative * hit->t;
        const bool facing = glm::dot(hit->normal, *dir) < 0.0;
        if (objects.terrainTriangle[hit->triangle]) {
          if (!underground && facing) hits.push_back({objects.objectOfTriangle[hit->triangle], hit->t, hit->triangle});
          underground = facing;  // entering the ground from above, or leaving it
          continue;
        }
        if (facing && !underground) hits.push_back({objects.objectOfTriangle[hit->triangle], hit->t, hit->triangle});
      }
    }
  };
  const unsigned threads = std::max(1u, std::min(std::thread::hardware_concurrency(), 16u));
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t)
    pool.emplace_back([&, t] {
      for (int y = int(t); y < h; y += int(threads)) castRow(y);
    });
  for (std::thread& t : pool) t.join();
  PixelHits out;
  out.width = w;
  out.height = h;
  out.faceOfTriangle = objects.faceOfTriangle;
  for (auto& p : perPixel) out.appendPixel(std::move(p));
  return out;
}

}  // namespace hv::layers
