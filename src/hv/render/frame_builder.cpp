#include "hv/render/frame_builder.h"

#include "hv/ibr/slice_image.h"
#include "hv/layers/sub_image.h"
#include "hv/render/geometry_tiles.h"
#include "hv/render/vehicles.h"
#include "hv/traffic/lift.h"

#include "hv/util/log.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hv::render {

namespace {

std::vector<glm::dvec3> centers(const Scene& s) {
  std::vector<glm::dvec3> c;
  for (const auto& p : s.photos) c.push_back(p.camera.center);
  return c;
}

DateInterval photoDate(const Photo& p) {
  if (p.date.empty()) return {};
  return parseDate(p.date).value_or(DateInterval{});
}

}  // namespace

FrameBuilder::FrameBuilder(const Scene& scene, const RenderSettings& settings, Diagnostics& diag, Backend& backend)
    : scene_(scene),
      settings_(settings),
      diag_(diag),
      backend_(backend),
      limits_(backend.limits()),
      index_(centers(scene)) {
  buildGeometry();
  if (scene_.terrainTiles)
    terrain_ =
        std::make_unique<TerrainStream>(*scene_.terrainTiles, scene_.origin, std::max(0, settings_.geometryThreads),
                                        std::max<std::size_t>(1, settings_.geometryMemoryBytes));
  if (scene_.buildingTiles)
    buildings_ =
        std::make_unique<BuildingStream>(scene_.buildingTiles, scene_.origin, std::max(0, settings_.geometryThreads),
                                         std::max<std::size_t>(1, settings_.geometryMemoryBytes));
  if (settings_.points.enabled) initPoints();
  allocateSlots();
  photoBroken_.assign(scene_.photos.size(), false);
  layered_.assign(scene_.photos.size(), nullptr);
  subKeys_.assign(scene_.photos.size(), {});
  depthInputs_ = depthMapInputs();
}

FrameBuilder::~FrameBuilder() = default;

