// The renderer: builds each frame in plain C++ (render/frame_builder.h) and runs its passes on the
// GLES backend (render/gl/gl_backend.h); docs/design.md maps the steps to the papers. Needs a
// current GLES 3.0 context (hv/gpu/context.h); owns no platform code, so the same class serves
// `render`, `eval`, the viewer and the browser.
#pragma once

#include "hv/ibr/frame_plan.h"
#include "hv/ibr/selection.h"
#include "hv/ibr/slice_image.h"
#include "hv/image/image.h"
#include "hv/layers/layered_texture.h"
#include "hv/render/settings.h"
#include "hv/scene/orthophoto.h"
#include "hv/scene/point_colors.h"
#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <glm/glm.hpp>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace hv::render {

enum class FrameMode {
  Batch,        // every needed depth map rendered first: deterministic output (render, eval)
  Progressive,  // at most depthMapsPerFrame depth maps; images whose map is not current wait
};

struct RenderOutput {
  Image8 rgba;          // alpha = 255 where some image contributed (coverage)
  Image16 counts;       // contributing images per pixel (when asked)
  Image16 loopLengths;  // images each pixel's shading loop visited (when counts are asked)
  Image16 debugValues;  // the debug view's raw values (RenderSettings::debug), when read back
};

struct RenderStats {
  int depthMapsRendered = 0;  // since construction
  int depthMapsThisFrame = 0;
  int depthMapsUploaded = 0;  // layered photographs' peeled depth maps uploaded (not drawn), since construction
  int imagesWaiting = 0;      // selected but left out of the last frame (depth map not current)
  double meanTileList = 0.0;  // per-tile culling: mean and longest list of the last frame
  int maxTileList = 0;
  std::size_t sliceBytes = 0;       // GPU memory of the image and depth-map arrays (fixed at start)
  std::size_t decodePeakBytes = 0;  // most memory the image loader ever held
  int imagesLoaded = 0;
  double lastFrameMs = 0.0;
  std::uint64_t pointsDrawn = 0;  // sprites of the last frame's view (not the depth maps)
  int mat3Images = 0;             // SpriteForm::Mat3: images the linked program carries
  // Why the last frame's images wait (imagesWaiting = decodesWaiting + depthMapsWaiting).
  int decodesWaiting = 0;    // selected, not resident yet (decoding or queued)
  int depthMapsWaiting = 0;  // resident, depth map not current
  int residentImages = 0;    // photographs in slots, selected or not
  // Debug views: debug.photo's index among the last frame's images (-1: not among them), its slot
  // (-1: not resident) and, for the DepthMap view, the depths its colours span (scene units).
  int debugImage = -1;
  int debugSlot = -1;
  double debugDepthNear = 0.0, debugDepthFar = 0.0;
  // Geometry tiles (render/geometry_tiles.h): how many there are, how many tiles and triangles
  // the last frame's view drew, and how many tiles its depth maps drew together.
  int geometryTiles = 0;
  int tilesDrawn = 0;
  std::int64_t trianglesDrawn = 0;
  int depthMapTilesThisFrame = 0;
  // Streamed terrain (render/terrain_stream.h; 0 without it): tiles resident, waiting to be read,
  // their bytes and the most they held, the budget, evictions so far; the last view's cut.
  int terrainTilesResident = 0;
  int terrainTilesPending = 0;
  std::size_t terrainBytes = 0, terrainPeakBytes = 0, terrainBudgetBytes = 0;
  std::size_t terrainFrameBytes = 0;  // what the last frame's cuts reserved of the budget
  std::size_t terrainEvictions = 0;
  int terrainViewTiles = 0;
  int terrainViewMissing = 0;  // tiles the view's cut waits for
  bool streamingTerrain = false;
  // Streamed buildings (render/building_stream.h; 0 without them), likewise; their bytes count
  // in the same budget as the terrain's (geometryMemoryBytes).
  int buildingTilesResident = 0;
  int buildingTilesPending = 0;
  int buildingTilesRetrying = 0;  // failed, waiting for their next try (BuildingRetryPolicy)
  int buildingTilesGivenUp = 0;   // failed as many times as the policy allows
  std::size_t buildingsResident = 0;
  std::size_t buildingBytes = 0, buildingPeakBytes = 0;
  std::size_t buildingEvictions = 0;
  int buildingViewTiles = 0;
  int buildingViewMissing = 0;
  bool buildingBudgetLimited = false;  // the view's cut left tiles out for the budget
  bool streamingBuildings = false;
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
  // Textures photograph `photo` with its edited layers (Layered projective texture maps, 2003, §5;
  // hv/layers/layered_texture.h) instead of its image: when selected, it is expanded into its
  // sub-images, each in an image slot with its peeled depth map D_k uploaded into the slot's depth
  // map, blended as one photograph (docs/layers.md). Null: the photograph as it is again. The
  // slots are emptied (every photograph is made resident again). Throws std::invalid_argument for
  // a photo index out of range or a sub-image without pixels.
  void setLayeredPhotograph(int photo, std::shared_ptr<const layers::LayeredPhotograph> layered);
  // Photograph `photo`'s Photo::imagePath now names a larger image of it (the page's IIIF
  // photographs: the preview they join with, then the full image; docs/services.md). A resident
  // photograph keeps its slot, camera and depth map and is textured by the image it has until the
  // new one is decoded and put in its place (the slice's mip levels redone from it); the frames
  // are not converged meanwhile and a batch frame waits for it. A photograph not resident reads
  // the new image when next needed. A new image that cannot be loaded leaves the one shown, the
  // error naming the camera, the field and the file or URL. Throws std::invalid_argument for an
  // index out of range.
  void replaceImage(int photo);
  // The orthophoto draped on untextured terrain (scene.json "orthophoto", read by
  // hv::loadOrthophoto beside the scene; settings().untextured.orthophoto switches it): uploaded
  // now. Null or empty: none.
  void setOrthophoto(std::shared_ptr<const Orthophoto> orthophoto);

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
  // (docs/conventions.md), so a window presenting it flips it. With a debug view it holds that view. Its size is the
  // last view's; it stays valid until the next render() (which may reallocate it for another size). 0 before the first
  // frame.
  unsigned int colorTexture() const;
  // The scene point under pixel `px` of the last rendered view (its pixels, top-left-corner
  // origin), from that frame's view depth (render/view_pick.h): the geometry and points the
  // picture shows. None for the sky, outside the view, or before the first frame. Reads one
  // pixel back: for a click, not every frame. The picker of builds without a ray caster (the
  // browser); accurate to the depth's 24-bit packing of [near, far] and to the view-depth
  // target's texel (Frame::rect.depthSize).
  std::optional<glm::dvec3> pickViewPoint(glm::dvec2 px);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hv::render
