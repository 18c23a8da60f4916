// One frame in plain C++: what the frame builder
// (render/frame_builder.h) decides and a GPU backend (render/backend.h) executes. Which
// photographs texture the view and with which weights (Brédif 2013 eq. 2), the depth maps to draw
// (de Castro & Brédif 2022 §2.2: at most Dmax per progressive frame, nearest camera first), the
// packed per-image parameters, the point chunks each pass draws, and which view passes run. No GL
// here: the frame logic is tested on the CPU through the null backend (render/null_backend.h).
#pragma once

#include "hv/ibr/frame_plan.h"
#include "hv/render/renderer.h"
#include "hv/render/untextured.h"
#include "hv/traffic/vehicle_model.h"

#include <glm/glm.hpp>

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

namespace hv::render {

// The geometry layers, in the order the geometry buffer holds them (one index buffer).
enum Layer { kLayerTerrain, kLayerBuildings, kLayerMesh, kLayerCount };

// Streamed tiles share one id space (Backend::uploadStreamedTile): a terrain node's id
// (TerrainQuadtree::makeId, whose level byte never reaches 128), or a building tile's index with
// this bit set.
constexpr std::uint64_t kBuildingTileId = std::uint64_t(1) << 63;

// Index range of one layer in the index buffer, or of one photograph's lines in the frustum buffer.
struct DrawRange {
  int first = 0, count = 0;
};

// One tile of a layer's triangles (render/geometry_tiles.h): its index range and its box.
struct GeometryTile {
  int layer = kLayerTerrain;
  DrawRange range;                 // into GeometryBuffers::indices
  glm::vec3 lo{0.0f}, hi{0.0f};    // box of its vertices, render frame
};

// The scene's surfaces as the GPU holds them (built once by the frame builder). Per vertex:
// render-frame position (3), the days its surface existed (2, ibr::gpuDays), building index + 1.
// The indices are ordered layer by layer and, within a layer, tile by tile.
struct GeometryBuffers {
  static constexpr int kStride = 6;
  std::vector<float> vertices;
  std::vector<std::uint32_t> indices;
  std::array<DrawRange, kLayerCount> layers;
  std::vector<GeometryTile> tiles;
  // Building validity (days), one RGBA32F texel per building index, rows of validityWidth.
  std::vector<float> validity;
  int validityWidth = 1, validityRows = 1;
};

// Per point in the GPU buffer: render-frame position, normal (0 when none), colour + class.
struct PointVertex {
  float position[3];
  float normal[3];
  std::uint8_t color[4];
};
static_assert(sizeof(PointVertex) == 28);

// One chunk's prefix of points, drawn with one sprite radius (scene units).
struct PointDraw {
  std::uint32_t first = 0, count = 0;
  float radius = 0.0f;
};

// The sprites one camera draws (hv::selectChunks within the budget) and how they are filtered.
struct PointPass {
  std::vector<PointDraw> draws;
  std::uint64_t points = 0;       // sum of the draws' counts
  bool classify = false;          // the classification filter applies (u_classify)
  std::array<std::uint32_t, 8> keptClasses{};  // 256-bit mask of PointSettings::keptClasses
  bool dropTransient = false;
  double depthOffset = 0.0;       // the mesh pushed back behind the points (hybrid, 2016 §4.2)
};

// One photograph's depth map to draw into its slot.
struct DepthMapJob {
  int slot = -1;
  int photo = -1;
  Camera camera;                  // as projected (without its distortion when the lens layer is off)
  hv::PinholeFrustum frustum;    // the ideal rectangle covering its image, its depth range
  glm::dmat4 clipFromRender{1.0};
  int size = 0;                   // the map's side, texels
  glm::dvec3 centerRender{0.0};
  DateInterval date;              // surfaces outside it are left out (scene validity)
  double pushBack = 0.0;          // the mesh pushed back behind the points
  std::array<bool, kLayerCount> layers{true, true, true};
  // The index ranges to draw: the tiles of those layers that its frustum may see (merged).
  std::vector<DrawRange> draws;
  int tiles = 0;                  // the tiles in `draws`
  // Streamed tiles to draw after `draws` (Backend::uploadStreamedTile ids): the photograph's own
  // cuts (render/terrain_stream.h, render/building_stream.h), those of their tiles its frustum may see.
  std::vector<std::uint64_t> streamedTiles;
  bool withPoints = false;        // non-transient points refine the occlusion (2016 §4.2, 2022 §2.4)
  PointPass points;
};

// The view's rectangle: linear depth is drawn over the pinhole rectangle covering the (distorted)
// view, at the output's pixel density.
struct ViewRect {
  hv::PinholeFrustum frustum;
  glm::dmat4 clipFromRender{1.0};
  glm::ivec2 depthSize{0};        // view-depth target
  bool distorted = false;
};

// The point pass of the view (PointSettings), when the points are drawn.
struct ViewPoints {
  bool enabled = false;
  PointPass pass;                 // into the view depth, then the winners' colours
  bool epsilonTest = false;
  double epsilon = 0.0;           // scene units
  bool eyeDome = false;
  double eyeDomeStrength = 0.0, eyeDomeRadiusPx = 0.0;
};

// The photographs' frusta as line segments (camera::frustumOutline), render frame, a range of
// vertices per photograph; `version` changes when they are rebuilt (depth or lens model changed).
struct FrustumLines {
  std::vector<float> xyz;
  std::vector<DrawRange> perPhoto;
  std::uint64_t version = 0;
};

// What the DebugView::DepthMap view and the frusta overlay show.
struct DebugPass {
  DebugView view = DebugView::None;
  int photo = -1;
  int slot = -1;                  // the depth-map view's slot (-1: none to show)
  hv::PinholeFrustum slotFrustum;
  int image = -1;                 // debug.photo's index among the frame's images
  bool frusta = false;            // the overlay (never over the DepthMap view)
  const FrustumLines* frustumLines = nullptr;  // when frusta: owned by the builder
};

// One vehicle of the frame (render/vehicles.h): its box on the terrain, render frame.
struct VehicleInstance {
  glm::vec3 position{0.0f};  // centre of its footprint, on the terrain
  glm::vec3 right{1.0f, 0.0f, 0.0f}, forward{0.0f, 1.0f, 0.0f}, up{0.0f, 0.0f, 1.0f};  // unit axes
  glm::vec3 size{4.5f, 1.8f, 1.5f};  // length, width, height
  glm::vec3 colour{0.5f};            // body colour, linear [0, 1]
  int model = 0;                     // its class (hv::VehicleClass): the model it is drawn with
};

// The traffic drawn over the picture, depth-tested against the view's depth (pinhole views only:
// vehicles_pass.cpp).
// Lit as the untextured surfaces (Frame::untextured: its sun, sky and ground light).
struct TrafficDraw {
  std::vector<VehicleInstance> vehicles;
  // The model of each class (Trajectories::models); null: the built-in box with wheels for all.
  std::shared_ptr<const VehicleModels> models;
};

struct Frame {
  std::uint64_t number = 0;       // 1 for the first frame
  FrameMode mode = FrameMode::Batch;
  Camera view;
  glm::dvec3 origin{0.0};         // the render frame's origin (world): Scene::origin
  ibr::BlendSettings blend;       // as planned: K capped by the slots
  ibr::FramePlan plan;
  std::vector<int> slots;         // per plan.images: its slot, -1 while its decode is pending
  // The dirty depth maps this frame may draw, in order (nearest camera first), at most Dmax in a
  // progressive frame; a time budget may stop before the end (RenderSettings::depthBudgetMs).
  std::vector<int> depthMapQueue;
  bool depthBudgeted = false;
  std::vector<int> depthMapsDrawn;  // what was drawn, the debug photograph's map included