void FrameBuilder::allocateSlots() {
  int w = 1, h = 1;
  for (const auto& p : scene_.photos) {
    w = std::max(w, p.camera.width);
    h = std::max(h, p.camera.height);
  }
  const int cap = std::min(settings_.maxSliceSize, limits_.maxTextureSize);
  if (w > cap || h > cap) {
    const double s = std::min(double(cap) / w, double(cap) / h);
    w = std::max(1, int(std::floor(w * s)));
    h = std::max(1, int(std::floor(h * s)));
  }
  layout_.slice = {w, h};
  layout_.depthSize = std::clamp(settings_.depthSize, 16, limits_.maxTextureSize);
  if (layout_.depthSize != settings_.depthSize)
    diag_.warn("depth-map size " + std::to_string(settings_.depthSize) + " exceeds MAX_TEXTURE_SIZE; using " +
               std::to_string(layout_.depthSize));
  // The array binding holds each slice's mip chain (mipmaps, feathering toward mask edges).
  const std::size_t perSlot = (naive() ? std::size_t(w) * h * 4 : ibr::mipChainBytes(w, h)) +
                              std::size_t(layout_.depthSize) * layout_.depthSize * 4;
  const int byMemory = int(std::max<std::size_t>(1, settings_.memoryBudgetBytes / perSlot));
  // What may be resident: every photograph and every layered photograph's sub-image.
  int slots = std::min({settings_.maxSlices, limits_.maxArrayTextureLayers, byMemory,
                        std::max(1, int(scene_.photos.size() + subImages_.size()))});
  slots = std::max(slots, 1);
  // What binds the slots, for the warning when K is capped by it: only the bounds that hold
  // (the photographs' own count is no bound worth a word), each under the name the user can act on.
  std::vector<std::string> bounds;
  if (settings_.maxSlices == slots) bounds.push_back("--max-slices " + std::to_string(settings_.maxSlices));
  if (limits_.maxArrayTextureLayers == slots)
    bounds.push_back("MAX_ARRAY_TEXTURE_LAYERS = " + std::to_string(limits_.maxArrayTextureLayers));
  if (byMemory == slots)
    bounds.push_back("--memory-budget " + std::to_string(settings_.memoryBudgetBytes >> 20) + " MiB");
  // The naive binding: two units per image; the shader's chain has 16 entries at most.
  if (naive() && slots > std::min(16, limits_.naiveImageUnits / 2)) {
    slots = std::min(16, limits_.naiveImageUnits / 2);
    bounds = {"MAX_TEXTURE_IMAGE_UNITS = " + std::to_string(limits_.maxTextureImageUnits) +
              " with --binding naive: two units per image, " + std::to_string(limits_.shadingUnits) +
              " for the pass itself"};
  }
  slotBound_.clear();
  for (const std::string& b : bounds) slotBound_ += (slotBound_.empty() ? "" : ", ") + b;
  layout_.slots = slots;
  layout_.binding = settings_.binding;
  // The depth maps are allocated as their slots are first drawn, kInitialDepthLayers at first,
  // when the budget also holds a growth's two arrays (the old one is copied into one at most twice
  // its size, no larger than `slots`); else all at once.
  const std::size_t depthBytes = std::size_t(layout_.depthSize) * layout_.depthSize * 4;
  const bool lazyDepth = !naive() && (perSlot + depthBytes) * std::size_t(slots) <= settings_.memoryBudgetBytes;
  layout_.initialDepthLayers = lazyDepth ? std::min(slots, kInitialDepthLayers) : slots;
  cache_ = ibr::SlotCache(slots);
  slotPreview_.assign(size_t(slots), false);
  stats_.sliceBytes = perSlot * size_t(slots);
  loader_ = makeLoader();
  depthScheduler_.resize(slots);
  slotFrustum_.assign(size_t(slots), {});
  slotCut_.assign(size_t(slots), {});
  slotCutDrawn_.assign(size_t(slots), {});
  slotBuildingCut_.assign(size_t(slots), {});
  slotBuildingCutDrawn_.assign(size_t(slots), {});
  backend_.allocateSlots(layout_);
  log::debug("slices: " + std::to_string(slots) + " of " + std::to_string(w) + "x" + std::to_string(h) +
             ", depth maps " + std::to_string(layout_.depthSize) + "^2");
}

std::unique_ptr<ibr::ImageLoader> FrameBuilder::makeLoader() const {
  return std::make_unique<ibr::ImageLoader>(layout_.slice, std::max(0, settings_.decodeThreads),
                                            settings_.decodeMemoryBytes, settings_.blend.masks);
}

// Residency (de Castro & Brédif 2022 §2.1): pins the plan's resident photos, asks the loader for
// the others (nearest first) and installs what it delivers: all of them in batch frames
// (waiting), what is ready in progressive ones. Returns false when a planned photo turned out broken.
bool FrameBuilder::makeResident(FrameMode mode) {
  cache_.unpinAll();
  std::vector<int> missing, larger;
  std::vector<ibr::LoadRequest> requests;
  for (const auto& im : plan_.images) {
    if (layeredPhoto(im.photo)) {
      // Its sub-images instead of the photograph: in memory, installed at once.
      for (int key : subKeys_[size_t(im.photo)])
        if (!cache_.pin(key)) installSubImage(key);
      continue;
    }
    if (cache_.pin(im.photo)) {
      // Resident as a smaller image whose larger one is loading: a batch frame waits for it.
      if (slotPreview_[size_t(cache_.slotOf(im.photo))]) larger.push_back(im.photo);
      continue;
    }
    missing.push_back(im.photo);
    // A batch frame waits for the full images: no preview first.
    requests.push_back({im.photo, &scene_.photos[size_t(im.photo)], im.distance, mode != FrameMode::Batch});
  }
  loader_->request(requests);
  auto needed = [&](int photo) { return std::find(missing.begin(), missing.end(), photo) != missing.end(); };
  auto sink = [&](ibr::LoadResult&& r) {
    const int photo = r.photo;
    install(std::move(r), needed(photo));
  };
  if (mode == FrameMode::Batch) {
    larger.insert(larger.end(), missing.begin(), missing.end());
    loader_->wait(larger, sink);
  } else {
    for (auto& r : loader_->poll()) sink(std::move(r));
  }
  stats_.decodePeakBytes = loader_->peakBytes();
  for (int photo : missing)
    if (photoBroken_[size_t(photo)]) return false;
  return true;
}

