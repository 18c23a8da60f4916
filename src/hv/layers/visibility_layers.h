// Visibility layers of a photograph (Layered projective texture maps, 2003, §4.1), CPU reference:
// the objects seen from the photograph's camera peeled in visibility order. Layer 1 holds the
// objects of the working set that are never behind another object of the working set on any ray;
// they leave the working set, and the next layer is peeled the same way, until the set is empty.
// An object hiding part of itself (an L-shaped building, a courtyard) does not block its own layer.
//
// The input is what a ray caster returns from the photograph: per pixel, the surfaces along its
// ray (object id and depth), nearest first. The paper peels on the GPU (item buffer, inverted depth
// test, stencil count); this is the same rule on per-pixel lists, the reference for such a pass.
//
// Cycles: when every object of the working set is behind another one somewhere (three objects
// overlapping one another in a ring), none can be taken whole. The paper splits the objects into
// faces, then triangles, and cuts cycles (Newell et al.). Here, with per-pixel data, one cycle is
// found and reported, and it is broken by splitting each of its objects at pixel level: the
// pixels where the object is the nearest surface of the working set go to the current layer, the
// rest of the object stays in the working set for the next layers. A split object then appears in
// several layers, each with its own pixels.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hv::layers {

struct SurfaceHit {
  std::uint32_t object = 0;
  double depth = 0.0;  // along the ray, any monotonic measure (distance, camera z)
};

// Per-pixel hit lists, compressed: the hits of pixel p (row-major, p = y * width + x) are
// hits[first[p] .. first[p + 1]), nearest first. first has width * height + 1 entries.
struct PixelHits {
  int width = 0, height = 0;
  std::vector<std::uint32_t> first{0};
  std::vector<SurfaceHit> hits;

  std::size_t pixelCount() const { return std::size_t(width) * std::size_t(height); }
  // Appends the next pixel's hits (sorted here by depth, ties kept in order).
  void appendPixel(std::vector<SurfaceHit> pixelHits);
};

struct VisibilityLayer {
  std::vector<std::uint32_t> objects;  // increasing
  std::vector<std::uint32_t> split;    // those of `objects` split by a cycle (only part of them here)
};

struct VisibilityLayers {
  std::vector<VisibilityLayer> layers;  // layers[0] is layer 1
  // Parallel to PixelHits::hits: the 1-based layer of each hit (0: not assigned, which does not
  // happen on return).
  std::vector<std::uint16_t> layerOfHit;
  // Each cycle met, as its objects in occlusion order (each one hides part of the next, the last
  // hides part of the first).
  std::vector<std::vector<std::uint32_t>> cycles;

  // The nearest hit of layer `layer` (1-based) at pixel p, as an index into PixelHits::hits; -1 when
  // the layer has nothing on that pixel's ray.
  std::int64_t hitOfLayer(const PixelHits& hits, std::size_t pixel, int layer) const;
};

// Peels the layers. Throws std::invalid_argument when `hits` is not consistent (sizes of first).
// More than 65535 layers is reported the same way (a scene that deep is not an editing job).
VisibilityLayers peelVisibilityLayers(const PixelHits& hits);

}  // namespace hv::layers
