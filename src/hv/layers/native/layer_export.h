// A photograph's layered image for editing (Layered projective texture maps, 2003, §4): its
// visibility layers (hv/layers/visibility_layers.h) from rays cast against the scene, each layer's
// objects grouped into sub-images by the power-of-two rule (hv/layers/clustering.h), and the
// pixels of each sub-image:
// - where the photograph sees the layer's surface (its first surface on the ray), the photograph's
//   own pixel (a pixel its mask discards counts as not seen);
// - where the surface is hidden, pre-filled from another photograph of the scene that sees the
//   same surface point (the point projected into it, and the ray cast from its camera to the point
//   meeting nothing before it); of those, the one with the finest footprint (distance / focal);
// - elsewhere transparent.
// Then a "background" layer (the photograph where no ray meets the geometry: the sky) and a hidden
// guide layer outlining every object, for the OpenRaster file (hv/layers/native/openraster.h).
#pragma once

#include "hv/layers/clustering.h"
#include "hv/layers/native/openraster.h"
#include "hv/layers/native/scene_objects.h"
#include "hv/layers/visibility_layers.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace hv::layers {

struct LayerExportSettings {
  int width = 0, height = 0;  // the layers' size; 0: the photograph's (same aspect ratio required)
  bool prefill = true;        // false: hidden parts stay transparent
  double terrainTileMetres = 50.0;
  // A point counts as seen by another photograph when that camera's first hit towards it lies
  // within this of it: metres plus a fraction of the distance.
  double seenToleranceMetres = 0.05, seenToleranceRelative = 2e-3;
  int namesPerLayer = 6;  // objects named in a layer's name before "+N more"
  RayCastSettings rays;
  // Whole-object layers found another way, for the camera at the layers' size (the GL pass,
  // render/layer_peeling.h: 1-based layer per object, 0 for those it leaves); the hits then take
  // them and the rest is peeled on the CPU (completeVisibilityLayers). Empty: the CPU reference
  // peels every layer.
  std::function<std::vector<std::uint16_t>(const Camera&, const SceneObjects&)> objectLayers;
};

struct ImageLayerInfo {
  int visibilityLayer = 0;  // 1-based
  std::string name;
  PixelBox box;
  std::vector<std::uint32_t> objects;
  std::size_t photoPixels = 0, prefilledPixels = 0, emptyPixels = 0;  // of the layer's object pixels
};

struct LayerExport {
  Camera camera;  // the photograph's camera at the layers' size
  SceneObjects objects;
  PixelHits hits;
  VisibilityLayers visibility;
  std::vector<std::uint16_t> gpuObjectLayers;  // what settings.objectLayers gave, when set
  std::vector<ImageLayerInfo> imageLayers;     // in the stack's order
  std::vector<std::string> cycleNames;         // each cycle met (visibility.splits), its objects' names joined
  OraDocument document;                        // top first: guide, L1..., background
  int prefillPhotos = 0;                       // other photographs decoded for the pre-fill
  double castSeconds = 0.0, peelSeconds = 0.0, fillSeconds = 0.0;
};

// Builds the layers of scene.photos[photo]. Throws InputError naming the camera when its image
// cannot be read or the size does not fit its aspect ratio; another photograph that cannot be read
// is reported in `diag` and left out of the pre-fill.
LayerExport exportLayers(const Scene& scene, std::size_t photo, const LayerExportSettings& settings, Diagnostics& diag);

}  // namespace hv::layers