std::vector<std::string> FrameBuilder::excludedIds() const {
  std::vector<std::string> ids = settings_.blend.exclude;
  for (size_t i = 0; i < photoBroken_.size(); ++i)
    if (photoBroken_[i]) ids.push_back(scene_.photos[i].camera.id);
  return ids;
}

ibr::BlendSettings FrameBuilder::frameBlendSettings() {
  ibr::BlendSettings blend = settings_.blend;
  const int slots = layout_.slots;
  if (blend.k > slots && blend.selection == ibr::Selection::Global) {
    // K at or above the photographs' count is no loss: every photograph has a slot. Otherwise it
    // is said once for this builder (and the log prints a message once per run).
    if (std::min(blend.k, int(scene_.photos.size())) > slots && !warnedK_ && !slotBound_.empty()) {
      diag_.warn("K = " + std::to_string(blend.k) + " exceeds the image slots available (" + std::to_string(slots) +
                 ", bounded by " + slotBound_ + "); using K = " + std::to_string(slots));
      warnedK_ = true;
    }
    blend.k = slots;
  }
  // The naive binding is the papers' blend with a sampler pair per image (the baseline of de Castro
  // & Brédif 2022's texture arrays): what goes beyond the papers is not in its shader.
  if (naive()) {
    std::vector<std::string> off;
    if (blend.featherPx > 0.0) off.push_back("--feather");
    if (blend.weighting == ibr::Weighting::Geometry) off.push_back("--weights geometry");
    if (blend.mipmaps) off.push_back("--mipmaps");
    if (blend.consensus > 0.0) off.push_back("--consensus");
    if (!off.empty() && !warnedNaive_) {
      std::string list;
      for (const auto& o : off) list += (list.empty() ? "" : ", ") + o;
      diag_.warn("--binding naive blends as the papers do: " + list + " not applied (--binding array applies them)");
      warnedNaive_ = true;
    }
    blend.featherPx = 0.0;
    blend.weighting = ibr::Weighting::Distance;
    blend.mipmaps = false;
    blend.consensus = 0.0;
  }
  // Region selection: the candidates are what is resident, so the slots bound them (and K stays
  // the most images blended at one pixel).
  if (blend.selection == ibr::Selection::Region || blend.weighting == ibr::Weighting::Geometry)
    blend.candidates = std::clamp(blend.candidates, 1, slots);
  // Geometry weights keep the K + 1 best of each pixel in the shader's fixed arrays.
  if (blend.weighting == ibr::Weighting::Geometry && blend.k > ibr::kMaxGeometryK) {
    diag_.warn("K = " + std::to_string(blend.k) + " exceeds what the geometry weights blend at one pixel (" +
               std::to_string(ibr::kMaxGeometryK) + "); using K = " + std::to_string(ibr::kMaxGeometryK));
    blend.k = ibr::kMaxGeometryK;
  }
  return blend;
}

