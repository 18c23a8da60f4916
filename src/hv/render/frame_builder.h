// The frame builder: turns (scene, view camera, settings, what is resident) into a Frame
// (render/frame.h) and drives a Backend (render/backend.h) through it. It owns everything about a
// frame that is not drawing: the plan (ibr::planFrame), residency (ibr::SlotCache, the decodes of
// ibr::ImageLoader), the depth-map schedule and its per-frame budget (ibr::DepthMapScheduler;
// de Castro & Brédif 2022 §2.2), the per-image parameters, the point chunks each pass draws, the
// statistics, and what a changed setting invalidates. No GL: tested through the null backend.
#pragma once

#include "hv/ibr/depth_scheduler.h"
#include "hv/ibr/image_loader.h"
#include "hv/ibr/slot_cache.h"
#include "hv/layers/layered_texture.h"
#include "hv/render/backend.h"
#include "hv/render/building_stream.h"
#include "hv/render/frame.h"
#include "hv/render/terrain_stream.h"
#include "hv/util/diagnostics.h"

#include <memory>
#include <vector>

namespace hv {
class MeshTerrainHeight;  // hv/traffic/lift.h
}

namespace hv::render {

class FrameBuilder {
 public:
  // Builds the geometry (and, when enabled, the points) and allocates the slots on `backend`.
  // `settings` is the renderer's: a change applies from the next frame.
  FrameBuilder(const Scene& scene, const RenderSettings& settings, Diagnostics& diag, Backend& backend);
  ~FrameBuilder();
  FrameBuilder(const FrameBuilder&) = delete;
  FrameBuilder& operator=(const FrameBuilder&) = delete;

  // One frame: applies the live settings, plans, makes the images resident (batch: waiting for
  // their decodes), draws the scheduled depth maps on the backend and packs the parameters. The
  // view passes are left to the caller (Backend::runViewPasses).
  Frame build(const Camera& view, FrameMode mode, bool withCounts);
  // The stats the view passes report, merged into stats().
  void viewPassesDone(const Frame& frame, const ViewPassStats& passStats);
  // Makes the images a view needs resident without building a frame.
  void preload(const Camera& view);

  // Converged: nothing waits, and no image is shown as its preview (ibr::ImageLoader).
  bool converged() const {
    return stats_.imagesWaiting == 0 && previewsShown_ == 0 && !debugWaiting_ && terrainMissing_ == 0 &&
           buildingsMissing_ == 0;
  }
  // The images of the last frame shown as their preview (their full image still loading).
  int previewsShown() const { return previewsShown_; }
  // The streamed terrain (null without Scene::terrainTiles) and buildings (null without
  // Scene::buildingTiles).
  const TerrainStream* terrainStream() const { return terrain_.get(); }
  const BuildingStream* buildingStream() const { return buildings_.get(); }
  const ibr::FramePlan& lastPlan() const { return plan_; }
  const std::vector<ibr::ImageParams>& lastImageParams() const { return params_; }
  ibr::SliceSize sliceSize() const { return layout_.slice; }
  int slotCount() const { return layout_.slots; }
  RenderStats& stats() { return stats_; }
  const RenderStats& stats() const { return stats_; }
  PhotoState photoState(int photo) const;
  int slotOf(int photo) const { return cache_.slotOf(photo); }
  // The job that draws the depth map of the photograph in `slot` with the current settings.
  DepthMapJob depthMapJob(int slot) const;
  // Renderer::setLayeredPhotograph: photograph `photo` is expanded into its sub-images when
  // selected (null: the photograph as it is). Empties the slots.
  void setLayeredPhotograph(int photo, std::shared_ptr<const layers::LayeredPhotograph> layered);
  // Renderer::replaceImage: photograph `photo`'s Photo::imagePath now names a larger image of it.
  void replaceImage(int photo);
  // Renderer::setOrthophoto: handed to the backend with its map from the render frame.
  void setOrthophoto(std::shared_ptr<const Orthophoto> orthophoto);
  // The cache keys of a layered photograph's sub-images, in blending order (visibility layer, then
  // the file's order); empty for a photograph as it is. Keys are photos.size() and up.
  const std::vector<int>& subImageKeys(int photo) const { return subKeys_[size_t(photo)]; }

