// The renderer: builds each frame in plain C++ (render/frame_builder.h) and runs its passes on the
// GLES backend (render/gl/gl_backend.h); docs/design.md maps the steps to the papers. Needs a
// current GLES 3.0 context (hv/gpu/context.h); owns no platform code, so the same class serves
// `render`, `eval`, the viewer and the browser.
#pragma once

#include "hv/ibr/frame_plan.h"
#include "hv/ibr/selection.h"
#include "hv/ibr/slice_image.h"
#include "hv/image/image.h"
#include "hv/points/point_colors.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <memory>
#include <string>
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
// How a point sprite finds its texture coordinates (DESIGN.md §2 step 6).
enum class SpriteForm {
  PlaneVector,  // 2022: one vec3 varying N', p_i = H'_i p + (N'.p) E_i in the fragment shader
  Mat3,         // 2016: a mat3 varying per image (H_i), capped by MAX_VARYING_COMPONENTS
};

// Which points the photographs texture (DESIGN.md §2 step 7; 2022 §2.4).
enum class PointFilter {
  Auto,            // Classification when the cloud has classes, else Epsilon
  Classification,  // only keptClasses are textured (and, keptInDepthMaps, occlude)
  Epsilon,         // depth maps hold the model only; image i textures a point within epsilon of it
  None,            // every point textured, depth maps the model only, the ordinary shadow test
};

// The point pass (issue 4): scene.points drawn as textured sprites over the mesh.
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

// Geometry layers and corrections switched off live, to see what each contributes (issue 6). A
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

// Debug views (issue 6). With a view other than None the picture (RenderOutput::rgba and
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

struct RenderSettings {
  Binding binding = Binding::Array;
  ibr::BlendSettings blend;
  int depthSize = 1024;               // depth-map resolution (square)
  glm::dvec3 background{0.0};         // [0, 1] RGB where no image contributes
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
  // Per-tile image lists (ibr/tile_culling.h): each pixel loops over the images that may cover its
  // tile instead of all the selected ones.
  bool tileCulling = true;
  int tileSize = 16;  // view-depth texels per tile side
  // false: render() leaves RenderOutput::rgba empty and the colour stays on the GPU, in
  // colorTexture() (a window presents it without a GPU -> CPU copy). Counts are read back anyway.
  bool readBackColour = true;
  PointSettings points;
  LayerSettings layers;
  DebugSettings debug;
};

enum class FrameMode {
  Batch,        // every needed depth map rendered first: deterministic output (render, eval)
  Progressive,  // at most depthMapsPerFrame depth maps; images whose map is not current wait
};

struct RenderOutput {
  Image8 rgba;           // alpha = 255 where some image contributed (coverage)
  Image16 counts;        // contributing images per pixel (when asked)
  Image16 loopLengths;   // images each pixel's shading loop visited (when counts are asked)
  Image16 debugValues;   // the debug view's raw values (RenderSettings::debug), when read back
};

struct RenderStats {
  int depthMapsRendered = 0;       // since construction
  int depthMapsThisFrame = 0;
  int imagesWaiting = 0;           // selected but left out of the last frame (depth map not current)
  double meanTileList = 0.0;       // per-tile culling: mean and longest list of the last frame
  int maxTileList = 0;
  std::size_t sliceBytes = 0;      // GPU memory of the image and depth-map arrays (fixed at start)
  std::size_t decodePeakBytes = 0; // most memory the image loader ever held
  int imagesLoaded = 0;
  double lastFrameMs = 0.0;
  std::uint64_t pointsDrawn = 0;   // sprites of the last frame's view (not the depth maps)
  int mat3Images = 0;              // SpriteForm::Mat3: images the linked program carries
  // Why the last frame's images wait (imagesWaiting = decodesWaiting + depthMapsWaiting).
  int decodesWaiting = 0;          // selected, not resident yet (decoding or queued)
  int depthMapsWaiting = 0;        // resident, depth map not current
  int residentImages = 0;          // photographs in slots, selected or not
  // Debug views: debug.photo's index among the last frame's images (-1: not among them), its slot
  // (-1: not resident) and, for the DepthMap view, the depths its colours span (scene units).
  int debugImage = -1;
  int debugSlot = -1;
  double debugDepthNear = 0.0, debugDepthFar = 0.0;
};

// Where a photograph stands in the renderer (the viewer's residency table).
enum class PhotoState {
  Absent,           // not resident and not asked for
  Decoding,         // queued or being decoded
  DepthMapPending,  // resident, its depth map not current
  Ready,            // resident with a current depth map
  Broken,           // could not be loaded (reported once); left out of every frame
};

// SpriteForm::Mat3 (a mat3 varying per image): the largest image count, up to `upTo`, whose
// point program links on the current context (0: none), found by linking K = 1, 2, ...
int probeMat3SpriteImages(int upTo);

// The programs the renderer links (vertex, fragment, defines): the one list the shader test checks.
struct ProgramSource {
  std::string vertex, fragment;
  std::vector<std::string> defines;
};
const std::vector<ProgramSource>& programSources();

class Renderer {
 public:
  // Uploads the scene's geometry. Throws std::runtime_error when the context cannot do it.
  Renderer(const Scene& scene, RenderSettings settings, Diagnostics& diag);
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Renders one view (batch: every needed image resident and every depth map current, so the
  // output is deterministic). A view with distortion is rendered distorted.
  RenderOutput render(const Camera& view, bool withCounts = false, FrameMode mode = FrameMode::Batch);
  // True when the last frame used every selected image with a current depth map (and, with the
  // depth-map debug view, showed its photograph's map, unless no slot could take it).
  bool converged() const;
  // Makes the images a view needs resident (waiting for their decodes) without rendering anything:
  // a viewer's start-up, or a test of the depth-map schedule alone.
  void preload(const Camera& view);

  const ibr::FramePlan& lastPlan() const;
  // The per-image parameters of the last frame, in the order the shader saw them.
  const std::vector<ibr::ImageParams>& lastImageParams() const;
  const RenderSettings& settings() const;
  RenderSettings& settings();  // changes apply from the next frame
  ibr::SliceSize sliceSize() const;
  int sliceCount() const;
  const RenderStats& stats() const;
  PhotoState photoState(int photo) const;
  int slotOf(int photo) const;  // -1 when not resident
  // The GL name of the RGBA8 texture that holds the last frame's colour (the same pixels as
  // RenderOutput::rgba, alpha = coverage), stored top row first like every offscreen target
  // (docs/conventions.md), so a window presenting it flips it. With a debug view it holds that view. Its size is the last view's; it
  // stays valid until the next render() (which may reallocate it for another size). 0 before the
  // first frame.
  unsigned int colorTexture() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hv::render