// Plans the frame and makes every selected image resident (batch) or asks for them
// (progressive); a photo that fails to load is excluded and the frame planned again, so the
// blend never counts an image it cannot sample.
void FrameBuilder::planAndLoad(const Camera& view, ibr::BlendSettings& blend, FrameMode mode) {
  for (int attempt = 0;; ++attempt) {
    blend.exclude = excludedIds();
    if (blend.selection == ibr::Selection::Region && !geometryBounds_.empty() &&
        (!frusta_ || frusta_->bounds().lo != geometryBounds_.lo || frusta_->bounds().hi != geometryBounds_.hi)) {
      std::vector<Camera> cameras;
      for (const auto& p : scene_.photos) cameras.push_back(p.camera);
      frusta_ = std::make_unique<ibr::FrustumIndex>(cameras, geometryBounds_);
    }
    plan_ = ibr::planFrame(scene_, index_, view, blend, geometryBounds_, frusta_.get());
    if (makeResident(mode)) return;
    if (attempt > int(scene_.photos.size())) throw std::runtime_error("cannot make the selected images resident");
  }
}

void FrameBuilder::preload(const Camera& view) {
  applyLiveSettings();
  ibr::BlendSettings blend = frameBlendSettings();
  planAndLoad(view, blend, FrameMode::Batch);
}

// The camera photograph `photo` is projected with: its own, or without its lens distortion
// (LayerSettings::lensDistortion off).
Camera FrameBuilder::photoCamera(int photo) const {
  Camera cam = scene_.photos[size_t(photo)].camera;
  if (!settings_.layers.lensDistortion) cam.distortion.reset();
  return cam;
}

// The pinhole frustum of a photograph's depth map: the ideal rectangle covering its image (with
// a pixel of margin), the depth range of everything that may be drawn into it.
hv::PinholeFrustum FrameBuilder::depthFrustum(int photo) const {
  const Camera cam = photoCamera(photo);
  hv::PinholeFrustum fr = hv::idealRectCoveringImage(cam, 1.0);
  hv::setDepthRange(fr, cam, bounds_);
  return fr;
}

FrameBuilder::DepthMapInputs FrameBuilder::depthMapInputs() const {
  DepthMapInputs in;
  in.layers = {settings_.layers.terrain, settings_.layers.buildings, settings_.layers.mesh};
  in.lensDistortion = settings_.layers.lensDistortion;
  in.points = pointsActive() && pointsInDepthMaps_;
  if (in.points) {
    const PointSettings& ps = settings_.points;
    in.pointBudget = ps.budget;
    in.pointRadius = ps.radius;
    in.pointRadiusScale = ps.radiusScale;
    in.keptClasses = ps.keptClasses;
    in.meshPushBack = meshPushBack();
  }
  return in;
}

// Every resident photograph's depth map is redrawn, with frusta recomputed (the bounds or the
// lens model may have changed).
void FrameBuilder::invalidateDepthMaps() {
  for (int slot = 0; slot < layout_.slots; ++slot)
    if (const int key = cache_.photoIn(slot); key >= 0)
      slotFrustum_[size_t(slot)] = isSubImage(key) ? subImageDepthFrustum(key) : depthFrustum(key);
  depthScheduler_.markAllDirty();
}

// Masks switched: the slices hold the colour premultiplied by the mask, so every photograph is
// decoded again (a new loader drops the pending decodes; broken photographs get another try, as
// their mask may have been what failed).
void FrameBuilder::reloadPhotographs() {
  loader_.reset();
  loader_ = makeLoader();
  loaderMasks_ = settings_.blend.masks;
  cache_.clear();
  slotPreview_.assign(slotPreview_.size(), false);
  photoBroken_.assign(scene_.photos.size(), false);
  depthScheduler_.markAllDirty();
}

// Compares the settings with what is resident and drawn, and invalidates what they change.
void FrameBuilder::applyLiveSettings() {
  if (settings_.blend.masks != loaderMasks_) reloadPhotographs();
  if (settings_.points.enabled && !pointsTried_) {
    initPoints();
    if (pointsOn_) invalidateDepthMaps();  // the points extended the bounds: depth ranges change
  }
  if (pointsOn_) resolvePointFilter();
  const DepthMapInputs now = depthMapInputs();
  if (now != depthInputs_) {
    invalidateDepthMaps();
    depthInputs_ = now;
  }
}