  // The images the shader blends, in order, and their packed rows (ibr::packImageParams).
  std::vector<ibr::ImageParams> params;
  std::vector<float> packedParams;

  ViewRect rect;
  std::array<bool, kLayerCount> layers{true, true, true};
  std::vector<DrawRange> draws;   // the view's geometry: the tiles its frustum may see (merged)
  std::vector<std::uint64_t> streamedTiles;  // streamed tiles of the view's cuts it may see
  ViewPoints points;
  bool culling = false;           // per-tile image lists (ibr/tile_culling.h)
  int tileSize = 16;
  double meshPushBack = 0.0;      // in the mesh's shadow test (points share the depth maps)
  double sphereRadius = 0.0;      // background sphere, 0: none
  glm::dvec3 background{0.0};
  UntexturedSettings untextured;  // where no photograph contributes (render/untextured.h)
  glm::dvec3 up{0.0, 0.0, 1.0};   // Scene::up
  DebugPass debug;
  TrafficDraw traffic;            // empty: no traffic (none in the scene, or switched off)
  bool withCounts = false;        // counts and loop lengths read back
  bool readBackColour = true;
};

// What the view passes report back.
struct ViewPassStats {
  bool tileListsBuilt = false;    // the tile statistics below are this frame's
  double meanTileList = 0.0;
  int maxTileList = 0;
  double debugDepthNear = 0.0, debugDepthFar = 0.0;
};

}  // namespace hv::render
