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
// overlapping one another in a ring, a shed in a courtyard), none can be taken whole. As the paper
// does (§4.1), the objects of the blocking cycle are split: the cycle is a source component of the
// "hides part of" relation among the working set (strongly connected, nothing outside it hides any
// of it), and its objects are split into their faces (planar groups of triangles, given with the
// hits), which are peeled as items of their own; faces that still form such a cycle are split into
// their triangles. Triangles that still do (interpenetrating or cyclically overlapping triangles)
// are a cycle reported as such and broken at pixel level: the pixels where a triangle of the cycle
// is the nearest surface of the working set go to the current layer, the rest stays in the working
// set for the next layers. Without faces (hits with no triangle), objects go straight to the
// pixel-level break.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hv::layers {

inline constexpr std::uint32_t kNoTriangle = 0xffffffffu;

struct SurfaceHit {
  std::uint32_t object = 0;
  double depth = 0.0;                    // along the ray, any monotonic measure (distance, camera z)
  std::uint32_t triangle = kNoTriangle;  // the triangle hit (an index into faceOfTriangle)
};

// Per-pixel hit lists, compressed: the hits of pixel p (row-major, p = y * width + x) are
// hits[first[p] .. first[p + 1]), nearest first. first has width * height + 1 entries.
struct PixelHits {
  int width = 0, height = 0;
  std::vector<std::uint32_t> first{0};
  std::vector<SurfaceHit> hits;
  // Per triangle, its face: a planar group of triangles of one object, numbered across all objects.
  // Empty: objects cannot be split (a cycle is broken at pixel level at once); otherwise every hit
  // names a triangle below its size.
  std::vector<std::uint32_t> faceOfTriangle;

  std::size_t pixelCount() const { return std::size_t(width) * std::size_t(height); }
  // Appends the next pixel's hits (sorted here by depth, ties kept in order).
  void appendPixel(std::vector<SurfaceHit> pixelHits);
};

struct VisibilityLayer {
  std::vector<std::uint32_t> objects;  // increasing
  // Those of `objects` here only in part: split into faces or triangles by a cycle (the pieces
  // here), or broken at pixel level in this layer. Increasing.
  std::vector<std::uint32_t> split;
};

// A cycle met while peeling, and how it was split.
struct CycleSplit {
  enum class Into { Faces, Triangles, Pixels };
  Into into = Into::Faces;
  std::vector<std::uint32_t> objects;  // a cycle through them, in occlusion order (each hides part of the next)
  std::size_t items = 0;               // the items of the cycle (objects, faces or triangles) before the split
  int beforeLayer = 1;                 // 1-based: the layer being peeled when it was met
};

struct VisibilityLayers {
  std::vector<VisibilityLayer> layers;  // layers[0] is layer 1
  // Parallel to PixelHits::hits: the 1-based layer of each hit (0: not assigned, which does not
  // happen on return).
  std::vector<std::uint16_t> layerOfHit;
  // Each cycle broken at pixel level (not ordered by splitting into faces and triangles), as its
  // objects in occlusion order (each one hides part of the next, the last hides part of the first).
  std::vector<std::vector<std::uint32_t>> cycles;
  // Every cycle met, in order: split into faces, into triangles, or broken at pixel level.
  std::vector<CycleSplit> splits;
  // The pieces the peel ended with: the objects split into faces, and the faces split into
  // triangles (increasing). A hit's piece is its triangle when its face is split, else its face
  // when its object is split, else its object (pieceOf).
  std::vector<std::uint32_t> splitObjects, splitFaces;

  enum class PieceKind : std::uint8_t { Object, Face, Triangle };
  struct Piece {
    PieceKind kind = PieceKind::Object;
    std::uint32_t id = 0;  // object, face or triangle
    bool operator==(const Piece&) const = default;
  };
  Piece pieceOf(const PixelHits& hits, const SurfaceHit& hit) const;

  // The nearest hit of layer `layer` (1-based) at pixel p, as an index into PixelHits::hits; -1 when
  // the layer has nothing on that pixel's ray.
  std::int64_t hitOfLayer(const PixelHits& hits, std::size_t pixel, int layer) const;
};

// Peels the layers. Throws std::invalid_argument when `hits` is not consistent (sizes of first, a
// hit's triangle beyond faceOfTriangle).
// More than 65535 layers is reported the same way (a scene that deep is not an editing job).
VisibilityLayers peelVisibilityLayers(const PixelHits& hits);

}  // namespace hv::layers
