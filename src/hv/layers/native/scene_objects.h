// The objects of a scene that visibility layers are made of (Layered projective texture maps,
// 2003, §4.1), and the rays cast from a photograph that order them.
//
// Objects: each building (the buildings mesh's triangle tag, the feature index the LOD1 extrusion
// and the CityJSON reader give it), the terrain cut into square tiles of the world's xy grid (a
// triangle belongs to the tile of its centroid), and each part of the mesh (its triangle tag; the
// whole mesh when it has none).
#pragma once

#include "hv/camera/camera.h"
#include "hv/layers/visibility_layers.h"
#include "hv/scene/mesh.h"
#include "hv/scene/ray_query.h"
#include "hv/scene/scene.h"

#include <cstdint>
#include <string>
#include <vector>

namespace hv::layers {

struct SceneObject {
  enum class Kind { Terrain, Building, MeshPart };
  Kind kind = Kind::Building;
  std::uint32_t tag = 0;  // building or mesh tag; for terrain the tile index
  std::string name;       // "building 12", "terrain 3,-1", "mesh 0"
};

struct SceneObjects {
  Mesh geometry;                                // terrain, then buildings, then the mesh
  std::vector<std::uint32_t> objectOfTriangle;  // index into `objects`
  std::vector<bool> terrainTriangle;            // true for the terrain's triangles
  std::vector<std::uint32_t> faceOfTriangle;    // its face (faceGroups), what a cycle splits objects into
  std::vector<SceneObject> objects;
};

// The faces of the objects of `mesh`, for splitting an object that a cycle keeps from being
// ordered whole (Layered projective texture maps, 2003, §4.1): per triangle, its face, numbered
// from 0 in the order of the faces' first triangles. A face is a group of triangles of one object
// (objectOfTriangle) connected through shared edges (vertices at equal positions) whose normals
// agree within `angleDegrees`: a building's wall, its roof, a flat terrain tile. A degenerate
// triangle is a face of its own. Throws std::invalid_argument when objectOfTriangle does not match.
std::vector<std::uint32_t> faceGroups(const Mesh& mesh, const std::vector<std::uint32_t>& objectOfTriangle,
                                      double angleDegrees = 0.1);

// `terrainTileMetres` > 0: the side of the terrain tiles.
SceneObjects collectSceneObjects(const Scene& scene, double terrainTileMetres);

struct RayCastSettings {
  int maxHitsPerRay = 64;
  // Two hits closer than this along a ray are one surface (a shared edge, coplanar triangles):
  // metres plus a fraction of the distance (Embree traces in float).
  double sameSurfaceMetres = 1e-3, sameSurfaceRelative = 1e-5;
};

// Casts one ray through the centre of each pixel of `camera` (its distorted pixels: the ray goes
// through the undistorted position; pixels outside the lens model's domain get no hit) and keeps,
// nearest first, the surfaces that face the camera and are not under the ground: a ray that enters
// the terrain from above is underground until it leaves it, and what it meets there (the buried
// foot of a wall on a slope) hides nothing. Depths are distances along the unit ray from the
// camera centre; each hit names its triangle, and the hit lists carry objects.faceOfTriangle. Rows
// are shared among the cores.
PixelHits castPixelHits(const Camera& camera, const SceneObjects& objects, const RayQuery& caster,
                        const RayCastSettings& settings = {});

// The unit world direction of the ray through pixel (x, y)'s centre; nullopt outside the domain.
std::optional<glm::dvec3> pixelRay(const Camera& camera, int x, int y);

}  // namespace hv::layers