// DebugView::DepthMap shows one photograph's depth map whether or not the frame selects it: it is
// made resident (batch frames wait for it) and pinned. Returns its slot, -1 when it is not (yet)
// resident, is broken, or every slot is pinned by the frame.
int FrameBuilder::prepareDebugPhoto(FrameMode mode) {
  const int photo = settings_.debug.photo;
  if (settings_.debug.view != DebugView::DepthMap || photo < 0 || photo >= int(scene_.photos.size()) ||
      photoBroken_[size_t(photo)])
    return -1;
  if (cache_.pin(photo)) return cache_.slotOf(photo);
  loader_->request(photo, scene_.photos[size_t(photo)], 0.0, mode != FrameMode::Batch);
  auto sink = [&](ibr::LoadResult&& r) {
    const int p = r.photo;
    install(std::move(r), p == photo);
  };
  if (mode == FrameMode::Batch)
    loader_->wait({photo}, sink);
  else
    for (auto& r : loader_->poll()) sink(std::move(r));
  return cache_.slotOf(photo);
}

DepthMapJob FrameBuilder::depthMapJob(int slot) const {
  DepthMapJob job;
  job.slot = slot;
  job.photo = cache_.photoIn(slot);
  job.camera = photoCamera(job.photo);
  job.frustum = slotFrustum_[size_t(slot)];
  job.clipFromRender = hv::clipFromRender(job.camera, job.frustum, scene_.origin);
  job.centerRender = job.camera.center - scene_.origin;
  job.date = photoDate(scene_.photos[size_t(job.photo)]);
  job.pushBack = meshPushBack();
  job.layers = {settings_.layers.terrain, settings_.layers.buildings, settings_.layers.mesh};
  job.draws = visibleRanges(tiles_, job.layers, job.clipFromRender, settings_.geometryCulling, &job.tiles);
  if (terrain_ && job.layers[kLayerTerrain])
    job.streamedTiles = visibleTerrain(slotCut_[size_t(slot)], job.clipFromRender);
  if (buildings_ && job.layers[kLayerBuildings]) {
    const std::vector<std::uint64_t> b = visibleBuildings(slotBuildingCut_[size_t(slot)], job.clipFromRender);
    job.streamedTiles.insert(job.streamedTiles.end(), b.begin(), b.end());
  }
  job.tiles += int(job.streamedTiles.size());
  job.size = layout_.depthSize;
  job.withPoints = pointsActive() && pointsInDepthMaps_;
  // Transient points never occlude.
  if (job.withPoints) job.points = pointPass(job.camera, true, 0.0);
  return job;
}