 private:
  // What the photographs' depth maps are drawn from besides the scene itself: when it changes
  // between frames every depth map is redrawn (a layer, the lens model, the points they hold).
  struct DepthMapInputs {
    std::array<bool, kLayerCount> layers{true, true, true};
    bool lensDistortion = true;
    bool points = false;
    std::uint64_t pointBudget = 0;
    double pointRadius = 0.0, pointRadiusScale = 0.0;
    std::vector<int> keptClasses;
    double meshPushBack = 0.0;
    bool operator==(const DepthMapInputs&) const = default;
  };

  // A layered photograph's sub-image (Layered projective texture maps, 2003, §5): which
  // photograph, which of its sub-images. Resident under its own key in the slot cache, its image
  // resampled into the slot and its peeled depth map D_k uploaded (never drawn).
  struct SubImageRef {
    int photo = -1;
    int index = -1;  // into LayeredPhotograph::subImages
  };
  bool isSubImage(int key) const { return key >= int(scene_.photos.size()); }
  const SubImageRef& subImage(int key) const { return subImages_[size_t(key) - scene_.photos.size()]; }
  bool layeredPhoto(int photo) const { return !subKeys_[size_t(photo)].empty(); }
  void installSubImage(int key);
  hv::PinholeFrustum subImageDepthFrustum(int key) const;
  std::vector<float> subImageDepth(int key, const hv::PinholeFrustum& frustum) const;
  Image8 subImageSlice(int key) const;
  // The slot of each sub-image of a layered photograph when all are resident, else -1.
  int layeredSlot(int photo) const;
  void buildGeometry();
  void initPoints();
  void resolvePointFilter();
  void allocateSlots();
  void install(ibr::LoadResult&& r, bool neededNow);
  bool makeResident(FrameMode mode);
  void planAndLoad(const Camera& view, ibr::BlendSettings& blend, FrameMode mode);
  ibr::BlendSettings frameBlendSettings();
  int prepareDebugPhoto(FrameMode mode);
  void drawDepthMaps(Frame& frame, int debugSlot);
  std::vector<int> drawnSlots(const Frame& frame, int debugSlot) const;
  void streamTerrain(Frame& frame, int debugSlot);
  std::vector<std::uint64_t> visibleTerrain(const std::vector<TerrainNodeId>& cut,
                                            const glm::dmat4& clipFromRender) const;
  void streamBuildings(Frame& frame, int debugSlot);
  std::vector<std::uint64_t> visibleBuildings(const std::vector<std::uint32_t>& cut,
                                              const glm::dmat4& clipFromRender) const;
  void setBuildingValidity(std::uint32_t first, const std::vector<glm::vec2>& days);
  std::size_t streamedTriangles(std::uint64_t id) const;
  void packParams(Frame& frame);
  void packLayered(Frame& frame, const ibr::SelectedImage& selected);
  void trafficOfFrame(Frame& frame);
  void applyLiveSettings();
  void invalidateDepthMaps();
  void reloadPhotographs();
  std::unique_ptr<ibr::ImageLoader> makeLoader() const;
  const FrustumLines& frustumLines();

  Camera photoCamera(int photo) const;
  hv::PinholeFrustum depthFrustum(int photo) const;
  DepthMapInputs depthMapInputs() const;
  std::vector<std::string> excludedIds() const;
  PointPass pointPass(const Camera& cam, bool dropTransient, double depthOffset) const;
  bool naive() const { return settings_.binding == Binding::Naive; }
  bool pointsActive() const { return pointsOn_ && settings_.points.enabled; }
  double meshPushBack() const;
  double meshOffset() const;
  double pointEpsilon() const;
  double depthBiasAbsolute() const;
  double sphereRadius() const;

