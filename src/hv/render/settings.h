// What a renderer can be asked to do: every setting of the frame (blend, depth maps, points,
// layers, debug views), plain data with its defaults. The renderer reads them at each frame, so a
// viewer changes them live.
#pragma once

#include "hv/ibr/frame_plan.h"
#include "hv/render/untextured.h"
#include "hv/scene/point_colors.h"

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace hv::render {

// How photographs and depth maps reach the shader.
enum class Binding {
  Array,  // one texture2DArray of photographs, one of depth maps, parameters in a data texture
  Naive,  // the baseline the papers improve on: a sampler2D per photograph and per depth map
          // (2 texture units per image), so at most MAX_TEXTURE_IMAGE_UNITS / 2 images (minus the
          // units the pass needs for itself) are blended
};

inline constexpr double kDefaultSphereRadius = 100.0;
// How a point sprite finds its texture coordinates (docs/design.md, step 6).
enum class SpriteForm {
  PlaneVector,  // 2022: one vec3 varying N', p_i = H'_i p + (N'.p) E_i in the fragment shader
  Mat3,         // 2016: a mat3 varying per image (H_i), capped by MAX_VARYING_COMPONENTS
};

// Which points the photographs texture (docs/design.md, step 7; 2022 §2.4).
enum class PointFilter {
  Auto,            // Classification when the cloud has classes, else Epsilon
  Classification,  // only keptClasses are textured (and, keptInDepthMaps, occlude)
  Epsilon,         // depth maps hold the model only; image i textures a point within epsilon of it
  None,            // every point textured, depth maps the model only, the ordinary shadow test
};

// The point pass: scene.points drawn as textured sprites over the mesh.
struct PointSettings {
  bool enabled = false;                // draw scene.points (when there are any)
  std::uint64_t budget = 2'000'000;    // points per frame (and per depth map), hv::selectChunks
  double radius = -1.0;                // world radius of a sprite, scene units; <= 0: per chunk,
  double radiusScale = 0.75;           //   this times the chunk's point spacing at the drawn density
  double maxPointSizePx = 64.0;        // also capped by ALIASED_POINT_SIZE_RANGE
  SpriteForm form = SpriteForm::PlaneVector;
  PointFilter filter = PointFilter::Auto;
  std::vector<int> keptClasses{2, 6, 9, 10, 11, 17};  // ground, building, water, rail, road, bridge deck
  bool keptInDepthMaps = true;         // Classification: non-transient points occlude in depth maps
  bool hideTransient = false;          // transient points hidden, else shown untextured
  double epsilon = -1.0;               // Epsilon filter, scene units; < 0: 2e-3 of the scene's extent
  // Hybrid rendering (2016 §4.2): the mesh counts as pushed back by this along its normal (scene
  // units: metres in a georeferenced scene) behind the points, in the view and in depth maps that
  // hold points, so that points on or slightly behind the LOD1 surface (windows, doors, a road
  // under a coarse DTM) show and are not shadowed by it; < 0: 6e-4 of the scene's extent (0.2 m
  // on the demo city).
  double meshOffset = -1.0;
  PointColorMode color = PointColorMode::Auto;  // untextured points
  bool eyeDome = true;                 // eye-dome lighting on untextured points (Potree)
  double eyeDomeStrength = 0.4;
  double eyeDomeRadiusPx = 1.4;
};

// Geometry layers and corrections switched off live, to see what each contributes. A
// layer switched off is left out of the view and of the photographs' depth maps; changing one
// redraws every depth map. (Masks are BlendSettings::masks: the slices hold the colour
// premultiplied by the mask, so switching them decodes the photographs again.)
struct LayerSettings {
  bool terrain = true;
  bool buildings = true;
  bool mesh = true;  // scene.json "mesh"
  // false: the photographs are projected as pinhole cameras, their lens distortion ignored, to
  // show what the correction does (a distorted view stays distorted). Their depth maps are redrawn
  // with the pinhole frusta.
  bool lensDistortion = true;
};

// Debug views. With a view other than None the picture (RenderOutput::rgba and
// colorTexture()) is that view, coloured with hv::colorRamp (dark purple 0 ... yellow 1), and
// RenderOutput::debugValues holds its raw values (16 bits, one channel) when the colour is read back.
enum class DebugView {
  None,
  // Contributing images per pixel; colour: count / (images in the frame), black where none;
  // raw: the count.
  Counts,
  // The share of photograph debug.photo in each pixel's blend, w_i a_i / sum_j w_j a_j (Brédif 2013
  // eq. 2; nearest: 1 where it wins), 0 where it does not contribute or is not among the frame's
  // images; background where no image covers the pixel. raw: share * 65535.
  Weight,
  // The depth map of photograph debug.photo (made resident for it), letterboxed into the view with
  // its frustum's aspect ratio; colour: nearest stored depth (yellow) to farthest (dark purple),
  // black where the photograph sees no geometry. raw: the stored value (linear depth between the
  // map's near and far planes) * 65535; 65535 outside the map and where it sees no geometry.
  DepthMap,
};

struct DebugSettings {
  DebugView view = DebugView::None;
  int photo = -1;              // Weight, DepthMap: index into Scene::photos
  // The photographs' frusta drawn over the picture (camera::frustumOutline): grey, the frame's
  // images yellow, debug.photo cyan; fainter where the geometry hides them. Not on distorted views,
  // nor over the DepthMap view (a picture in the photograph's image, not the view's).
  bool frusta = false;
  double frustumDepth = -1.0;  // scene units; <= 0: the scene's camera spacing
};

// The vehicles of scene.json "traffic" (docs/traffic.md): the trajectories at `time` on the
// simulation's clock, lifted onto the terrain and drawn over the picture, hidden by what the view's
// depth holds in front of them (the 2013 paper, §3).
struct TrafficSettings {
  bool enabled = true;  // off: the empty street
  double time = 0.0;    // seconds, the trajectories' own clock
};

struct RenderSettings {
  Binding binding = Binding::Array;
  ibr::BlendSettings blend;
  int depthSize = 1024;               // depth-map resolution (square)
  // [0, 1] RGB where no image contributes and untextured.shading (surfaces) or untextured.sky
  // (pixels without geometry) is off, in the debug views, and outside a distorted view's lens domain.
  glm::dvec3 background{0.0};
  UntexturedSettings untextured;  // shaded surfaces and the sky where no photograph contributes
  // Pixels that see no geometry are projected onto a sphere of this radius (scene units) around the
  // view, as iTowns' backgroundDistance: > 0 always, 0 never, < 0 only in a scene without geometry
  // (a panorama collection), with radius kDefaultSphereRadius.
  double backgroundSphere = -1.0;
  double depthBiasAbsolute = -1.0;    // scene units; < 0: derived from the scene's extent
  double depthBiasTexels = 1.5;       // plus this many depth-map texel footprints, slope-scaled (ibr::shadowBias)
  int maxSliceSize = 2048;            // largest slice side; bigger photographs are scaled down
  int maxSlices = 256;                // image slots (also capped by MAX_ARRAY_TEXTURE_LAYERS and memory)
  std::size_t memoryBudgetBytes = std::size_t(1) << 30;  // images + depth maps
  // Progressive frames (a viewer): at most this many depth maps per frame, nearest camera first;
  // <= 0: all. Batch frames ignore it.
  int depthMapsPerFrame = 4;
  // Alternatively (> 0), a time budget for a progressive frame's depth maps: maps are rendered,
  // nearest camera first, until it is spent (at least one per frame, at most depthMapsPerFrame).
  double depthBudgetMs = 0.0;
  // Photographs are decoded off the render thread (ibr/image_loader.h) by this many workers; 0
  // decodes on the calling thread (the browser build has no threads). Decodes in flight and
  // decoded slices not yet uploaded never hold more than decodeMemoryBytes.
  int decodeThreads = 2;
  std::size_t decodeMemoryBytes = std::size_t(512) << 20;
  // A DTM too large to mesh whole (Scene::terrainTiles) is streamed per view
  // (render/terrain_stream.h): each camera (the view, each photograph's depth map) draws its own
  // cut of the quadtree at geometryTolerancePx of screen-space error, its tiles read and
  // triangulated by geometryThreads workers (0: on the render thread, as photographs with
  // decodeThreads 0), kept within geometryMemoryBytes, the least recently used evicted.
  int geometryThreads = 2;
  std::size_t geometryMemoryBytes = std::size_t(256) << 20;
  double geometryTolerancePx = 2.0;
  // Per-tile image lists (ibr/tile_culling.h): each pixel loops over the images that may cover its
  // tile instead of all the selected ones.
  bool tileCulling = true;
  int tileSize = 16;  // view-depth texels per tile side
  // The view and each depth map draw only the geometry tiles their frustum may see
  // (render/geometry_tiles.h); off: every tile (the same pixels, more work).
  bool geometryCulling = true;
  // Streamed building tiles (render/building_stream.h) whose box's picture in the view is thinner
  // than this many pixels are not drawn in the view (a sliver at most that thick, far off at street
  // level); depth maps keep their reach rule. 0: every tile the view may see.
  double buildingMinPixels = 2.0;
  // false: render() leaves RenderOutput::rgba empty and the colour stays on the GPU, in
  // colorTexture() (a window presents it without a GPU -> CPU copy). Counts are read back anyway.
  bool readBackColour = true;
  PointSettings points;
  LayerSettings layers;
  DebugSettings debug;
  TrafficSettings traffic;
};

}  // namespace hv::render
