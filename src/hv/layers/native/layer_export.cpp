#include "hv/layers/native/layer_export.h"

#include "hv/camera/frustum.h"
#include "hv/image/image.h"
#include "hv/layers/object_layers.h"
#include "hv/scene/native/raycast.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <unordered_set>

namespace hv::layers {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Another photograph, decoded, for the pre-fill.
struct Source {
  const Camera* camera = nullptr;
  Image8 rgb, mask;
};

// Bilinear RGB at a position in camera pixels (the image may have another size, same aspect).
std::optional<glm::u8vec3> sample(const Source& s, glm::dvec2 px) {
  const double scale = double(s.rgb.width) / s.camera->width;
  const glm::dvec2 p = px * scale - 0.5;  // texel centres at +0.5
  const int x0 = int(std::floor(p.x)), y0 = int(std::floor(p.y));
  if (x0 < 0 || y0 < 0 || x0 + 1 >= s.rgb.width || y0 + 1 >= s.rgb.height) return std::nullopt;
  if (!s.mask.empty()) {
    const double ms = double(s.mask.width) / s.rgb.width;
    const int mx = std::clamp(int((p.x + 0.5) * ms), 0, s.mask.width - 1);
    const int my = std::clamp(int((p.y + 0.5) * ms), 0, s.mask.height - 1);
    if (s.mask.at(mx, my, 0) < 128) return std::nullopt;
  }
  const double fx = p.x - x0, fy = p.y - y0;
  glm::u8vec3 out;
  for (int c = 0; c < 3; ++c) {
    const double v = (1 - fx) * (1 - fy) * s.rgb.at(x0, y0, c) + fx * (1 - fy) * s.rgb.at(x0 + 1, y0, c) +
                     (1 - fx) * fy * s.rgb.at(x0, y0 + 1, c) + fx * fy * s.rgb.at(x0 + 1, y0 + 1, c);
    out[c] = std::uint8_t(std::clamp(std::lround(v), 0L, 255L));
  }
  return out;
}

std::string layerName(int k, const std::vector<std::uint32_t>& members, const VisibilityLayer& layer,
                      const SceneObjects& objects, int namesPerLayer) {
  std::string name = "L" + std::to_string(k);
  const std::unordered_set<std::uint32_t> split(layer.split.begin(), layer.split.end());
  for (std::size_t i = 0; i < members.size(); ++i) {
    if (int(i) == namesPerLayer) {
      name += " +" + std::to_string(members.size() - i) + " more";
      break;
    }
    name += (i == 0 ? " " : ", ") + objects.objects[members[i]].name;
    if (split.count(members[i])) name += " (part)";
  }
  return name;
}

// A colour per object for the guide layer (a hash spread over bright hues).
glm::u8vec3 guideColour(std::uint32_t object) {
  std::uint32_t h = object * 2654435761u;
  return {std::uint8_t(96 + (h >> 8) % 160), std::uint8_t(96 + (h >> 16) % 160), std::uint8_t(96 + (h >> 24) % 160)};
}

}  // namespace

