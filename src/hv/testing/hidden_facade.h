// Shared by the layered-photograph tests (layers/native/layer_export_test.cpp, the CPU path;
// render/layers_gltest.cpp, the GL renderer): the paper's use of layered projective texture maps
// (2003, §5) on a demo city. The photograph where a building (layer 1) hides another (layer 2) on
// the most rays, its hidden façade painted in a known colour in the layer-2 image layer that holds
// it, and the places from which the painting can be checked: a viewpoint that sees both buildings,
// and the occluder's far walls between it and the painted façade.
#pragma once

#include "hv/layers/native/layer_export.h"
#include "hv/layers/native/scene_objects.h"
#include "hv/scene/native/raycast.h"
#include "hv/scene/scene.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <vector>

namespace hv::testing {

struct HiddenFacade {
  std::size_t photo = 0;                   // the scene's photograph
  std::size_t layerIndex = 0;              // ex.imageLayers' layer-2 layer holding the hidden building
  std::size_t rays = 0;                    // the export's pixels where the occluder hides it
  std::uint32_t occluder = 0, hidden = 0;  // ex.objects' buildings
  layers::LayerExportSettings settings;    // the export's: a quarter of the photograph's size, no pre-fill
  layers::LayerExport ex;

  const layers::ImageLayerInfo& layer() const { return ex.imageLayers[std::size_t(layerIndex)]; }
  // Whether the export's pixel (x, y) sees the hidden building in layer 2 (false outside the image).
  bool hiddenAt(int x, int y) const {
    if (x < 0 || y < 0 || x >= ex.hits.width || y >= ex.hits.height) return false;
    const std::size_t p = std::size_t(y) * std::size_t(ex.hits.width) + std::size_t(x);
    const std::int64_t k = ex.visibility.hitOfLayer(ex.hits, p, 2);
    return k >= 0 && ex.hits.hits[std::size_t(k)].object == hidden;
  }
  // ... and the occluder in front of it (layer 1).
  bool hiddenBehindOccluderAt(int x, int y) const {
    return hiddenAt(x, y) &&
           ex.hits.hits[ex.hits.first[std::size_t(y) * std::size_t(ex.hits.width) + std::size_t(x)]].object == occluder;
  }
};

// The photograph of `scene` where a building (layer 1) hides another (layer 2) on the most rays,
// with a layer-2 image layer holding the hidden one; none when no photograph has such a pair.
inline std::optional<HiddenFacade> findHiddenFacade(const Scene& scene) {
  using layers::SceneObject;
  std::optional<HiddenFacade> best;
  for (std::size_t i = 0; i < scene.photos.size(); ++i) {
    layers::LayerExportSettings s;
    s.prefill = false;
    s.width = scene.photos[i].camera.width / 4;
    s.height = scene.photos[i].camera.height / 4;
    Diagnostics diag;
    layers::LayerExport e = layers::exportLayers(scene, i, s, diag);
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::size_t> pairs;
    const layers::PixelHits& h = e.hits;
    for (std::size_t p = 0; p < h.pixelCount(); ++p) {
      if (h.first[p] == h.first[p + 1]) continue;
      const std::uint32_t front = h.hits[h.first[p]].object;
      if (e.objects.objects[front].kind != SceneObject::Kind::Building || e.visibility.layerOfHit[h.first[p]] != 1)
        continue;
      for (std::uint32_t k = h.first[p] + 1; k < h.first[p + 1]; ++k)
        if (e.visibility.layerOfHit[k] == 2 &&
            e.objects.objects[h.hits[k].object].kind == SceneObject::Kind::Building) {
          ++pairs[{front, h.hits[k].object}];
          break;
        }
    }
    for (const auto& [pair, n] : pairs) {
      if (best && n <= best->rays) continue;
      for (std::size_t j = 0; j < e.imageLayers.size(); ++j) {
        const layers::ImageLayerInfo& l = e.imageLayers[j];
        if (l.visibilityLayer == 2 && std::count(l.objects.begin(), l.objects.end(), pair.second)) {
          best = HiddenFacade{i, j, n, pair.first, pair.second, s, e};
          break;
        }
      }
    }
  }
  return best;
}

// The artist's edit: the hidden building's pixels of its layer-2 image layer painted `colour`
// (opaque), in the export's document, before the file is written. Returns the pixels painted.
inline int paintHiddenFacade(HiddenFacade& f, glm::u8vec4 colour) {
  int painted = 0;
  for (layers::OraLayer& l : f.ex.document.layers) {
    if (l.name != f.layer().name) continue;
    for (int y = 0; y < l.rgba.height; ++y)
      for (int x = 0; x < l.rgba.width; ++x)
        if (f.hiddenAt(l.x + x, l.y + y)) {
          std::uint8_t* c = l.rgba.px(x, y);
          for (int k = 0; k < 4; ++k) c[k] = colour[k];
          ++painted;
        }
  }
  return painted;
}

// Another viewpoint that sees the hidden façade and the occluder's face in front of it: around the
// façade's points that the occluder hides from the photograph, the photograph's centre turned about
// the vertical by up to 60 degrees and raised by up to 40 m, looking at their centroid; the one
// that sees most of both (the least of the two counts; `seen` 0: none sees both).
struct FacadeViewpoint {
  std::vector<glm::dvec3> hiddenPoints, frontPoints;  // world: the hidden façade's, the occluder's on the same rays
  glm::dvec3 centroid{0.0};                           // of hiddenPoints
  glm::dvec3 centre{0.0};                             // the viewpoint
  std::size_t seen = 0;
};

inline FacadeViewpoint facadeViewpoint(const HiddenFacade& f, const RayCaster& caster) {
  const layers::LayerExport& ex = f.ex;
  FacadeViewpoint v;
  for (int y = 0; y < ex.hits.height; ++y)
    for (int x = 0; x < ex.hits.width; ++x) {
      const std::optional<glm::dvec3> ray = layers::pixelRay(ex.camera, x, y);
      if (!ray || !f.hiddenBehindOccluderAt(x, y)) continue;
      const std::size_t p = std::size_t(y) * std::size_t(ex.hits.width) + std::size_t(x);
      const std::int64_t k = ex.visibility.hitOfLayer(ex.hits, p, 2);
      v.hiddenPoints.push_back(ex.camera.center + *ray * ex.hits.hits[std::size_t(k)].depth);
      v.frontPoints.push_back(ex.camera.center + *ray * ex.hits.hits[ex.hits.first[p]].depth);
      v.centroid += v.hiddenPoints.back();
    }
  if (v.hiddenPoints.empty()) return v;
  v.centroid /= double(v.hiddenPoints.size());
  const auto seenFrom = [&](const glm::dvec3& c, const glm::dvec3& x) {
    const double d = glm::length(x - c);
    const std::optional<RayHit> h = caster.intersect(c, (x - c) / d);
    return h && std::abs(h->t - d) < 0.05 + 1e-3 * d;
  };
  for (double deg : {-60.0, -40.0, -20.0, 20.0, 40.0, 60.0})
    for (double up : {0.0, 15.0, 40.0}) {
      const double a = deg * 3.14159265358979 / 180.0;
      const glm::dvec3 r = ex.camera.center - v.centroid;
      const glm::dvec3 c = v.centroid + glm::dvec3(std::cos(a) * r.x - std::sin(a) * r.y,
                                                   std::sin(a) * r.x + std::cos(a) * r.y, r.z + up);
      std::size_t seenHidden = 0, seenFront = 0;
      for (std::size_t i = 0; i < v.hiddenPoints.size(); i += 1 + v.hiddenPoints.size() / 400) {
        seenHidden += seenFrom(c, v.hiddenPoints[i]);
        seenFront += seenFrom(c, v.frontPoints[i]);
      }
      const std::size_t seen = std::min(seenHidden, seenFront);
      if (seen > v.seen) v.seen = seen, v.centre = c;
    }
  return v;
}

// The occluder's far walls (faces turned away from the photograph) on the photograph's rays
// between its front and the painted façade, on rays one texel or more inside the painted region
// (at its border a depth test reads the texels of the next surface too): (wall point, façade point
// behind it), world.
inline std::vector<std::pair<glm::dvec3, glm::dvec3>> occluderFarWalls(const HiddenFacade& f, const RayCaster& caster) {
  const layers::LayerExport& ex = f.ex;
  std::vector<std::pair<glm::dvec3, glm::dvec3>> walls;
  for (int y = 0; y < ex.hits.height; ++y)
    for (int x = 0; x < ex.hits.width; ++x) {
      bool interior = true;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) interior = interior && f.hiddenBehindOccluderAt(x + dx, y + dy);
      const std::optional<glm::dvec3> ray = layers::pixelRay(ex.camera, x, y);
      if (!interior || !ray) continue;
      const std::size_t p = std::size_t(y) * std::size_t(ex.hits.width) + std::size_t(x);
      const double behind = ex.hits.hits[std::size_t(ex.visibility.hitOfLayer(ex.hits, p, 2))].depth;
      double t = ex.hits.hits[ex.hits.first[p]].depth + 1e-3;
      while (const std::optional<RayHit> h = caster.intersect(ex.camera.center, *ray, t)) {
        if (h->t >= behind - 0.5) break;
        if (ex.objects.objectOfTriangle[h->triangle] == f.occluder && glm::dot(h->normal, *ray) > 0.0)
          walls.push_back({h->position, ex.camera.center + *ray * behind});
        t = h->t + 1e-3;
      }
    }
  return walls;
}

}  // namespace hv::testing
