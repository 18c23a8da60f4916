// Visibility layers peeled on the GPU (Layered projective texture maps, 2003, §4.1): the paper's
// item buffer and inverted depth test in GLES 3.0. The CPU reference is hv/layers/visibility_layers.h
// over the rays of hv/layers/native/scene_objects.h; this pass gives the same whole-object layers
// and stops at the first cycle, which the CPU finishes (hv::layers::completeVisibilityLayers).
//
// Per layer: an item buffer (RG32UI: object id + 1, distance along the ray as float bits) of the
// working set from the photograph's camera, with the depth test; then each object of the working
// set drawn again in an occlusion query (GL_ANY_SAMPLES_PASSED) whose fragments pass where the
// item buffer holds another object in front of them: the object is blocked. Its own surfaces in
// front of it (an L-shape's near wing, a courtyard's front wall) do not block it. The objects no
// query saw blocked are the layer; they leave the working set. When every object left is blocked,
// the pass stops (a cycle: the CPU reference splits it into faces, triangles, or at pixel level).
//
// As the ray caster does, only surfaces facing the camera count, and none under the ground: a
// terrain pass stores where each pixel's ray enters the ground (nearest terrain surface facing the
// camera) and where it leaves it (nearest facing away); what lies between hides nothing. A ray that
// enters the ground a second time (behind a hill, then a second hill) is not followed there.
// Pixels are the camera's ideal (pinhole) pixels over the rectangle covering its image
// (hv::idealRectCoveringImage): for a camera with a lens model the grid is not the ray caster's
// distorted one, and an object seen only at the image's border may be seen by one and not the other.
#pragma once

#include "hv/camera/camera.h"
#include "hv/scene/mesh.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hv::render {

struct GpuLayerPeelSettings {
  // Two surfaces closer than this along a ray are one (the ray caster's same-surface tolerance):
  // metres plus a fraction of the distance.
  double sameSurfaceMetres = 1e-3, sameSurfaceRelative = 1e-5;
};

struct GpuObjectLayers {
  // Per object: its 1-based layer; 0 for an object no pixel sees, and for those left when the pass
  // stopped at a cycle.
  std::vector<std::uint16_t> layerOfObject;
  int layers = 0;               // whole-object layers peeled
  bool stoppedAtCycle = false;  // objects were left, each behind another one somewhere
  std::size_t objectsSeen = 0;  // objects some pixel sees (the first working set)
  std::size_t queries = 0;      // occlusion queries issued
};

// Peels the objects of `geometry` (objectOfTriangle[t] < objectCount: triangle t's object;
// terrainTriangle[t]: a terrain triangle) seen from `camera` at its size. Needs a current GLES 3.0
// context; throws std::invalid_argument when the arrays do not match the mesh, std::runtime_error
// when the context cannot do it.
GpuObjectLayers peelObjectLayersGl(const Camera& camera, const Mesh& geometry,
                                   const std::vector<std::uint32_t>& objectOfTriangle,
                                   const std::vector<bool>& terrainTriangle, std::size_t objectCount,
                                   const GpuLayerPeelSettings& settings = {});

}  // namespace hv::render