  const Scene& scene_;
  const RenderSettings& settings_;
  Diagnostics& diag_;
  Backend& backend_;
  BackendLimits limits_;
  ibr::CameraIndex index_;
  // Region selection: the photographs' frusta over geometryBounds_, built at the first region frame
  // and again when the bounds change.
  std::unique_ptr<ibr::FrustumIndex> frusta_;
  Aabb bounds_;          // geometry and camera centres: depth ranges
  Aabb geometryBounds_;  // geometry only: the frustum filter
  Aabb inlierBounds_;    // robustExtent (hv/scene/robust_extent.h): what the two boxes above may cover

  SlotLayout layout_;
  ibr::SlotCache cache_;
  std::vector<bool> slotPreview_;  // the slot holds a smaller image of its photograph (the larger one follows)
  int previewsShown_ = 0;
  std::unique_ptr<ibr::ImageLoader> loader_;
  bool loaderMasks_ = true;
  ibr::DepthMapScheduler depthScheduler_;
  std::vector<hv::PinholeFrustum> slotFrustum_;
  std::vector<bool> photoBroken_;
  DepthMapInputs depthInputs_;
  std::uint64_t frame_ = 0;

  // The points (uploaded on first use).
  bool pointsTried_ = false, pointsOn_ = false;
  bool classify_ = false, epsilonTest_ = false, pointsInDepthMaps_ = false;
  bool warnedPointClasses_ = false, warnedMat3_ = false, warnedK_ = false, warnedNaive_ = false;
  std::string slotBound_;  // what bounds layout_.slots, in words (allocateSlots)
  int mat3K_ = 0;
  std::vector<double> chunkSpacing_;  // mean point spacing of each chunk, scene units
  std::vector<GeometryTile> tiles_;   // the geometry's tiles (render/geometry_tiles.h)
  // The streamed terrain (Scene::terrainTiles): each slot's cut as of this frame and as its depth
  // map was drawn (a change marks the map dirty), the tiles this frame's cuts wait for.
  std::unique_ptr<TerrainStream> terrain_;
  std::vector<std::vector<TerrainNodeId>> slotCut_, slotCutDrawn_;
  int terrainMissing_ = 0;
  // The streamed buildings (Scene::buildingTiles), likewise, and the validity texels of the
  // resident buildings (uploaded whole when a tile brings new ones).
  static constexpr int kValidityWidth = 1024;
  // Depth-map layers allocated at start when they grow lazily (allocateSlots): a first progressive
  // frame's maps and then some.
  static constexpr int kInitialDepthLayers = 8;
  std::unique_ptr<BuildingStream> buildings_;
  std::vector<std::vector<std::uint32_t>> slotBuildingCut_, slotBuildingCutDrawn_;
  int buildingsMissing_ = 0;
  std::vector<float> validity_;
  bool validityDirty_ = false;

  ibr::FramePlan plan_;
  // Layered photographs (setLayeredPhotograph): per photo its layers (null: none) and its
  // sub-images' keys; per key - photos.size(), the sub-image.
  std::vector<std::shared_ptr<const layers::LayeredPhotograph>> layered_;
  std::vector<std::vector<int>> subKeys_;
  std::vector<SubImageRef> subImages_;
  std::vector<ibr::ImageParams> params_;
  RenderStats stats_;
  bool debugWaiting_ = false;  // the depth-map view's photograph is still being decoded
  FrustumLines frustumLines_;
  double frustumDepthBuilt_ = -1.0;
  bool frustumLensBuilt_ = true;
  // The traffic's terrain heights (scene.terrain), built on first use.
  std::unique_ptr<MeshTerrainHeight> terrainHeight_;
  bool warnedTrafficDistorted_ = false;
};

}  // namespace hv::render
