// The frame builder's scene side: the geometry and point buffers it hands the backend once, the
// point chunks each pass draws, the frusta overlay's lines, and the scale-derived defaults.
#include "hv/render/frame_builder.h"

#include "hv/render/geometry_tiles.h"

#include "hv/camera/frustum_outline.h"
#include "hv/scene/building_tiles.h"
#include "hv/scene/chunks.h"
#include "hv/scene/point_normals.h"
#include "hv/scene/robust_extent.h"
#include "hv/scene/point_colors.h"
#include "hv/util/log.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace hv::render {

namespace {

// `box` limited to `limit` (unchanged when either is empty or they do not meet).
Aabb clippedTo(const Aabb& box, const Aabb& limit) {
  if (box.empty() || limit.empty()) return box;
  Aabb c;
  c.lo = glm::max(box.lo, limit.lo);
  c.hi = glm::min(box.hi, limit.hi);
  return c.empty() ? box : c;
}

}  // namespace

void FrameBuilder::buildGeometry() {
  GeometryBuffers g;
  constexpr int kStride = GeometryBuffers::kStride;
  const glm::vec2 always = ibr::gpuDays(DateInterval{});
  // A streamed terrain (render/terrain_stream.h) and streamed buildings (render/building_stream.h)
  // are drawn from their own tiles, not from the buffer.
  static const Mesh kNone;
  const std::array<const Mesh*, kLayerCount> layers = {scene_.terrainTiles ? &kNone : &scene_.terrain,
                                                       scene_.buildingTiles ? &kNone : &scene_.buildings, &scene_.mesh};
  // The tile grid covers the inliers' ground extent (one absurd vertex does not stretch it).
  const Aabb inliers = robustExtent(scene_).bounds;
  std::size_t triangles = 0;
  for (const Mesh* m : layers) triangles += m->triangles.size();
  const TileGridXY grid = inliers.empty() ? TileGridXY{}
                                          : makeTileGrid(glm::dvec2(inliers.lo - scene_.origin),
                                                         glm::dvec2(inliers.hi - scene_.origin), triangles);
  std::vector<glm::dvec3> renderPositions;
  for (int layer = 0; layer < kLayerCount; ++layer) {
    const Mesh* m = layers[size_t(layer)];
    const bool isBuildings = m == &scene_.buildings;
    const bool isMesh = m == &scene_.mesh;
    const auto base = std::uint32_t(g.vertices.size() / kStride);
    g.layers[size_t(layer)] = {int(g.indices.size()), int(3 * m->triangles.size())};
    // A building's vertices are its own (LOD1 meshes are appended per footprint).
    std::vector<std::uint32_t> vertexTag(m->positions.size(), 0);
    if (isBuildings && !m->triangleTags.empty())
      for (size_t t = 0; t < m->triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) vertexTag[m->triangles[t][k]] = m->triangleTags[t];
    for (size_t v = 0; v < m->positions.size(); ++v) {
      // The render frame keeps coordinates small for floats (docs/conventions.md).
      const glm::dvec3 r = m->positions[v] - scene_.origin;
      glm::vec2 valid = always;
      // Terrain 0, a building its index + 1, the "mesh" kMeshSurfaceId: the shading pass drapes
      // the orthophoto on the terrain only.
      float building = isMesh ? float(kMeshSurfaceId) : 0.0f;
      if (isBuildings) {
        const std::uint32_t tag = vertexTag[v];
        if (tag < scene_.buildingValidity.size()) valid = ibr::gpuDays(scene_.buildingValidity[tag]);
        building = float(tag + 1);
      }
      g.vertices.insert(g.vertices.end(), {float(r.x), float(r.y), float(r.z), valid.x, valid.y, building});
    }
    renderPositions.resize(m->positions.size());
    for (size_t v = 0; v < m->positions.size(); ++v) renderPositions[v] = m->positions[v] - scene_.origin;
    // Buildings keep each footprint's triangles in one tile; terrain and meshes go by triangle.
    static const std::vector<std::uint32_t> kNoTags;
    appendTiledLayer(layer, renderPositions, m->triangles, isBuildings ? m->triangleTags : kNoTags, base, grid,
                     g.indices, g.tiles, isBuildings ? scene_.tileOfBuilding : kNoTags);
    bounds_.extend(m->bounds());
  }
  // The load-time cut's box stands for the streamed terrain's (finer tiles stay within about the
  // tolerance of it; its skirts reach below).
  if (scene_.terrainTiles) bounds_.extend(scene_.terrain.bounds());
  // Streamed buildings: the tiles' boxes (conservative in height).
  if (scene_.buildingTiles)
    for (const Aabb& b : scene_.buildingTiles->boxes) bounds_.extend(b);
  tiles_ = g.tiles;
  stats_.geometryTiles = int(tiles_.size());
  // Padded so that flat geometry (a single wall, flat ground) still has a volume to sample.
  // One absurd coordinate (an inf vertex, an unflagged no-data cell) never stretches the depth
  // ranges until the picture is black: both boxes stop at the scene's inliers
  // (hv/scene/robust_extent.h).
  inlierBounds_ = robustExtent(scene_).bounds;
  // Streamed buildings are not in the scene's meshes: their tiles' boxes are what the views may
  // see of them.
  if (scene_.buildingTiles)
    for (const Aabb& b : scene_.buildingTiles->boxes) inlierBounds_.extend(b);
  bounds_ = clippedTo(bounds_, inlierBounds_);
  geometryBounds_ = bounds_;
  if (!geometryBounds_.empty()) {
    const glm::dvec3 pad(1e-3 * glm::length(geometryBounds_.size()) + 1e-3);
    geometryBounds_.lo -= pad;
    geometryBounds_.hi += pad;
  }
  for (const auto& p : scene_.photos) bounds_.extend(p.camera.center);
  bounds_ = clippedTo(bounds_, inlierBounds_);

  // Streamed buildings bring their dates with their tiles (streamBuildings).
  const int n = scene_.buildingTiles ? 1 : std::max<int>(1, int(scene_.buildingValidity.size()));
  g.validityWidth = std::min(n, 1024);
  g.validityRows = (n + g.validityWidth - 1) / g.validityWidth;
  g.validity.assign(size_t(g.validityWidth) * g.validityRows * 4, 0.0f);
  for (int i = 0; i < n; ++i) {
    const glm::vec2 d =
        size_t(i) < scene_.buildingValidity.size() ? ibr::gpuDays(scene_.buildingValidity[size_t(i)]) : always;
    g.validity[size_t(i) * 4] = d.x;
    g.validity[size_t(i) * 4 + 1] = d.y;
  }
  backend_.uploadGeometry(g);
}

