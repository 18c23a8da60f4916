// A photograph's edited layers read back (Layered projective texture maps, 2003, §5): the
// OpenRaster file `histoview layers export` wrote, after an artist painted in it, as sub-images with
// their windows in the photograph's pixels, ready to become projective textures through their
// sheared frusta (hv/layers/sub_image.h), each on its own visibility layer's surfaces
// (hv/layers/layered_texture.h).
#pragma once

#include "hv/camera/camera.h"
#include "hv/image/image.h"
#include "hv/layers/layered_texture.h"
#include "hv/layers/native/layer_export.h"
#include "hv/layers/sub_image.h"

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace hv::layers {

struct ImportedSubImage {
  int visibilityLayer = 0;  // k of the layer's name "L<k> ..."
  std::string name;
  SubImageWindow window;  // in the photograph's pixels (its camera's size)
  Image8 rgba;            // as painted, at the file's resolution
};

struct ImportedLayers {
  std::string path;
  int fileWidth = 0, fileHeight = 0;        // the .ora image's size
  std::vector<ImportedSubImage> subImages;  // the file's order: top first, L1 before L2
  int skipped = 0;                          // layers whose name does not start with "L<k> " (the guide, the background)
};

// scene.json's "layers": { "camera id": "file.ora" } (docs/formats.md), paths resolved against the
// scene file's folder. An entry naming no photograph of `scene`, or a file that does not exist, is
// reported in `diag` (naming scene.json, "layers" and the id) and left out. Empty without the key.
std::map<std::string, std::string> readLayerFiles(const Scene& scene, Diagnostics& diag);

// Reads `path` for the photograph of `camera`. Layers are kept when their name starts with
// "L<k> " (k >= 1) whatever their visibility; others are skipped and counted. Throws InputError
// naming the file when it cannot be read, when its aspect ratio is not the camera's (more than a
// pixel off), or when it holds no "L<k> " layer.
ImportedLayers importLayers(const std::string& path, const Camera& camera);

// The edited layers of photograph `photo` of `scene`, ready to texture the geometry
// (hv/layers/layered_texture.h): the sub-images of `layers` and one peeled depth map per visibility
// layer, from the rays cast and peeled again at the file's size with `settings`' objects and rays
// (the export's: the same scene, size and terrain tiles give the same layers; its size and pre-fill
// are not used). A sub-image of a layer deeper than the geometry now has is reported in `diag`
// (the file, the layer's name) and left out: the scene changed since the export.
LayeredPhotograph layeredPhotograph(const Scene& scene, std::size_t photo, const ImportedLayers& layers,
                                    const LayerExportSettings& settings, Diagnostics& diag);

// Texture memory (texels) of sub-images as the paper counts it (§4.2): each in the smallest
// power-of-two texture that holds it, against one whole power-of-two texture per visibility layer.
struct LayerTextureMemory {
  std::int64_t subImageTexels = 0, wholeImageTexels = 0;
  int visibilityLayers = 0, subImages = 0;
};
LayerTextureMemory layerTextureMemory(const std::vector<int>& visibilityLayerOfSubImage,
                                      const std::vector<glm::ivec2>& subImageSizes, int width, int height);

}  // namespace hv::layers