// Depth maps (de Castro & Brédif 2022 §2.2): all of them in batch mode, else the nearest Dmax,
// or fewer when the time budget is spent (at least one per frame).
void FrameBuilder::drawDepthMaps(Frame& f, int debugSlot) {
  std::vector<int> residentSlots;
  std::vector<double> residentPriority;
  for (size_t i = 0; i < f.plan.images.size(); ++i) {
    if (layeredPhoto(f.plan.images[i].photo)) {
      // Each resident sub-image's map, at the photograph's priority.
      for (int key : subKeys_[size_t(f.plan.images[i].photo)])
        if (const int slot = cache_.slotOf(key); slot >= 0) {
          residentSlots.push_back(slot);
          residentPriority.push_back(f.plan.images[i].distance);
        }
      continue;
    }
    if (f.slots[i] < 0) continue;
    residentSlots.push_back(f.slots[i]);
    residentPriority.push_back(f.plan.images[i].distance);
  }
  stats_.depthMapsThisFrame = 0;
  const int dmax = f.mode == FrameMode::Batch ? 0 : settings_.depthMapsPerFrame;
  f.depthBudgeted = f.mode == FrameMode::Progressive && settings_.depthBudgetMs > 0.0;
  f.depthMapQueue = depthScheduler_.next(residentSlots, residentPriority, dmax);
  stats_.depthMapTilesThisFrame = 0;
  auto draw = [&](int slot) {
    if (const int key = cache_.photoIn(slot); isSubImage(key)) {
      // A sub-image's peeled depth map: uploaded, not drawn.
      backend_.uploadDepthMap(slot, subImageDepth(key, slotFrustum_[size_t(slot)]));
      depthScheduler_.done(slot);
      ++stats_.depthMapsUploaded;
      return;
    }
    const DepthMapJob job = depthMapJob(slot);
    stats_.depthMapTilesThisFrame += job.tiles;
    backend_.drawDepthMap(job);
    depthScheduler_.done(slot);
    slotCutDrawn_[size_t(slot)] = slotCut_[size_t(slot)];
    slotBuildingCutDrawn_[size_t(slot)] = slotBuildingCut_[size_t(slot)];
    f.depthMapsDrawn.push_back(slot);
    ++stats_.depthMapsRendered;
    ++stats_.depthMapsThisFrame;
  };
  const auto start = std::chrono::steady_clock::now();
  for (int slot : f.depthMapQueue) {
    if (f.depthBudgeted && stats_.depthMapsThisFrame > 0 &&
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count() >=
            settings_.depthBudgetMs)
      break;
    draw(slot);
    if (f.depthBudgeted) backend_.finishDepthMaps();
  }
  // The depth-map debug view's photograph, outside the schedule: one map, when it is shown.
  if (debugSlot >= 0 && depthScheduler_.isDirty(debugSlot)) draw(debugSlot);
}

// Per-image parameters (2022 §2.1, ibr::packImageParams): one row per image. An image whose
// depth map is not current yet (progressive frames) waits, unless occlusion is off.
void FrameBuilder::packParams(Frame& f) {
  params_.clear();
  const double biasAbs = depthBiasAbsolute();
  stats_.imagesWaiting = stats_.decodesWaiting = stats_.depthMapsWaiting = 0;
  previewsShown_ = 0;
  for (size_t i = 0; i < f.plan.images.size(); ++i) {
    if (layeredPhoto(f.plan.images[i].photo)) {
      packLayered(f, f.plan.images[i]);
      continue;
    }
    const int slot = f.slots[i];
    if (slot < 0 || (f.blend.occlusion && depthScheduler_.isDirty(slot))) {
      ++stats_.imagesWaiting;
      ++(slot < 0 ? stats_.decodesWaiting : stats_.depthMapsWaiting);
      continue;
    }
    const int photo = f.plan.images[i].photo;
    if (slotPreview_[size_t(slot)]) ++previewsShown_;
    const Camera cam = photoCamera(photo);
    const hv::PinholeFrustum& fr = slotFrustum_[size_t(slot)];
    const double texel = std::max((fr.pxMax.x - fr.pxMin.x) / (layout_.depthSize * cam.focal.x),
                                  (fr.pxMax.y - fr.pxMin.y) / (layout_.depthSize * cam.focal.y));
    const ibr::DepthBias bias{biasAbs, settings_.depthBiasTexels * texel};
    params_.push_back(ibr::makeImageParams(cam, scene_.origin, ibr::sliceLayout(cam, layout_.slice, slot),
                                           f.plan.images[i].weight, fr, bias));
    params_.back().photo = photo;
    params_.back().date = photoDate(scene_.photos[size_t(photo)]);
    if (settings_.blend.colourCorrection) params_.back().colour = scene_.photos[size_t(photo)].colour;
    f.packedParams.resize(f.packedParams.size() + ibr::kTexelsPerImage * 4);
    ibr::packImageParams(params_.back(), f.packedParams.data() + f.packedParams.size() - ibr::kTexelsPerImage * 4);
  }
  f.params = params_;
}