void FrameBuilder::setOrthophoto(std::shared_ptr<const Orthophoto> orthophoto) {
  static const Orthophoto kNone;
  const Orthophoto& o = orthophoto ? *orthophoto : kNone;
  backend_.uploadOrthophoto(o, o.empty() ? OrthophotoAffine{} : orthophotoAffine(o, scene_.origin));
}

// The filter that applies (PointSettings::filter, which may change between frames).
void FrameBuilder::resolvePointFilter() {
  const PointCloud& cloud = scene_.points;
  const PointSettings& ps = settings_.points;
  PointFilter filter = ps.filter;
  const bool hasClasses = cloud.fields().classification;
  if (filter == PointFilter::Auto) filter = hasClasses ? PointFilter::Classification : PointFilter::Epsilon;
  if (filter == PointFilter::Classification && !hasClasses) {
    if (!warnedPointClasses_) diag_.warn(cloud.sourcePath + ": no classification; filtering points by epsilon instead");
    warnedPointClasses_ = true;
    filter = PointFilter::Epsilon;
  }
  classify_ = filter == PointFilter::Classification;
  epsilonTest_ = filter == PointFilter::Epsilon;
  pointsInDepthMaps_ = classify_ && ps.keptInDepthMaps;
}

// The point buffer (uploaded once, in chunk order, when the points are first enabled), the
// filters that apply and the programs.
void FrameBuilder::initPoints() {
  const PointCloud& cloud = scene_.points;
  const PointSettings& ps = settings_.points;
  if (pointsTried_) return;
  pointsTried_ = true;
  if (cloud.empty()) return;
  if (naive()) {
    diag_.warn("points are drawn only with the texture-array binding; --binding naive leaves them out");
    return;
  }
  if (cloud.chunks.empty()) throw std::runtime_error("point cloud not organised into chunks (hv::organizeChunks)");
  // Deferred normals (hv/scene/point_normals.h) are estimated here, when the points are first drawn.
  const std::vector<glm::vec3>& normals = pointNormals(cloud);
  resolvePointFilter();

  const std::vector<glm::u8vec4> colors = pointDisplayColors(cloud, ps.color);
  std::vector<PointVertex> vertices(cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) {
    const glm::dvec3 r = cloud.positions[i] - scene_.origin;  // render frame (docs/conventions.md)
    const glm::vec3 n = normals.empty() ? glm::vec3(0.0f) : normals[i];
    vertices[i] = {{float(r.x), float(r.y), float(r.z)}, {n.x, n.y, n.z},
                   {colors[i].r, colors[i].g, colors[i].b, colors[i].a}};
  }
  // The 2016 form carries 9 floats per image in varyings: the backend links the largest K up to
  // the requested one that fits (MAX_VARYING_COMPONENTS).
  const int want = std::max(1, std::min(settings_.blend.k, std::max(1, int(scene_.photos.size()))));
  const PointProgramInfo info = backend_.uploadPoints(vertices, {ps.form, want, ps.maxPointSizePx});
  mat3K_ = info.mat3Images;
  if (ps.form == SpriteForm::Mat3) {
    if (mat3K_ < want)
      diag_.warn("mat3 sprites: K = " + std::to_string(want) + " does not link (MAX_VARYING_COMPONENTS = " +
                 std::to_string(limits_.maxVaryingComponents) + ", 9 per image); using K = " +
                 std::to_string(mat3K_) + " for the points");
    stats_.mat3Images = mat3K_;
  }

  // Mean spacing of each chunk's points on the surface they sample: the area of the box's two
  // largest sides over the count (a chunk of lidar covers a patch of ground or facade).
  for (const PointChunk& c : cloud.chunks) {
    glm::dvec3 e = c.bounds.size();
    std::sort(&e[0], &e[0] + 3);
    const double area = std::max(e[1] * e[2], 1e-6);
    chunkSpacing_.push_back(std::sqrt(area / std::max<std::uint32_t>(c.count, 1)));
  }
  const Aabb pb = clippedTo(cloud.bounds(), inlierBounds_);
  bounds_.extend(pb);
  geometryBounds_.extend(pb);
  pointsOn_ = true;
  log::debug("points: " + std::to_string(cloud.size()) + " in " + std::to_string(cloud.chunks.size()) +
             " chunks; filter " + (classify_ ? "classification" : epsilonTest_ ? "epsilon" : "none") +
             (mat3K_ > 0 ? ", mat3 form K = " + std::to_string(mat3K_) : ", N' form"));
}

