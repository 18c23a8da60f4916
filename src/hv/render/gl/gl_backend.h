// The GLES 3.0 backend (render/backend.h): the geometry, the slots' photographs and depth maps,
// and the passes of a frame, each in its own file under render/gl/:
//   depth_pass.cpp    photographs' depth maps and the view's depth (Brédif 2013 §3, shadow maps)
//   points_pass.cpp   point sprites into the view depth, their colours, eye-dome lighting (2022 §2.3)
//   tile_pass.cpp     per-tile image lists (ibr/tile_culling.h)
//   shade_pass.cpp    the blend (Brédif 2013 eq. 2), parameter upload, the distorted-view lookup
//   debug_pass.cpp    the debug views (counts, weight, a depth map)
//   overlay_pass.cpp  the photographs' frusta over the picture
//   gl_backend.cpp    uploads, slots, and the order of the view passes and the read-back
// Needs a current GLES 3.0 context (hv/gpu/context.h).
#pragma once

#include "hv/gpu/gl.h"
#include "hv/render/backend.h"
#include "hv/render/gl/programs.h"
#include "hv/traffic/vehicle_model.h"
#include "hv/util/diagnostics.h"

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace hv::render::gl {

// Texture units, fixed for every program.
enum Unit : GLint {
  kUnitImages = 0,
  kUnitDepthMaps = 1,
  kUnitParams = 2,
  kUnitViewDepth = 3,
  kUnitLookup = 4,
  kUnitTileLists = 5,
  kUnitViewBuilding = 6,
  kUnitValidity = 7,
  kUnitPointColor = 8,
  kUnitPointParams = 9,
  // The orthophoto (the array binding only: the naive binding's photographs take the units above
  // kUnitValidity).
  kUnitOrthophoto = 10
};

// Shading-pass modes (u_mode in shaders/ibr_shade.frag).
enum ShadeMode : GLint {
  kShadeColour = 0,
  kShadeCount = 1,
  kShadeLoopLength = 2,
  kShadeShare = 3,
  kShadeCountColour = 4,
  kShadeShareColour = 5
};

// The bound colour target, RGBA8.
Image8 readColour(int w, int h);
// Counts encoded in red (low byte) and green (high byte).
Image16 decodeCounts(const Image8& enc);

class GlBackend final : public Backend {
 public:
  explicit GlBackend(Diagnostics& diag);

  BackendLimits limits() const override;
  void uploadGeometry(const GeometryBuffers& geometry) override;
  void uploadStreamedTile(std::uint64_t id, const std::vector<float>& vertices,
                         const std::vector<std::uint32_t>& indices) override;
  void releaseStreamedTile(std::uint64_t id) override { streamedTiles_.erase(id); }
  void uploadValidity(const std::vector<float>& validity, int width, int rows) override;
  void uploadOrthophoto(const Orthophoto& orthophoto, const OrthophotoAffine& affine) override;
  PointProgramInfo uploadPoints(const std::vector<PointVertex>& points, const PointProgramRequest& req) override;
  void allocateSlots(const SlotLayout& layout) override;
  void uploadImage(int slot, const Image8& slice) override;
  void drawDepthMap(const DepthMapJob& job) override;
  void uploadDepthMap(int slot, const std::vector<float>& depth) override;
  void finishDepthMaps() override;
  RenderOutput runViewPasses(const Frame& frame, ViewPassStats& stats) override;
  unsigned int colorTexture() const override { return viewColor_.id(); }
  // The last frame's view depth at `texel` of its target (Frame::rect.depthSize, row 0 at the top):
  // the stored value, [0, 1] between near and far, 1 where nothing was drawn (render/view_pick.h);
  // none before the first frame or outside the target. Reads one pixel back (pick_pass.cpp): a
  // click's cost, not a frame's. GL backend only: the picker of builds without a ray caster.
  std::optional<double> readViewDepth(glm::ivec2 texel);
  // Depth-map layers allocated so far (the array binding; the naive binding's, all at once).
  int depthLayers() const { return depthLayers_; }

 private:
  bool naive() const { return layout_.binding == Binding::Naive; }
  // Grows the depth-map array to hold `slot` (gl_backend.cpp).
  void ensureDepthLayer(int slot);
  // depth_pass.cpp
  void drawDepth(const DepthProgram& program, const glm::dmat4& clip, double near, double far, const DateInterval& date,
                 const std::vector<DrawRange>& draws, const std::vector<std::uint64_t>& streamedTiles, double pushBack,
                 glm::dvec3 centerRender);
  // Draws the ranges; `sinceFlush` counts the indices submitted since the last glFlush (flushed
  // every kFlushIndices, see depth_pass.cpp).
  void drawRanges(const std::vector<DrawRange>& draws, std::size_t& sinceFlush);
  void ensureViewTargets(glm::ivec2 depthSize, glm::ivec2 colorSize);
  void viewDepthPass(const Frame& f);
  // points_pass.cpp
  void drawPoints(const PointProgram& program, const PointPass& pass, const Camera& cam, const hv::PinholeFrustum& fr,
                  glm::ivec2 size, glm::dvec3 centerRender);
  void uploadPointParams(const Frame& f, const glm::dmat3& viewM);
  void viewPointsPass(const Frame& f);
  // tile_pass.cpp
  void tileListPass(const Frame& f, ViewPassStats& stats);
  // shade_pass.cpp
  void uploadParams(const Frame& f);
  void uploadIdealLookup(const Camera& view);
  void bindShadeInputs(const Frame& f);
  // Picks (links on first use) the frame's shade program into shade_.
  void selectShadeProgram(const Frame& f, const ViewPassStats& stats);
  Image8 shade(ShadeMode mode, int w, int h, bool readBack);
  // debug_pass.cpp
  Image16 debugViewPass(const Frame& f, ViewPassStats& stats);
  Image16 depthMapView(const Frame& f, ViewPassStats& stats);
  // overlay_pass.cpp
  void frustaPass(const Frame& f);
  // vehicles_pass.cpp
  void vehiclesPass(const Frame& f);
  void vehicleShapes(const std::shared_ptr<const VehicleModels>& models);

  Diagnostics& diag_;
  gpu::GlLimits limits_;
  SlotLayout layout_;

  DepthProgram depthProgram_, viewDepthProgram_;
  // The generic shade program (and the naive binding's); the per-configuration ones by key
  // (gl/shade_config.h), linked when a frame first needs one; shade_ the frame's.
  ShadeProgram shadeProgram_;
  std::unordered_map<std::string, ShadeProgram> shadePrograms_;
  const ShadeProgram* shade_ = &shadeProgram_;
  TileDepthProgram tileDepthProgram_;
  gpu::VertexArray meshVao_, emptyVao_;
  gpu::Buffer vertexBuffer_, indexBuffer_;
  int indexCount_ = 0;
  std::array<DrawRange, kLayerCount> layerRange_;
  gpu::Texture validityTexture_;
  // Streamed terrain and building tiles (render/terrain_stream.h, building_stream.h), each in
  // buffers of its own.
  struct StreamedTileBuffers {
    gpu::VertexArray vao;
    gpu::Buffer vertices, indices;
    int indexCount = 0;
  };
  std::unordered_map<std::uint64_t, StreamedTileBuffers> streamedTiles_;
  int validityWidth_ = 1;

  // Slot i of both stores holds one photograph: texture arrays, or (the naive binding) one 2D
  // texture per slot for the photograph and one for its depth map, on the units the shading pass
  // leaves free.
  gpu::Texture imageArray_, depthArray_;
  // The depth-map array's layers: allocated lazily, since llvmpipe zero-fills an allocation (64
  // maps of 1024^2 are 256 MiB to clear); grown by doubling, the drawn maps blitted across.
  int depthLayers_ = 0;
  gpu::Framebuffer depthCopyRead_, depthCopyDraw_;
  std::vector<gpu::Texture> naiveImages_, naiveDepths_;
  std::vector<GLint> naiveUnits_;
  gpu::Texture paramsTexture_;
  int paramsRows_ = 0;

  gpu::Framebuffer depthFbo_, viewFbo_;
  gpu::Texture orthophoto_;  // Scene::orthophoto, RGBA8, linear, clamped to its edges
  OrthophotoAffine orthophotoAffine_;
  gpu::Texture viewDepth_, viewBuilding_, viewColor_, lookupTexture_, tileRange_, tileLists_;
  glm::ivec2 viewDepthSize_{0}, viewColorSize_{0}, tileRangeSize_{0};
  bool cullingThisFrame_ = false;
  int tilesX_ = 0;

  // The point pass.
  PointProgram pointDepthProgram_, pointColorProgram_;
  gpu::VertexArray pointVao_;
  gpu::Buffer pointBuffer_;
  float maxPointSize_ = 1.0f;
  gpu::Texture pointColor_, pointParamsTexture_;
  glm::ivec2 pointColorSize_{0};
  int pointParamsRows_ = 0;

  // Debug views and overlays, linked on first use.
  DebugDepthProgram debugDepthProgram_;
  LinesProgram linesProgram_;
  gpu::VertexArray frustumVao_;
  gpu::Buffer frustumBuffer_;
  std::uint64_t frustumVersion_ = 0;

  // Picking (pick_pass.cpp), linked on first use: a 1x1 target the packed depth is read from.
  PickDepthProgram pickDepthProgram_;
  gpu::Framebuffer pickFbo_;
  gpu::Texture pickTarget_;

  // The traffic (vehicles_pass.cpp), linked on first use.
  VehicleProgram vehicleProgram_;
  VehicleDepthProgram vehicleDepthProgram_;
  // The view's depth in the rasteriser's encoding, the traffic's depth buffer (vehicles_pass.cpp).
  gpu::Texture vehicleDepth_;
  glm::ivec2 vehicleDepthSize_{0};
  // One vertex array per vehicle class's model, and the shadow quad's last.
  std::array<gpu::VertexArray, kVehicleClasses + 1> vehicleVaos_;
  std::array<gpu::Buffer, kVehicleClasses + 1> vehicleShapes_;
  std::array<int, kVehicleClasses + 1> vehicleShapeVertices_{};
  std::shared_ptr<const VehicleModels> vehicleModels_;  // what vehicleShapes_ hold
  bool vehicleShapesBuilt_ = false;
  gpu::Buffer vehicleInstances_;
  std::vector<VehicleInstance> vehicleSorted_;  // the frame's vehicles by class
  bool warnedDebugNaive_ = false;
};

}  // namespace hv::render::gl
