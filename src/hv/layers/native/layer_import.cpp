#include "hv/layers/native/layer_import.h"

#include "hv/layers/clustering.h"
#include "hv/layers/native/openraster.h"
#include "hv/util/diagnostics.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

namespace hv::layers {

namespace {

// k of "L<k> ...", 0 when the name is not of that form.
int visibilityLayerOf(const std::string& name) {
  if (name.size() < 3 || name[0] != 'L') return 0;
  std::size_t i = 1;
  int k = 0;
  while (i < name.size() && name[i] >= '0' && name[i] <= '9' && k < 100000) k = k * 10 + (name[i++] - '0');
  if (i == 1 || i >= name.size() || name[i] != ' ') return 0;
  return k;
}

}  // namespace

std::map<std::string, std::string> readLayerFiles(const Scene& scene, Diagnostics& diag) {
  namespace fs = std::filesystem;
  std::map<std::string, std::string> out;
  nlohmann::json doc;
  try {
    std::ifstream f(scene.path);
    doc = nlohmann::json::parse(f);
  } catch (const std::exception& e) {
    diag.error(scene.path + ": cannot be read again for its layers: " + e.what());
    return out;
  }
  if (!doc.is_object() || !doc.contains("layers")) return out;
  const nlohmann::json& layers = doc["layers"];
  if (!layers.is_object()) {
    diag.error(scene.path + ": layers: expected an object { \"camera id\": \"file.ora\" } (layers left out)");
    return out;
  }
  const fs::path dir = fs::path(scene.path).parent_path();
  for (const auto& [id, file] : layers.items()) {
    const std::string where = scene.path + ": layers: '" + id + "'";
    if (!file.is_string() || file.get<std::string>().empty()) {
      diag.error(where + ": expected the path of an OpenRaster file (left out)");
      continue;
    }
    if (std::none_of(scene.photos.begin(), scene.photos.end(), [&](const Photo& p) { return p.camera.id == id; })) {
      diag.error(where + ": no photograph with this camera id (left out)");
      continue;
    }
    const fs::path p = file.get<std::string>();
    const std::string resolved = (p.is_absolute() ? p : dir / p).lexically_normal().string();
    if (!fs::is_regular_file(resolved)) {
      diag.error(where + ": " + resolved + ": no such file (left out)");
      continue;
    }
    out[id] = resolved;
  }
  return out;
}

ImportedLayers importLayers(const std::string& path, const Camera& camera) {
  OraDocument doc = readOpenRaster(path);
  ImportedLayers out;
  out.path = path;
  out.fileWidth = doc.width;
  out.fileHeight = doc.height;
  const double s = double(camera.width) / doc.width;
  if (std::abs(doc.height * s - camera.height) > 1.0)
    throw InputError(path + ": stack.xml: the image is " + std::to_string(doc.width) + "x" +
                     std::to_string(doc.height) + ", not of the aspect ratio of camera '" + camera.id + "' (" +
                     std::to_string(camera.width) + "x" + std::to_string(camera.height) + ")");
  for (OraLayer& l : doc.layers) {
    const int k = visibilityLayerOf(l.name);
    if (k <= 0) {
      ++out.skipped;
      continue;
    }
    ImportedSubImage sub;
    sub.visibilityLayer = k;
    sub.name = l.name;
    sub.window.pxMin = glm::dvec2(l.x, l.y) * s;
    sub.window.pxMax = glm::dvec2(l.x + l.rgba.width, l.y + l.rgba.height) * s;
    sub.rgba = std::move(l.rgba);
    out.subImages.push_back(std::move(sub));
  }
  if (out.subImages.empty())
    throw InputError(path + ": stack.xml: no layer named \"L<k> ...\" (the layers histoview layers export writes)");
  return out;
}

LayerTextureMemory layerTextureMemory(const std::vector<int>& visibilityLayerOfSubImage,
                                      const std::vector<glm::ivec2>& subImageSizes, int width, int height) {
  LayerTextureMemory m;
  for (const glm::ivec2& size : subImageSizes) m.subImageTexels += powerOfTwoArea({0, 0, size.x, size.y});
  m.subImages = int(subImageSizes.size());
  m.visibilityLayers = int(std::set<int>(visibilityLayerOfSubImage.begin(), visibilityLayerOfSubImage.end()).size());
  m.wholeImageTexels = std::int64_t(m.visibilityLayers) * powerOfTwoArea({0, 0, width, height});
  return m;
}

LayeredPhotograph layeredPhotograph(const Scene& scene, std::size_t photo, const ImportedLayers& layers,
                                    const LayerExportSettings& settings, Diagnostics& diag) {
  LayerExportSettings s = settings;
  s.width = layers.fileWidth;
  s.height = layers.fileHeight;
  s.prefill = false;
  Diagnostics quiet;  // the export's own notes (cycles) were given when the file was made
  const LayerExport ex = exportLayers(scene, photo, s, quiet);
  LayeredPhotograph out;
  out.camera = scene.photos.at(photo).camera;
  const int depth = int(ex.visibility.layers.size());
  for (int k = 1; k <= depth; ++k) out.depthMaps.push_back(peeledDepthMap(ex.hits, ex.visibility, k));
  for (const ImportedSubImage& sub : layers.subImages) {
    if (sub.visibilityLayer > depth) {
      diag.error(layers.path + ": layer '" + sub.name + "': visibility layer " + std::to_string(sub.visibilityLayer) +
                 ", the geometry seen from '" + out.camera.id + "' now has " + std::to_string(depth) + "; left out");
      continue;
    }
    out.subImages.push_back({sub.visibilityLayer, sub.window, sub.rgba});
  }
  return out;
}

}  // namespace hv::layers