LayerExport exportLayers(const Scene& scene, std::size_t photoIndex, const LayerExportSettings& settings,
                         Diagnostics& diag) {
  const Photo& photo = scene.photos.at(photoIndex);
  LayerExport out;
  const int w = settings.width > 0 ? settings.width : photo.camera.width;
  const int h = settings.height > 0 ? settings.height : photo.camera.height;
  try {
    out.camera = photo.camera.resized(w, h);
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string("--size: ") + e.what());
  }
  const Camera& cam = out.camera;
  Image8 rgb = readImage(photo.imagePath, 3);
  if (rgb.width != w || rgb.height != h) rgb = resizeImage(rgb, w, h);
  Image8 mask;
  if (!photo.maskPath.empty()) {
    mask = readImage(photo.maskPath, 1);
    if (mask.width != w || mask.height != h) mask = resizeImage(mask, w, h);
  }

  auto t0 = Clock::now();
  out.objects = collectSceneObjects(scene, settings.terrainTileMetres);
  if (out.objects.geometry.empty()) throw InputError(scene.path + ": the scene has no surfaces to make layers of");
  const RayCaster caster(out.objects.geometry);
  out.hits = castPixelHits(cam, out.objects, caster, settings.rays);
  out.castSeconds = since(t0);
  t0 = Clock::now();
  if (settings.objectLayers) {
    out.gpuObjectLayers = settings.objectLayers(cam, out.objects);
    out.visibility = completeVisibilityLayers(out.hits, out.gpuObjectLayers);
  } else {
    out.visibility = peelVisibilityLayers(out.hits);
  }
  out.peelSeconds = since(t0);
  for (const CycleSplit& cycle : out.visibility.splits) {
    std::string names;
    for (std::uint32_t o : cycle.objects) names += (names.empty() ? "" : " > ") + out.objects.objects[o].name;
    out.cycleNames.push_back(names);
  }

  t0 = Clock::now();
  // The other photographs that may see what this one sees (their frusta overlap).
  std::vector<Source> sources;
  if (settings.prefill) {
    const Aabb bounds = scene.bounds();
    const FrustumCorners mine = sceneFrustum(photo.camera, bounds);
    for (std::size_t j = 0; j < scene.photos.size(); ++j) {
      if (j == photoIndex) continue;
      const Photo& other = scene.photos[j];
      if (!frustaOverlap(mine, sceneFrustum(other.camera, bounds))) continue;
      Source s;
      s.camera = &other.camera;
      try {
        s.rgb = readImage(other.imagePath, 3);
        if (!other.maskPath.empty()) s.mask = readImage(other.maskPath, 1);
      } catch (const InputError& e) {
        diag.warn(std::string(e.what()) + " (camera '" + other.camera.id + "' is left out of the pre-fill)");
        continue;
      }
      sources.push_back(std::move(s));
    }
    out.prefillPhotos = int(sources.size());
  }
  auto prefill = [&](const glm::dvec3& point) -> std::optional<glm::u8vec3> {
    std::vector<std::pair<double, const Source*>> candidates;
    for (const Source& s : sources) {
      const Projection p = s.camera->project(point);
      if (!p.inImage) continue;
      candidates.push_back(
          {glm::length(point - s.camera->center) / std::max(s.camera->focal.x, s.camera->focal.y), &s});
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [footprint, s] : candidates) {
      const glm::dvec3 toPoint = point - s->camera->center;
      const double dist = glm::length(toPoint);
      const auto hit = caster.intersect(s->camera->center, toPoint);
      const double tol = settings.seenToleranceMetres + settings.seenToleranceRelative * dist;
      if (!hit || std::abs(hit->t - dist) > tol) continue;  // hidden from that camera too
      if (const auto c = sample(*s, s->camera->project(point).pxDistorted)) return c;
    }
    return std::nullopt;
  };

  const PixelHits& hits = out.hits;
  const VisibilityLayers& vis = out.visibility;
  auto seenHere = [&](std::size_t p) { return mask.empty() || mask.data[p] >= 128; };
  for (std::size_t k = 1; k <= vis.layers.size(); ++k) {
    const VisibilityLayer& layer = vis.layers[k - 1];
    // Each object's box in this layer.
    std::vector<PixelBox> boxes(layer.objects.size(), PixelBox{w, h, 0, 0});
    std::vector<std::int64_t> hitAt(std::size_t(w) * std::size_t(h));
    for (std::size_t p = 0; p < hitAt.size(); ++p) {
      hitAt[p] = vis.hitOfLayer(hits, p, int(k));
      if (hitAt[p] < 0) continue;
      const std::uint32_t o = hits.hits[std::size_t(hitAt[p])].object;
      const auto at = std::lower_bound(layer.objects.begin(), layer.objects.end(), o);
      PixelBox& b = boxes[std::size_t(at - layer.objects.begin())];
      const int x = int(p % std::size_t(w)), y = int(p / std::size_t(w));
      b = {std::min(b.x0, x), std::min(b.y0, y), std::max(b.x1, x + 1), std::max(b.y1, y + 1)};
    }
    for (const BoxCluster& cluster : clusterBoxes(boxes)) {
      ImageLayerInfo info;
      info.visibilityLayer = int(k);
      info.box = cluster.box;
      for (std::size_t m : cluster.members) info.objects.push_back(layer.objects[m]);
      info.name = layerName(int(k), info.objects, layer, out.objects, settings.namesPerLayer);
      OraLayer ora;
      ora.name = info.name;
      ora.x = cluster.box.x0;
      ora.y = cluster.box.y0;
      ora.rgba = Image8(cluster.box.width(), cluster.box.height(), 4, 0);
      for (int y = cluster.box.y0; y < cluster.box.y1; ++y)
        for (int x = cluster.box.x0; x < cluster.box.x1; ++x) {
          const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
          if (hitAt[p] < 0) continue;
          const SurfaceHit& hit = hits.hits[std::size_t(hitAt[p])];
          if (!std::binary_search(info.objects.begin(), info.objects.end(), hit.object)) continue;
          std::uint8_t* d = ora.rgba.px(x - cluster.box.x0, y - cluster.box.y0);
          if (std::uint32_t(hitAt[p]) == hits.first[p] && seenHere(p)) {
            std::copy_n(rgb.px(x, y), 3, d);
            d[3] = 255;
            ++info.photoPixels;
            continue;
          }
          std::optional<glm::u8vec3> c;
          if (settings.prefill)
            if (const auto dir = pixelRay(cam, x, y)) c = prefill(cam.center + hit.depth * *dir);
          if (c) {
            d[0] = c->r, d[1] = c->g, d[2] = c->b, d[3] = 255;
            ++info.prefilledPixels;
          } else {
            ++info.emptyPixels;
          }
        }
      out.document.layers.push_back(std::move(ora));
      out.imageLayers.push_back(std::move(info));
    }
  }
  out.fillSeconds = since(t0);

  // The photograph where no ray meets the geometry (the sky, beyond the scene).
  OraLayer background;
  background.name = "background (no geometry)";
  background.rgba = Image8(w, h, 4, 0);
  bool anyBackground = false;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
      if (hits.first[p] != hits.first[p + 1]) continue;
      std::copy_n(rgb.px(x, y), 3, background.rgba.px(x, y));
      background.rgba.px(x, y)[3] = 255;
      anyBackground = true;
    }
  if (anyBackground) out.document.layers.push_back(std::move(background));

  // The guide: every object's outline (its pixels, in any layer, with a 4-neighbour outside it).
  OraLayer guide;
  guide.name = "guide: object outlines";
  guide.visible = false;
  guide.rgba = Image8(w, h, 4, 0);
  auto has = [&](int x, int y, std::uint32_t o) {
    if (x < 0 || y < 0 || x >= w || y >= h) return false;
    const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
    for (std::uint32_t i = hits.first[p]; i < hits.first[p + 1]; ++i)
      if (hits.hits[i].object == o) return true;
    return false;
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const std::size_t p = std::size_t(y) * std::size_t(w) + std::size_t(x);
      for (std::uint32_t i = hits.first[p]; i < hits.first[p + 1]; ++i) {
        const std::uint32_t o = hits.hits[i].object;
        if (has(x - 1, y, o) && has(x + 1, y, o) && has(x, y - 1, o) && has(x, y + 1, o)) continue;
        const glm::u8vec3 c = guideColour(o);
        std::uint8_t* d = guide.rgba.px(x, y);
        d[0] = c.r, d[1] = c.g, d[2] = c.b, d[3] = 255;
        break;  // the nearest object's outline wins
      }
    }
  out.document.layers.insert(out.document.layers.begin(), std::move(guide));
  out.document.width = w;
  out.document.height = h;
  return out;
}

}  // namespace hv::layers