// Hybrid rendering: how much farther the mesh counts in the photographs' depth maps and in the
// mesh's shadow test; only where points share the depth maps.
double FrameBuilder::meshPushBack() const { return pointsActive() && pointsInDepthMaps_ ? meshOffset() : 0.0; }

double FrameBuilder::meshOffset() const {
  if (settings_.points.meshOffset >= 0.0) return settings_.points.meshOffset;
  return 6e-4 * glm::length(bounds_.size());  // the data's own scale, not fixed metres
}

double FrameBuilder::pointEpsilon() const {
  if (settings_.points.epsilon >= 0.0) return settings_.points.epsilon;
  return 2e-3 * glm::length(bounds_.size());  // the data's own scale, not fixed metres
}

double FrameBuilder::depthBiasAbsolute() const {
  if (settings_.depthBiasAbsolute >= 0.0) return settings_.depthBiasAbsolute;
  return 5e-4 * glm::length(bounds_.size());  // the data's own scale, not fixed metres
}

// The background sphere's radius this frame; 0 when there is none (RenderSettings::backgroundSphere).
double FrameBuilder::sphereRadius() const {
  if (settings_.backgroundSphere > 0.0) return settings_.backgroundSphere;
  if (settings_.backgroundSphere < 0.0 && geometryBounds_.empty()) return kDefaultSphereRadius;
  return 0.0;
}

PointPass FrameBuilder::pointPass(const Camera& cam, bool dropTransient, double depthOffset) const {
  const PointSettings& ps = settings_.points;
  PointPass pass;
  pass.classify = classify_;
  pass.dropTransient = dropTransient;
  pass.depthOffset = depthOffset;
  for (int k : ps.keptClasses)
    if (k >= 0 && k < 256) pass.keptClasses[size_t(k >> 5)] |= 1u << (k & 31);
  for (const ChunkDraw& d : selectChunks(scene_.points, cam, ps.budget)) {
    const PointChunk& chunk = scene_.points.chunks[d.chunk];
    // A prefix of k of the chunk's n points is a uniform subsample: spacing grows by sqrt(n / k).
    const double r = ps.radius > 0.0 ? ps.radius
                                     : ps.radiusScale * chunkSpacing_[d.chunk] *
                                           std::sqrt(double(chunk.count) / std::max<std::uint32_t>(d.count, 1));
    pass.draws.push_back({chunk.first, d.count, float(r)});
    pass.points += d.count;
  }
  return pass;
}

// The frusta of every photograph (frustumOutline, truncated at the frustum depth), a range per
// photograph; rebuilt when the depth or the lens setting changes.
const FrustumLines& FrameBuilder::frustumLines() {
  const double depth = settings_.debug.frustumDepth > 0.0 ? settings_.debug.frustumDepth : scene_.cameraSpacing();
  if (frustumLines_.version > 0 && depth == frustumDepthBuilt_ && settings_.layers.lensDistortion == frustumLensBuilt_)
    return frustumLines_;
  frustumLines_.xyz.clear();
  frustumLines_.perPhoto.clear();
  for (size_t i = 0; i < scene_.photos.size(); ++i) {
    const Camera cam = photoCamera(int(i));
    // A distorted border is curved: 8 segments per side follow it well at debug-view sizes.
    const bool curved = cam.distortion && !cam.distortion->isIdentity();
    const std::vector<glm::dvec3> lines = frustumLineSegments(frustumOutline(cam, depth, curved ? 8 : 1));
    frustumLines_.perPhoto.push_back({int(frustumLines_.xyz.size() / 3), int(lines.size())});
    for (const glm::dvec3& p : lines) {
      const glm::dvec3 r = p - scene_.origin;  // render frame (docs/conventions.md)
      frustumLines_.xyz.insert(frustumLines_.xyz.end(), {float(r.x), float(r.y), float(r.z)});
    }
  }
  ++frustumLines_.version;
  frustumDepthBuilt_ = depth;
  frustumLensBuilt_ = settings_.layers.lensDistortion;
  return frustumLines_;
}

}  // namespace hv::render
