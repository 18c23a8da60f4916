// OpenRaster files (.ora: the layered image format GIMP, Krita and MyPaint open), written and read
// through libzip. The layout (OpenRaster 0.0.5 specification):
// - a zip whose first entry is `mimetype`, stored (not compressed), holding "image/openraster";
// - `stack.xml`: <image version w h><stack><layer name src x y visibility opacity/>...</stack></image>,
//   layers listed top first;
// - one PNG per layer (`data/<n>.png`), placed at (x, y) in the image;
// - `mergedimage.png`, the visible layers composited, full size;
// - `Thumbnails/thumbnail.png`, the same at most 256 pixels on its longer side.
#pragma once

#include "hv/image/image.h"

#include <string>
#include <vector>

namespace hv::layers {

struct OraLayer {
  std::string name;
  int x = 0, y = 0;     // where the layer's top-left pixel sits in the image
  bool visible = true;  // visibility="visible" | "hidden"
  Image8 rgba;          // 4 channels, straight (not premultiplied) alpha
  std::string src;      // the entry it was read from (set by readOpenRaster)
};

struct OraDocument {
  int width = 0, height = 0;
  std::vector<OraLayer> layers;  // top first
};

// The visible layers composited bottom to top ("source over", straight alpha): RGBA, full size.
Image8 compositeLayers(const OraDocument& doc);

// Writes the document. Throws std::runtime_error naming the file on failure (and when a layer is
// not RGBA or the image size is not positive).
void writeOpenRaster(const std::string& path, const OraDocument& doc);

// Reads a document written by any OpenRaster editor: stack.xml's layers (nested stacks are
// flattened, their layers kept in order) with their PNGs decoded to RGBA. Throws InputError naming
// the file and the entry or attribute at fault.
OraDocument readOpenRaster(const std::string& path);

}  // namespace hv::layers