Frame FrameBuilder::build(const Camera& view, FrameMode mode, bool withCounts) {
  Frame f;
  f.number = ++frame_;
  f.mode = mode;
  f.view = view;
  f.origin = scene_.origin;
  applyLiveSettings();
  f.blend = frameBlendSettings();
  planAndLoad(view, f.blend, mode);
  f.plan = plan_;
  const int debugSlot = prepareDebugPhoto(mode);
  for (const auto& im : plan_.images)
    f.slots.push_back(layeredPhoto(im.photo) ? layeredSlot(im.photo) : cache_.slotOf(im.photo));
  // The view's rectangle: the pinhole rectangle covering the (distorted) view, at the output's
  // pixel density.
  f.rect.distorted = view.distortion && !view.distortion->isIdentity();
  f.rect.frustum = hv::idealRectCoveringImage(view, 0.0);
  hv::setDepthRange(f.rect.frustum, view, bounds_);
  f.rect.depthSize = glm::ivec2(view.width, view.height);
  if (f.rect.distorted) {
    const hv::PinholeFrustum& vf = f.rect.frustum;
    f.rect.depthSize = glm::ivec2(std::ceil(vf.pxMax.x - vf.pxMin.x), std::ceil(vf.pxMax.y - vf.pxMin.y));
    f.rect.depthSize = glm::min(f.rect.depthSize, glm::ivec2(limits_.maxTextureSize));
  }
  f.rect.clipFromRender = hv::clipFromRender(view, f.rect.frustum, scene_.origin);
  streamTerrain(f, debugSlot);
  streamBuildings(f, debugSlot);
  drawDepthMaps(f, debugSlot);
  debugWaiting_ = settings_.debug.view == DebugView::DepthMap && debugSlot < 0 && settings_.debug.photo >= 0 &&
                  loader_->isPending(settings_.debug.photo);
  packParams(f);
  // What a frame shows of its photographs: previews stand in for full images still loading.
  if (log::level() == log::Level::Debug)
    log::debug("frame " + std::to_string(f.number) + (mode == FrameMode::Batch ? " (batch)" : " (progressive)") + ": " +
               std::to_string(params_.size()) + " images shown, " + std::to_string(previewsShown_) + " as previews, " +
               std::to_string(stats_.imagesWaiting) + " waiting");

  stats_.residentImages = cache_.residentCount();
  stats_.debugSlot = debugSlot >= 0 ? debugSlot : cache_.slotOf(settings_.debug.photo);
  stats_.debugImage = -1;
  for (size_t i = 0; i < params_.size(); ++i)
    if (params_[i].photo == settings_.debug.photo) stats_.debugImage = int(i);

  f.layers = {settings_.layers.terrain, settings_.layers.buildings, settings_.layers.mesh};
  f.draws = visibleRanges(tiles_, f.layers, f.rect.clipFromRender, settings_.geometryCulling, &stats_.tilesDrawn);
  stats_.trianglesDrawn = 0;
  for (const DrawRange& r : f.draws) stats_.trianglesDrawn += r.count / 3;
  for (std::uint64_t id : f.streamedTiles) stats_.trianglesDrawn += std::int64_t(streamedTriangles(id));
  stats_.tilesDrawn += int(f.streamedTiles.size());
  const PointSettings& ps = settings_.points;
  f.points.enabled = pointsActive();
  stats_.pointsDrawn = 0;
  if (f.points.enabled) {
    f.points.pass = pointPass(view, ps.hideTransient, meshOffset());
    f.points.epsilonTest = epsilonTest_;
    f.points.epsilon = pointEpsilon();
    f.points.eyeDome = ps.eyeDome;
    f.points.eyeDomeStrength = ps.eyeDomeStrength;
    f.points.eyeDomeRadiusPx = ps.eyeDomeRadiusPx;
    stats_.pointsDrawn = f.points.pass.points;
    const int n = int(params_.size());
    if (mat3K_ > 0 && n > mat3K_) {
      if (!warnedMat3_)
        diag_.warn("mat3 sprites carry " + std::to_string(mat3K_) + " images; the points blend the " +
                   std::to_string(mat3K_) + " nearest of " + std::to_string(n));
      warnedMat3_ = true;
    }
  }
  f.sphereRadius = sphereRadius();
  // The naive binding walks every selected image (it is the baseline without culling). Tile
  // lists come from the geometry's depth: pixels on the background sphere have none.
  f.culling = settings_.tileCulling && !naive() && !params_.empty() && f.sphereRadius <= 0.0;
  f.tileSize = std::max(1, settings_.tileSize);
  f.meshPushBack = meshPushBack();
  f.background = settings_.background;
  f.untextured = settings_.untextured;
  f.up = scene_.up;
  f.debug.view = settings_.debug.view;
  f.debug.photo = settings_.debug.photo;
  f.debug.slot = debugSlot;
  if (debugSlot >= 0) f.debug.slotFrustum = slotFrustum_[size_t(debugSlot)];
  f.debug.image = stats_.debugImage;
  // Not over the depth-map view: that picture is in the photograph's image, not the view's.
  f.debug.frusta = settings_.debug.frusta && settings_.debug.view != DebugView::DepthMap;
  if (f.debug.frusta) f.debug.frustumLines = &frustumLines();
  f.withCounts = withCounts;
  f.readBackColour = settings_.readBackColour;
  trafficOfFrame(f);
  return f;
}

// The vehicles at the settings' time, on the terrain the view shows (scene.terrain, whatever it
// was made from). Pinhole views only (render/gl/vehicles_pass.cpp).
void FrameBuilder::trafficOfFrame(Frame& f) {
  if (!settings_.traffic.enabled || !scene_.traffic || scene_.traffic->vehicles.empty()) return;
  if (!terrainHeight_) {
    terrainHeight_ = std::make_unique<MeshTerrainHeight>(scene_.terrain);
    if (terrainHeight_->empty()) diag_.warn("traffic: the scene has no terrain to put the vehicles on (not drawn)");
  }
  if (terrainHeight_->empty()) return;
  if (f.rect.distorted) {
    if (!warnedTrafficDistorted_) diag_.warn("traffic: not drawn in a view with lens distortion (pinhole views only)");
    warnedTrafficDistorted_ = true;
    return;
  }
  f.traffic.vehicles = vehicleInstances(*scene_.traffic, *terrainHeight_, settings_.traffic.time, scene_.origin);
  f.traffic.models = scene_.traffic->models;
}

void FrameBuilder::viewPassesDone(const Frame& f, const ViewPassStats& s) {
  if (s.tileListsBuilt) {
    stats_.meanTileList = s.meanTileList;
    stats_.maxTileList = s.maxTileList;
  }
  if (f.debug.view == DebugView::DepthMap) {
    stats_.debugDepthNear = s.debugDepthNear;
    stats_.debugDepthFar = s.debugDepthFar;
  }
}

PhotoState FrameBuilder::photoState(int photo) const {
  if (photo < 0 || photo >= int(scene_.photos.size())) return PhotoState::Absent;
  if (photoBroken_[size_t(photo)]) return PhotoState::Broken;
  if (layeredPhoto(photo)) {
    bool anyResident = false, allResident = true, dirty = false;
    for (int key : subKeys_[size_t(photo)]) {
      const int s = cache_.slotOf(key);
      anyResident = anyResident || s >= 0;
      allResident = allResident && s >= 0;
      dirty = dirty || (s >= 0 && depthScheduler_.isDirty(s));
    }
    if (!anyResident) return PhotoState::Absent;
    return !allResident || dirty ? PhotoState::DepthMapPending : PhotoState::Ready;
  }
  const int slot = cache_.slotOf(photo);
  if (slot < 0) return loader_->isPending(photo) ? PhotoState::Decoding : PhotoState::Absent;
  return depthScheduler_.isDirty(slot) ? PhotoState::DepthMapPending : PhotoState::Ready;
}

}  // namespace hv::render
