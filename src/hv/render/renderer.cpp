#include "hv/render/renderer.h"

#include "hv/camera/frustum_outline.h"
#include "hv/gpu/gl.h"
#include "hv/ibr/depth_scheduler.h"
#include "hv/ibr/image_loader.h"
#include "hv/ibr/slot_cache.h"
#include "hv/ibr/sprite_homography.h"
#include "hv/points/chunks.h"
#include "hv/scene/robust_extent.h"
#include "hv/ibr/slice_image.h"
#include "hv/ibr/tile_culling.h"
#include "hv/image/colormap.h"
#include "hv/util/log.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

namespace hv::render {

using gpu::checkGlError;

namespace {

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
  kUnitPointParams = 9
};

void setNearestClamp(GLenum target) {
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

// An RGBA8 texture of w x h with nearest filtering: the view's colour, building-id and tile-range
// targets.
gpu::Texture makeRgba8Target(int w, int h) {
  gpu::Texture t = gpu::makeTexture();
  glBindTexture(GL_TEXTURE_2D, t.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  setNearestClamp(GL_TEXTURE_2D);
  return t;
}

// Binds `id` to texture unit `unit` and leaves unit 0 active (where uploads bind their textures).
void bindUnit(int unit, GLenum target, GLuint id) {
  glActiveTexture(GLenum(GL_TEXTURE0 + unit));
  glBindTexture(target, id);
  glActiveTexture(GL_TEXTURE0);
}

void uploadMat4(GLint loc, const glm::dmat4& m) {
  float f[16];
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) f[4 * c + r] = float(m[c][r]);
  glUniformMatrix4fv(loc, 1, GL_FALSE, f);
}

void uploadMat3(GLint loc, const glm::dmat3& m) {
  float f[9];
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) f[3 * c + r] = float(m[c][r]);
  glUniformMatrix3fv(loc, 1, GL_FALSE, f);
}

enum ProgramIndex { kProgramDepth, kProgramViewDepth, kProgramShade, kProgramTileDepth, kProgramNaive,
                    kProgramPointDepth, kProgramPointColor };
// The debug programs, at the end of programSources() (after the mat3 sprite form).
enum DebugProgramIndex { kProgramDebugDepth = 8, kProgramLines = 9 };

// Shading-pass modes (u_mode in shaders/ibr_shade.frag).
enum ShadeMode : GLint {
  kShadeColour = 0,
  kShadeCount = 1,
  kShadeLoopLength = 2,
  kShadeShare = 3,
  kShadeCountColour = 4,
  kShadeShareColour = 5
};

// The geometry layers, in the order uploadGeometry appends them to the one index buffer.
enum Layer { kLayerTerrain, kLayerBuildings, kLayerMesh, kLayerCount };

// Index range of one layer in the index buffer.
struct DrawRange {
  GLsizei first = 0, count = 0;
};

// What the photographs' depth maps are drawn from besides the scene itself. When it changes
// between frames every depth map is redrawn (issue 6's live toggles).
struct DepthMapInputs {
  std::array<bool, kLayerCount> layers{true, true, true};
  bool lensDistortion = true;  // the frusta: the ideal rectangle covering the distorted image, or W x H
  // Point sprites in the depth maps (the classification filter) and what decides which are drawn.
  bool points = false;
  std::uint64_t pointBudget = 0;
  double pointRadius = 0.0, pointRadiusScale = 0.0;
  std::vector<int> keptClasses;
  double meshPushBack = 0.0;  // the mesh pushed back behind the points (hybrid mesh offset)
  bool operator==(const DepthMapInputs&) const = default;
};

// Frustum colours (RGBA) of the DebugSettings::frusta overlay; hidden parts are drawn at
// kHiddenLineAlpha of these.
constexpr float kFrustumOther[4] = {0.8f, 0.8f, 0.8f, 0.9f};
constexpr float kFrustumInFrame[4] = {1.0f, 0.85f, 0.15f, 1.0f};
constexpr float kFrustumDebug[4] = {0.2f, 0.95f, 1.0f, 1.0f};
constexpr float kHiddenLineAlpha = 0.3f;

// Per point in the GPU buffer: render-frame position, normal (0 when none), colour + class.
struct PointVertex {
  float position[3];
  float normal[3];
  std::uint8_t color[4];
};
static_assert(sizeof(PointVertex) == 28);

// `box` limited to `limit` (unchanged when either is empty or they do not meet).
Aabb clippedTo(const Aabb& box, const Aabb& limit) {
  if (box.empty() || limit.empty()) return box;
  Aabb c;
  c.lo = glm::max(box.lo, limit.lo);
  c.hi = glm::min(box.hi, limit.hi);
  return c.empty() ? box : c;
}

}  // namespace

const std::vector<ProgramSource>& programSources() {
  static const std::vector<ProgramSource> list = {
      {"depth.vert", "depth.frag", {}},                        // photographs' depth maps
      {"depth.vert", "depth.frag", {"HV_WRITE_BUILDING"}},     // the view's depth and building ids
      {"fullscreen.vert", "ibr_shade.frag", {}},               // the blend
      {"fullscreen.vert", "tile_depth.frag", {}},              // tile depth ranges for culling
      // The naive baseline; the renderer links it with its own count, this entry with one that any
      // ES 3.0 context has units for (16 units: 6 for the pass, 2 per image).
      {"fullscreen.vert", "ibr_shade.frag", {"HV_NAIVE", "HV_NAIVE_COUNT=5"}},
      {"points.vert", "points.frag", {"HV_DEPTH_ONLY"}},   // point sprites into depth maps and the view
      {"points.vert", "points.frag", {}},                  // textured sprites, 2022 form (N')
      {"points.vert", "points.frag", {"HV_MAT3_K=4"}},     // the 2016 form (the renderer picks K)
      {"fullscreen.vert", "debug_depth.frag", {}},         // DebugView::DepthMap
      {"lines.vert", "lines.frag", {}},                    // DebugSettings::frusta
  };
  return list;
}

struct Renderer::Impl {
  const Scene& scene;
  RenderSettings settings;
  Diagnostics& diag;
  gpu::GlLimits limits;
  ibr::CameraIndex index;

  gpu::Program depthProgram, viewDepthProgram, shadeProgram, tileDepthProgram;
  gpu::Texture validityTexture, viewBuilding;
  int validityWidth = 1;
  gpu::VertexArray meshVao, emptyVao;
  gpu::Buffer vertexBuffer, indexBuffer;
  GLsizei indexCount = 0;
  std::array<DrawRange, kLayerCount> layerRange;
  // What the current depth maps were drawn from, and whether the loader applies masks: compared
  // with the settings at the start of each frame (applyLiveSettings).
  DepthMapInputs depthInputs;
  bool loaderMasks = true;
  Aabb bounds;          // geometry and camera centres: depth ranges
  Aabb geometryBounds;  // geometry only: the frustum filter
  Aabb inlierBounds;    // robustExtent (hv/scene/robust_extent.h): what the two boxes above may cover

  // Slots: slice i of both arrays holds cache.photoIn(i).
  ibr::SliceSize sliceSize;
  int depthSize = 0;
  int slotCount = 0;
  gpu::Texture imageArray, depthArray, paramsTexture;
  // The naive binding: one 2D texture per slot for the photograph and one for its depth map, and
  // the texture units they are bound to (those the shading pass leaves free).
  std::vector<gpu::Texture> naiveImages, naiveDepths;
  std::vector<GLint> naiveUnits;
  int paramsRows = 0;
  ibr::SlotCache cache;
  std::unique_ptr<ibr::ImageLoader> loader;
  ibr::DepthMapScheduler depthScheduler;
  std::vector<ibr::PinholeFrustum> slotFrustum;
  std::vector<bool> photoBroken;
  std::uint64_t frame = 0;
  gpu::Framebuffer depthFbo, viewFbo;
  gpu::Texture viewDepth, viewColor, lookupTexture, tileRange, tileLists;
  glm::ivec2 tileRangeSize{0};
  bool cullingThisFrame = false;
  int tilesX = 0;
  glm::ivec2 viewDepthSize{0}, viewColorSize{0};

  ibr::FramePlan plan;
  std::vector<ibr::ImageParams> params;
  RenderStats stats;

  // The point pass (issue 4).
  bool pointsOn = false;        // the scene's points are uploaded (array binding; pointsActive: and enabled)
  bool classify = false;        // the classification filter applies
  bool epsilonTest = false;     // the epsilon filter applies
  bool pointsInDepthMaps = false;
  int mat3K = 0;                // > 0: the 2016 form with this many images
  float maxPointSize = 1.0f;
  gpu::Program pointDepthProgram, pointColorProgram;
  gpu::VertexArray pointVao;
  gpu::Buffer pointBuffer;
  std::vector<double> chunkSpacing;  // mean point spacing of each chunk, scene units
  gpu::Texture pointColor, pointParamsTexture;
  glm::ivec2 pointColorSize{0};
  int pointParamsRows = 0;
  bool pointsThisFrame = false;
  bool warnedMat3 = false;
  bool pointsTried = false;        // initPoints ran (points are uploaded on first use)
  bool warnedPointClasses = false;

  // Debug views and overlays (issue 6), linked on first use.
  gpu::Program debugDepthProgram, linesProgram;
  gpu::VertexArray frustumVao;
  gpu::Buffer frustumBuffer;
  std::vector<DrawRange> frustumRange;  // per photograph, in frustumBuffer's vertices
  double frustumDepthBuilt = -1.0;
  bool frustumLensBuilt = true;
  bool warnedDebugNaive = false;
  bool debugWaiting = false;  // the depth-map view's photograph is still being decoded

  Impl(const Scene& s, RenderSettings st, Diagnostics& d) : scene(s), settings(st), diag(d), index(centers(s)) {}

  static std::vector<glm::dvec3> centers(const Scene& s) {
    std::vector<glm::dvec3> c;
    for (const auto& p : s.photos) c.push_back(p.camera.center);
    return c;
  }

  void init() {
    limits = gpu::queryLimits();
    const auto& src = programSources();
    auto link = [&](int i) { return gpu::Program(src[size_t(i)].vertex, src[size_t(i)].fragment, src[size_t(i)].defines); };
    depthProgram = link(kProgramDepth);
    viewDepthProgram = link(kProgramViewDepth);
    shadeProgram = link(kProgramShade);  // replaced below for the naive binding
    tileDepthProgram = link(kProgramTileDepth);
    uploadGeometry();
    if (settings.points.enabled) initPoints();
    allocateSlots();
    if (naive()) {
      const auto& sh = src[kProgramShade];
      shadeProgram = gpu::Program(sh.vertex, sh.fragment, {"HV_NAIVE", "HV_NAIVE_COUNT=" + std::to_string(slotCount)});
    }
    depthFbo = gpu::makeFramebuffer();
    viewFbo = gpu::makeFramebuffer();
    emptyVao = gpu::makeVertexArray();
    photoBroken.assign(scene.photos.size(), false);
    depthInputs = depthMapInputs();
    checkGlError("renderer initialisation");
  }

  void uploadGeometry() {
    // Per vertex: render-frame position (3), the days its surface existed (2), building index + 1.
    constexpr int kStride = 6;
    std::vector<float> vertices;
    std::vector<std::uint32_t> indices;
    const glm::vec2 always = ibr::gpuDays(DateInterval{});
    const std::array<const Mesh*, kLayerCount> layers = {&scene.terrain, &scene.buildings, &scene.mesh};
    for (int layer = 0; layer < kLayerCount; ++layer) {
      const Mesh* m = layers[size_t(layer)];
      const bool isBuildings = m == &scene.buildings;
      const auto base = std::uint32_t(vertices.size() / kStride);
      layerRange[size_t(layer)] = {GLsizei(indices.size()), GLsizei(3 * m->triangles.size())};
      // A building's vertices are its own (LOD1 meshes are appended per footprint).
      std::vector<std::uint32_t> vertexTag(m->positions.size(), 0);
      if (isBuildings && !m->triangleTags.empty())
        for (size_t t = 0; t < m->triangles.size(); ++t)
          for (int k = 0; k < 3; ++k) vertexTag[m->triangles[t][k]] = m->triangleTags[t];
      for (size_t v = 0; v < m->positions.size(); ++v) {
        const glm::dvec3 r = m->positions[v] - scene.origin;  // render frame: small floats (DESIGN.md §1)
        glm::vec2 valid = always;
        float building = 0.0f;
        if (isBuildings) {
          const std::uint32_t tag = vertexTag[v];
          if (tag < scene.buildingValidity.size()) valid = ibr::gpuDays(scene.buildingValidity[tag]);
          building = float(tag + 1);
        }
        vertices.insert(vertices.end(), {float(r.x), float(r.y), float(r.z), valid.x, valid.y, building});
      }
      for (const auto& t : m->triangles) indices.insert(indices.end(), {t.x + base, t.y + base, t.z + base});
      bounds.extend(m->bounds());
    }
    // One absurd coordinate (an inf vertex, an unflagged no-data cell) never stretches the depth
    // ranges until the picture is black: both boxes stop at the scene's inliers
    // (hv/scene/robust_extent.h).
    inlierBounds = robustExtent(scene).bounds;
    bounds = clippedTo(bounds, inlierBounds);
    // Padded so that flat geometry (a single wall, flat ground) still has a volume to sample.
    geometryBounds = bounds;
    if (!geometryBounds.empty()) {
      const glm::dvec3 pad(1e-3 * glm::length(geometryBounds.size()) + 1e-3);
      geometryBounds.lo -= pad;
      geometryBounds.hi += pad;
    }
    for (const auto& p : scene.photos) bounds.extend(p.camera.center);
    bounds = clippedTo(bounds, inlierBounds);
    indexCount = GLsizei(indices.size());
    meshVao = gpu::makeVertexArray();
    vertexBuffer = gpu::makeBuffer();
    indexBuffer = gpu::makeBuffer();
    glBindVertexArray(meshVao.id());
    glBindBuffer(GL_ARRAY_BUFFER, vertexBuffer.id());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(), GL_STATIC_DRAW);
    const GLsizei stride = kStride * sizeof(float);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(5 * sizeof(float)));
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer.id());
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(),
                 GL_STATIC_DRAW);
    glBindVertexArray(0);

    // Building validity, one texel per building index, rows of validityWidth.
    const int n = std::max<int>(1, int(scene.buildingValidity.size()));
    validityWidth = std::min(n, 1024);
    const int rows = (n + validityWidth - 1) / validityWidth;
    std::vector<float> validity(size_t(validityWidth) * rows * 4, 0.0f);
    for (int i = 0; i < n; ++i) {
      const glm::vec2 d =
          size_t(i) < scene.buildingValidity.size() ? ibr::gpuDays(scene.buildingValidity[size_t(i)]) : always;
      validity[size_t(i) * 4] = d.x;
      validity[size_t(i) * 4 + 1] = d.y;
    }
    validityTexture = gpu::makeTexture();
    glBindTexture(GL_TEXTURE_2D, validityTexture.id());
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, validityWidth, rows, 0, GL_RGBA, GL_FLOAT, validity.data());
    setNearestClamp(GL_TEXTURE_2D);
    checkGlError("geometry upload");
  }

  bool naive() const { return settings.binding == Binding::Naive; }

  // The points are drawn this frame: uploaded (initPoints) and enabled in the settings.
  bool pointsActive() const { return pointsOn && settings.points.enabled; }

  // The filter that applies (PointSettings::filter, which may change between frames).
  void resolvePointFilter() {
    const PointCloud& cloud = scene.points;
    const PointSettings& ps = settings.points;
    const PointFields fields = cloud.fields();
    PointFilter filter = ps.filter;
    if (filter == PointFilter::Auto) filter = fields.classification ? PointFilter::Classification : PointFilter::Epsilon;
    if (filter == PointFilter::Classification && !fields.classification) {
      if (!warnedPointClasses) diag.warn(cloud.sourcePath + ": no classification; filtering points by epsilon instead");
      warnedPointClasses = true;
      filter = PointFilter::Epsilon;
    }
    classify = filter == PointFilter::Classification;
    epsilonTest = filter == PointFilter::Epsilon;
    pointsInDepthMaps = classify && ps.keptInDepthMaps;
  }

  // The point buffer (uploaded once, in chunk order, when the points are first enabled), the
  // filters that apply and the programs.
  void initPoints() {
    const PointCloud& cloud = scene.points;
    const PointSettings& ps = settings.points;
    if (pointsTried) return;
    pointsTried = true;
    if (cloud.empty()) return;
    if (naive()) {
      diag.warn("points are drawn only with the texture-array binding; --binding naive leaves them out");
      return;
    }
    if (cloud.chunks.empty()) throw std::runtime_error("point cloud not organised into chunks (hv::organizeChunks)");
    const PointFields fields = cloud.fields();
    resolvePointFilter();

    const std::vector<glm::u8vec4> colors = pointDisplayColors(cloud, ps.color);
    std::vector<PointVertex> vertices(cloud.size());
    for (size_t i = 0; i < cloud.size(); ++i) {
      const glm::dvec3 r = cloud.positions[i] - scene.origin;  // render frame (DESIGN.md §1)
      const glm::vec3 n = fields.normals ? cloud.normals[i] : glm::vec3(0.0f);
      vertices[i] = {{float(r.x), float(r.y), float(r.z)}, {n.x, n.y, n.z},
                     {colors[i].r, colors[i].g, colors[i].b, colors[i].a}};
    }
    pointVao = gpu::makeVertexArray();
    pointBuffer = gpu::makeBuffer();
    glBindVertexArray(pointVao.id());
    glBindBuffer(GL_ARRAY_BUFFER, pointBuffer.id());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(PointVertex)), vertices.data(), GL_STATIC_DRAW);
    const GLsizei stride = sizeof(PointVertex);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(PointVertex, normal)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, stride,
                          reinterpret_cast<const void*>(offsetof(PointVertex, color)));
    glBindVertexArray(0);
    checkGlError("point upload");

    // Mean spacing of each chunk's points on the surface they sample: the area of the box's two
    // largest sides over the count (a chunk of lidar covers a patch of ground or facade).
    for (const PointChunk& c : cloud.chunks) {
      glm::dvec3 e = c.bounds.size();
      std::sort(&e[0], &e[0] + 3);
      const double area = std::max(e[1] * e[2], 1e-6);
      chunkSpacing.push_back(std::sqrt(area / std::max<std::uint32_t>(c.count, 1)));
    }
    const Aabb pb = clippedTo(cloud.bounds(), inlierBounds);
    bounds.extend(pb);
    geometryBounds.extend(pb);

    GLfloat range[2] = {1.0f, 1.0f};
    glGetFloatv(GL_ALIASED_POINT_SIZE_RANGE, range);
    maxPointSize = float(std::max(1.0, std::min<double>(range[1], ps.maxPointSizePx)));
    const auto& src = programSources();
    pointDepthProgram = gpu::Program(src[kProgramPointDepth].vertex, src[kProgramPointDepth].fragment,
                                     src[kProgramPointDepth].defines);
    if (ps.form == SpriteForm::Mat3) {
      // The 2016 form carries 9 floats per image in varyings: link the largest K up to the
      // requested one that fits (MAX_VARYING_COMPONENTS).
      const int want = std::max(1, std::min(settings.blend.k, std::max(1, int(scene.photos.size()))));
      // Linking far beyond the limit can crash a driver's compiler (llvmpipe does at K = 40)
      // instead of failing: start from what the limit allows, 9 components per image.
      const int start = std::max(1, std::min(want, limits.maxVaryingComponents / 9));
      for (int k = start; k >= 1 && mat3K == 0; --k) {
        try {
          pointColorProgram = gpu::Program("points.vert", "points.frag", {"HV_MAT3_K=" + std::to_string(k)});
          mat3K = k;
        } catch (const std::runtime_error&) {
        }
      }
      if (mat3K == 0) throw std::runtime_error("the mat3 sprite program links with no image at all");
      if (mat3K < want)
        diag.warn("mat3 sprites: K = " + std::to_string(want) + " does not link (MAX_VARYING_COMPONENTS = " +
                  std::to_string(limits.maxVaryingComponents) + ", 9 per image); using K = " + std::to_string(mat3K) +
                  " for the points");
      stats.mat3Images = mat3K;
    } else {
      pointColorProgram = gpu::Program(src[kProgramPointColor].vertex, src[kProgramPointColor].fragment,
                                       src[kProgramPointColor].defines);
    }
    pointsOn = true;
    log::debug("points: " + std::to_string(cloud.size()) + " in " + std::to_string(cloud.chunks.size()) +
               " chunks; filter " + (classify ? "classification" : epsilonTest ? "epsilon" : "none") +
               (mat3K > 0 ? ", mat3 form K = " + std::to_string(mat3K) : ", N' form"));
  }

  // Hybrid rendering: how much farther the mesh counts in the photographs' depth maps (depth.frag)
  // and in the mesh's shadow test (ibr_shade.frag); only where points share the depth maps.
  double meshPushBack() const { return pointsActive() && pointsInDepthMaps ? meshOffset() : 0.0; }

  double meshOffset() const {
    if (settings.points.meshOffset >= 0.0) return settings.points.meshOffset;
    return 6e-4 * glm::length(bounds.size());  // the data's own scale (DESIGN.md §1)
  }

  double pointEpsilon() const {
    if (settings.points.epsilon >= 0.0) return settings.points.epsilon;
    return 2e-3 * glm::length(bounds.size());  // the data's own scale (DESIGN.md §1)
  }

  // Draws the sprites a camera sees (selectChunks within the budget) with `program` into a target
  // of `size` texels covering `fr`. The caller sets the depth state and the program's own uniforms.
  std::uint64_t drawPoints(const gpu::Program& program, const Camera& cam, const ibr::PinholeFrustum& fr,
                           glm::ivec2 size, bool dropTransient, double depthOffset) {
    const PointSettings& ps = settings.points;
    const glm::dmat3 M = ibr::targetCameraMatrix(cam, fr, size);
    const glm::dmat3 Minv = glm::inverse(M);
    const glm::dvec3 c = cam.center - scene.origin;
    program.use();
    uploadMat3(program.uniform("u_M"), M);
    uploadMat3(program.uniform("u_MinvT"), glm::transpose(Minv));
    uploadMat3(program.uniform("u_Minv"), Minv);
    glUniform3f(program.uniform("u_C"), float(c.x), float(c.y), float(c.z));
    glUniform2f(program.uniform("u_targetSize"), float(size.x), float(size.y));
    glUniform1f(program.uniform("u_near"), float(fr.near));
    glUniform1f(program.uniform("u_far"), float(fr.far));
    glUniform1f(program.uniform("u_maxPointSize"), maxPointSize);
    glUniform1f(program.uniform("u_depthOffset"), float(depthOffset));
    glUniform1i(program.uniform("u_classify"), classify ? 1 : 0);
    glUniform1i(program.uniform("u_dropTransient"), dropTransient ? 1 : 0);
    GLuint mask[8] = {0, 0, 0, 0, 0, 0, 0, 0};
    for (int k : ps.keptClasses)
      if (k >= 0 && k < 256) mask[k >> 5] |= 1u << (k & 31);
    glUniform1uiv(program.uniform("u_keptClasses"), 8, mask);
    const GLint radiusLoc = program.uniform("u_radius");
    std::uint64_t drawn = 0;
    glBindVertexArray(pointVao.id());
    for (const ChunkDraw& d : selectChunks(scene.points, cam, ps.budget)) {
      const PointChunk& chunk = scene.points.chunks[d.chunk];
      // A prefix of k of the chunk's n points is a uniform subsample: spacing grows by sqrt(n / k).
      const double r = ps.radius > 0.0 ? ps.radius
                                       : ps.radiusScale * chunkSpacing[d.chunk] *
                                             std::sqrt(double(chunk.count) / std::max<std::uint32_t>(d.count, 1));
      glUniform1f(radiusLoc, float(r));
      glDrawArrays(GL_POINTS, GLint(chunk.first), GLsizei(d.count));
      drawn += d.count;
    }
    glBindVertexArray(0);
    return drawn;
  }

  // H'_i and E_i of every image of the frame for the view's target (2022 §2.3): 3 texels per image.
  void uploadPointParams(const glm::dmat3& viewM, const glm::dvec3& viewC) {
    const int rows = std::max<int>(1, int(params.size()));
    if (!pointParamsTexture || rows > pointParamsRows) {
      pointParamsRows = std::max(rows, 64);
      pointParamsTexture = gpu::makeTexture();
      glBindTexture(GL_TEXTURE_2D, pointParamsTexture.id());
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 3, pointParamsRows, 0, GL_RGBA, GL_FLOAT, nullptr);
      setNearestClamp(GL_TEXTURE_2D);
    }
    std::vector<float> packed;
    for (const ibr::ImageParams& im : params) {
      const ibr::SpriteImage si = ibr::spriteImage(viewM, viewC, im.pixFromWorld, im.centerRender);
      for (int r = 0; r < 3; ++r)
        packed.insert(packed.end(), {float(si.hPrime[0][r]), float(si.hPrime[1][r]), float(si.hPrime[2][r]),
                                     float(si.e[r])});
    }
    if (!params.empty()) {
      glBindTexture(GL_TEXTURE_2D, pointParamsTexture.id());
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 3, GLsizei(params.size()), GL_RGBA, GL_FLOAT, packed.data());
    }
  }

  // The view's point passes, after the mesh's depth pass, in the view-depth target (the ideal
  // rectangle covering the view, so distorted views resample it as they do the mesh's depth):
  // sprites' depths into the view depth (depth test against the mesh), then the winners'
  // colours into pointColor. Leaves viewFbo bound.
  void renderViewPoints(const Camera& view, const ibr::PinholeFrustum& vf, glm::ivec2 depthSz,
                        const ibr::BlendSettings& blend) {
    const PointSettings& ps = settings.points;
    const GLenum none = GL_NONE, color0 = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &none);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    stats.pointsDrawn = drawPoints(pointDepthProgram, view, vf, depthSz, ps.hideTransient, meshOffset());
    glDisable(GL_DEPTH_TEST);

    if (depthSz != pointColorSize) {
      pointColor = makeRgba8Target(depthSz.x, depthSz.y);
      pointColorSize = depthSz;
    }
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, 0, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, pointColor.id(), 0);
    glDrawBuffers(1, &color0);
    gpu::checkFramebuffer("point colour");
    const GLfloat clear[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, clear);
    const glm::dmat3 M = ibr::targetCameraMatrix(view, vf, depthSz);
    uploadPointParams(M, view.center - scene.origin);
    const gpu::Program& p = pointColorProgram;
    p.use();
    bindUnit(kUnitImages, GL_TEXTURE_2D_ARRAY, imageArray.id());
    bindUnit(kUnitDepthMaps, GL_TEXTURE_2D_ARRAY, depthArray.id());
    bindUnit(kUnitParams, GL_TEXTURE_2D, paramsTexture.id());
    bindUnit(kUnitViewDepth, GL_TEXTURE_2D, viewDepth.id());
    bindUnit(kUnitPointParams, GL_TEXTURE_2D, pointParamsTexture.id());
    glUniform1i(p.uniform("u_images"), kUnitImages);
    glUniform1i(p.uniform("u_depthMaps"), kUnitDepthMaps);
    glUniform1i(p.uniform("u_params"), kUnitParams);
    glUniform1i(p.uniform("u_viewDepth"), kUnitViewDepth);
    glUniform1i(p.uniform("u_pointParams"), kUnitPointParams);
    int n = int(params.size());
    if (mat3K > 0 && n > mat3K) {
      if (!warnedMat3)
        diag.warn("mat3 sprites carry " + std::to_string(mat3K) + " images; the points blend the " +
                  std::to_string(mat3K) + " nearest of " + std::to_string(n));
      warnedMat3 = true;
    }
    glUniform1i(p.uniform("u_imageCount"), n);
    glUniform1i(p.uniform("u_method"), blend.method == ibr::BlendMethod::Nearest ? 1 : 0);
    glUniform1i(p.uniform("u_occlusion"), blend.occlusion ? 1 : 0);
    glUniform1i(p.uniform("u_epsilonTest"), epsilonTest ? 1 : 0);
    glUniform1f(p.uniform("u_epsilon"), float(pointEpsilon()));
    glUniform1i(p.uniform("u_eyeDome"), ps.eyeDome ? 1 : 0);
    glUniform1f(p.uniform("u_edlStrength"), float(ps.eyeDomeStrength));
    glUniform1f(p.uniform("u_edlRadius"), float(ps.eyeDomeRadiusPx));
    // Both passes compute the same float expression; the tolerance only absorbs compilers that
    // evaluate it differently in the two programs (1e-6 of the depth range).
    glUniform1f(p.uniform("u_depthTolerance"), 1e-6f);
    drawPoints(p, view, vf, depthSz, ps.hideTransient, meshOffset());
    checkGlError("point passes");
  }

  void allocateSlots() {
    int w = 1, h = 1;
    for (const auto& p : scene.photos) {
      w = std::max(w, p.camera.width);
      h = std::max(h, p.camera.height);
    }
    const int cap = std::min(settings.maxSliceSize, limits.maxTextureSize);
    if (w > cap || h > cap) {
      const double s = std::min(double(cap) / w, double(cap) / h);
      w = std::max(1, int(std::floor(w * s)));
      h = std::max(1, int(std::floor(h * s)));
    }
    sliceSize = {w, h};
    depthSize = std::clamp(settings.depthSize, 16, limits.maxTextureSize);
    if (depthSize != settings.depthSize)
      diag.warn("depth-map size " + std::to_string(settings.depthSize) + " exceeds MAX_TEXTURE_SIZE; using " +
                std::to_string(depthSize));
    const std::size_t perSlot = std::size_t(w) * h * 4 + std::size_t(depthSize) * depthSize * 4;
    const int byMemory = int(std::max<std::size_t>(1, settings.memoryBudgetBytes / perSlot));
    slotCount = std::min({settings.maxSlices, limits.maxArrayTextureLayers, byMemory,
                          std::max(1, int(scene.photos.size()))});
    slotCount = std::max(slotCount, 1);
    if (naive()) {
      // Two units per image, among those the shading pass does not use itself (kUnit* 2..7);
      // the shader's chain has 16 entries at most.
      for (GLint u = 0; u < limits.maxTextureImageUnits; ++u)
        if (u < kUnitParams || u > kUnitValidity) naiveUnits.push_back(u);
      slotCount = std::min(slotCount, std::min(16, int(naiveUnits.size()) / 2));
    }
    cache = ibr::SlotCache(slotCount);
    stats.sliceBytes = perSlot * size_t(slotCount);
    loader = std::make_unique<ibr::ImageLoader>(sliceSize, std::max(0, settings.decodeThreads),
                                                settings.decodeMemoryBytes, settings.blend.masks);
    loaderMasks = settings.blend.masks;
    depthScheduler.resize(slotCount);
    slotFrustum.assign(size_t(slotCount), {});

    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    if (naive()) {
      for (int i = 0; i < slotCount; ++i) {
        naiveImages.push_back(gpu::makeTexture());
        glBindTexture(GL_TEXTURE_2D, naiveImages.back().id());
        glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
        naiveDepths.push_back(gpu::makeTexture());
        glBindTexture(GL_TEXTURE_2D, naiveDepths.back().id());
        glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, depthSize, depthSize, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                     nullptr);
        setNearestClamp(GL_TEXTURE_2D);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
      }
      checkGlError("naive slices");
      return;
    }
    imageArray = gpu::makeTexture();
    glBindTexture(GL_TEXTURE_2D_ARRAY, imageArray.id());
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, w, h, slotCount, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    depthArray = gpu::makeTexture();
    glBindTexture(GL_TEXTURE_2D_ARRAY, depthArray.id());
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_DEPTH_COMPONENT32F, depthSize, depthSize, slotCount, 0,
                 GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    setNearestClamp(GL_TEXTURE_2D_ARRAY);  // float depth is not filterable in ES 3.0
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_MODE, GL_NONE);
    checkGlError("slice arrays");
    log::debug("slices: " + std::to_string(slotCount) + " of " + std::to_string(w) + "x" + std::to_string(h) +
               ", depth maps " + std::to_string(depthSize) + "^2");
  }

  // Puts a decoded photograph into a slot (a free one, else the least recently used one that this
  // frame does not need) and marks its depth map dirty. A decoding error marks the photo broken.
  void install(ibr::LoadResult&& r, bool neededNow) {
    const Photo& p = scene.photos[size_t(r.photo)];
    if (!r.ok()) {
      diag.error(r.error + " (camera '" + p.camera.id + "' skipped)");
      photoBroken[size_t(r.photo)] = true;
      return;
    }
    const ibr::SlotCache::Grant grant = cache.acquire(r.photo, neededNow);
    if (!grant || !grant.isNew) return;  // every slot pinned (it will be asked for again), or already there
    depthScheduler.markDirty(grant.slot);
    slotFrustum[size_t(grant.slot)] = depthFrustum(r.photo);
    if (naive()) {
      glBindTexture(GL_TEXTURE_2D, naiveImages[size_t(grant.slot)].id());
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, sliceSize.width, sliceSize.height, GL_RGBA, GL_UNSIGNED_BYTE,
                      r.slice.data.data());
    } else {
      glBindTexture(GL_TEXTURE_2D_ARRAY, imageArray.id());
      glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, grant.slot, sliceSize.width, sliceSize.height, 1, GL_RGBA,
                      GL_UNSIGNED_BYTE, r.slice.data.data());
    }
    checkGlError("image upload");
    ++stats.imagesLoaded;
  }

  // Residency (DESIGN.md §2 step 2): pins the plan's resident photos, asks the loader for the
  // others (nearest first) and installs what it delivers: all of them in batch frames (waiting),
  // what is ready in progressive ones. Returns false when a planned photo turned out broken.
  bool makeResident(FrameMode mode) {
    cache.unpinAll();
    std::vector<int> missing;
    std::vector<ibr::LoadRequest> requests;
    for (const auto& im : plan.images) {
      if (cache.pin(im.photo)) continue;
      missing.push_back(im.photo);
      requests.push_back({im.photo, &scene.photos[size_t(im.photo)], im.distance});
    }
    loader->request(requests);
    auto needed = [&](int photo) { return std::find(missing.begin(), missing.end(), photo) != missing.end(); };
    auto sink = [&](ibr::LoadResult&& r) {
      const int photo = r.photo;
      install(std::move(r), needed(photo));
    };
    if (mode == FrameMode::Batch) {
      loader->wait(missing, sink);
    } else {
      for (auto& r : loader->poll()) sink(std::move(r));
    }
    stats.decodePeakBytes = loader->peakBytes();
    for (int photo : missing)
      if (photoBroken[size_t(photo)]) return false;
    return true;
  }

  void drawDepth(const gpu::Program& program, const glm::dmat4& clip, double near, double far,
                 const DateInterval& date, double pushBack = 0.0, glm::dvec3 centerRender = glm::dvec3(0.0)) {
    program.use();
    glUniform1f(program.uniform("u_pushBack"), float(pushBack));
    glUniform3f(program.uniform("u_center"), float(centerRender.x), float(centerRender.y), float(centerRender.z));
    uploadMat4(program.uniform("u_clipFromRender"), clip);
    glUniform1f(program.uniform("u_near"), float(near));
    glUniform1f(program.uniform("u_far"), float(far));
    const glm::vec2 days = ibr::gpuDays(date);
    glUniform2f(program.uniform("u_date"), days.x, days.y);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glClearDepthf(1.0f);
    glClear(GL_DEPTH_BUFFER_BIT);
    if (indexCount > 0) drawLayers();
    glDisable(GL_DEPTH_TEST);
  }

  // The geometry layers that settings.layers keeps, contiguous ranges in one draw.
  void drawLayers() {
    const std::array<bool, kLayerCount> on = {settings.layers.terrain, settings.layers.buildings, settings.layers.mesh};
    glBindVertexArray(meshVao.id());
    for (int layer = 0; layer < kLayerCount;) {
      if (!on[size_t(layer)]) {
        ++layer;
        continue;
      }
      const GLsizei first = layerRange[size_t(layer)].first;
      GLsizei count = 0;
      for (; layer < kLayerCount && on[size_t(layer)]; ++layer) count += layerRange[size_t(layer)].count;
      if (count > 0)
        glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT,
                       reinterpret_cast<const void*>(std::uintptr_t(first) * sizeof(std::uint32_t)));
    }
    glBindVertexArray(0);
  }

  void renderDepthMap(int slot) {
    const Photo& photo = scene.photos[size_t(cache.photoIn(slot))];
    const Camera cam = photoCamera(cache.photoIn(slot));
    const ibr::PinholeFrustum& fr = slotFrustum[size_t(slot)];
    glBindFramebuffer(GL_FRAMEBUFFER, depthFbo.id());
    if (naive())
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, naiveDepths[size_t(slot)].id(), 0);
    else
      glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, depthArray.id(), 0, slot);
    const GLenum none = GL_NONE;
    glDrawBuffers(1, &none);
    glReadBuffer(GL_NONE);
    gpu::checkFramebuffer("depth map");
    glViewport(0, 0, depthSize, depthSize);
    drawDepth(depthProgram, ibr::clipFromRender(cam, fr, scene.origin), fr.near, fr.far, photoDate(photo),
              meshPushBack(), cam.center - scene.origin);
    if (pointsActive() && pointsInDepthMaps) {
      // Non-transient points refine the occlusion (2016 §4.2, 2022 §2.4); transient ones never occlude.
      glEnable(GL_DEPTH_TEST);
      glDepthFunc(GL_LESS);
      drawPoints(pointDepthProgram, cam, fr, {depthSize, depthSize}, true, 0.0);
      glDisable(GL_DEPTH_TEST);
    }
    depthScheduler.done(slot);
    ++stats.depthMapsRendered;
    ++stats.depthMapsThisFrame;
  }

  void ensureParamsTexture(int rows) {
    if (paramsTexture && rows <= paramsRows) return;
    paramsRows = std::max(rows, 64);
    if (paramsRows > limits.maxTextureSize)
      throw std::runtime_error("more images per pass than MAX_TEXTURE_SIZE rows of parameters");
    paramsTexture = gpu::makeTexture();
    glBindTexture(GL_TEXTURE_2D, paramsTexture.id());
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, ibr::kTexelsPerImage, paramsRows, 0, GL_RGBA, GL_FLOAT, nullptr);
    setNearestClamp(GL_TEXTURE_2D);
  }

  void ensureViewTargets(glm::ivec2 depthSz, glm::ivec2 colorSz) {
    if (depthSz != viewDepthSize) {
      viewDepth = gpu::makeTexture();
      glBindTexture(GL_TEXTURE_2D, viewDepth.id());
      glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, depthSz.x, depthSz.y, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
                   nullptr);
      setNearestClamp(GL_TEXTURE_2D);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
      viewBuilding = makeRgba8Target(depthSz.x, depthSz.y);
      viewDepthSize = depthSz;
    }
    if (colorSz != viewColorSize) {
      viewColor = makeRgba8Target(colorSz.x, colorSz.y);
      viewColorSize = colorSz;
    }
    checkGlError("view targets");
  }

  static DateInterval photoDate(const Photo& p) {
    if (p.date.empty()) return {};
    return parseDate(p.date).value_or(DateInterval{});
  }

  double depthBiasAbsolute() const {
    if (settings.depthBiasAbsolute >= 0.0) return settings.depthBiasAbsolute;
    // Derived from the data's own scale (DESIGN.md §1), not fixed metres.
    return 5e-4 * glm::length(bounds.size());
  }

  std::vector<std::string> excludedIds() const {
    std::vector<std::string> ids = settings.blend.exclude;
    for (size_t i = 0; i < photoBroken.size(); ++i)
      if (photoBroken[i]) ids.push_back(scene.photos[i].camera.id);
    return ids;
  }

  ibr::BlendSettings frameBlendSettings() {
    ibr::BlendSettings blend = settings.blend;
    if (blend.k > slotCount) {
      const std::string bound =
          naive() ? "MAX_TEXTURE_IMAGE_UNITS = " + std::to_string(limits.maxTextureImageUnits) +
                        " with the naive binding: two units per image, " +
                        std::to_string(kUnitValidity - kUnitParams + 1) + " for the pass itself"
                  : "MAX_ARRAY_TEXTURE_LAYERS = " + std::to_string(limits.maxArrayTextureLayers) +
                        ", --max-slices and the memory budget";
      diag.warn("K = " + std::to_string(blend.k) + " exceeds the image slots available (" +
                std::to_string(slotCount) + ", bounded by " + bound + "); using K = " + std::to_string(slotCount));
      blend.k = slotCount;
    }
    return blend;
  }

  // Plans the frame and makes every selected image resident (batch) or asks for them
  // (progressive); a photo that fails to load is excluded and the frame planned again, so the
  // blend never counts an image it cannot sample.
  void planAndLoad(const Camera& view, ibr::BlendSettings& blend, FrameMode mode) {
    for (int attempt = 0;; ++attempt) {
      blend.exclude = excludedIds();
      plan = ibr::planFrame(scene, index, view, blend, geometryBounds);
      if (makeResident(mode)) return;
      if (attempt > int(scene.photos.size())) throw std::runtime_error("cannot make the selected images resident");
    }
  }

  void preload(const Camera& view) {
    applyLiveSettings();
    ibr::BlendSettings blend = frameBlendSettings();
    planAndLoad(view, blend, FrameMode::Batch);
  }

  // ---- Live settings (issue 6): what a viewer may change between frames ----

  // The camera photograph `photo` is projected with: its own, or without its lens distortion
  // (LayerSettings::lensDistortion off).
  Camera photoCamera(int photo) const {
    Camera cam = scene.photos[size_t(photo)].camera;
    if (!settings.layers.lensDistortion) cam.distortion.reset();
    return cam;
  }

  // The pinhole frustum of a photograph's depth map: the ideal rectangle covering its image (with
  // a pixel of margin), the depth range of everything that may be drawn into it.
  ibr::PinholeFrustum depthFrustum(int photo) const {
    const Camera cam = photoCamera(photo);
    ibr::PinholeFrustum fr = ibr::idealRectCoveringImage(cam, 1.0);
    ibr::setDepthRange(fr, cam, bounds);
    return fr;
  }

  DepthMapInputs depthMapInputs() const {
    DepthMapInputs in;
    in.layers = {settings.layers.terrain, settings.layers.buildings, settings.layers.mesh};  // as drawLayers
    in.lensDistortion = settings.layers.lensDistortion;
    in.points = pointsActive() && pointsInDepthMaps;
    if (in.points) {
      const PointSettings& ps = settings.points;
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
  void invalidateDepthMaps() {
    for (int slot = 0; slot < slotCount; ++slot)
      if (cache.photoIn(slot) >= 0) slotFrustum[size_t(slot)] = depthFrustum(cache.photoIn(slot));
    depthScheduler.markAllDirty();
  }

  // Masks switched: the slices hold the colour premultiplied by the mask, so every photograph is
  // decoded again (a new loader drops the pending decodes; broken photographs get another try, as
  // their mask may have been what failed).
  void reloadPhotographs() {
    loader.reset();
    loader = std::make_unique<ibr::ImageLoader>(sliceSize, std::max(0, settings.decodeThreads),
                                                settings.decodeMemoryBytes, settings.blend.masks);
    loaderMasks = settings.blend.masks;
    cache.clear();
    photoBroken.assign(scene.photos.size(), false);
    depthScheduler.markAllDirty();
  }

  // Compares the settings with what is resident and drawn, and invalidates what they change.
  void applyLiveSettings() {
    if (settings.blend.masks != loaderMasks) reloadPhotographs();
    if (settings.points.enabled && !pointsTried) {
      initPoints();
      if (pointsOn) invalidateDepthMaps();  // the points extended the bounds: depth ranges change
    }
    if (pointsOn) resolvePointFilter();
    const DepthMapInputs now = depthMapInputs();
    if (now != depthInputs) {
      invalidateDepthMaps();
      depthInputs = now;
    }
  }

  // DebugView::DepthMap shows one photograph's depth map whether or not the frame selects it: it
  // is made resident (batch frames wait for it) and pinned. Returns its slot, -1 when it is not
  // (yet) resident, is broken, or every slot is pinned by the frame.
  int prepareDebugPhoto(FrameMode mode) {
    const int photo = settings.debug.photo;
    if (settings.debug.view != DebugView::DepthMap || photo < 0 || photo >= int(scene.photos.size()) ||
        photoBroken[size_t(photo)])
      return -1;
    if (cache.pin(photo)) return cache.slotOf(photo);
    loader->request(photo, scene.photos[size_t(photo)], 0.0);
    auto sink = [&](ibr::LoadResult&& r) {
      const int p = r.photo;
      install(std::move(r), p == photo);
    };
    if (mode == FrameMode::Batch)
      loader->wait({photo}, sink);
    else
      for (auto& r : loader->poll()) sink(std::move(r));
    return cache.slotOf(photo);
  }

  RenderOutput render(const Camera& view, bool withCounts, FrameMode mode) {
    const auto t0 = std::chrono::steady_clock::now();
    ++frame;
    applyLiveSettings();
    ibr::BlendSettings blend = frameBlendSettings();
    planAndLoad(view, blend, mode);
    const int debugSlot = prepareDebugPhoto(mode);
    // Slots of the planned images; -1 while a progressive frame still waits for the decode.
    std::vector<int> slots;
    std::vector<int> residentSlots;
    std::vector<double> residentPriority;
    for (const auto& im : plan.images) {
      slots.push_back(cache.slotOf(im.photo));
      if (slots.back() < 0) continue;
      residentSlots.push_back(slots.back());
      residentPriority.push_back(im.distance);
    }
    // Depth maps (DESIGN.md §2 step 3): all of them in batch mode, else the nearest Dmax.
    stats.depthMapsThisFrame = 0;
    const int dmax = mode == FrameMode::Batch ? 0 : settings.depthMapsPerFrame;
    const bool budgeted = mode == FrameMode::Progressive && settings.depthBudgetMs > 0.0;
    const auto depthStart = std::chrono::steady_clock::now();
    for (int slot : depthScheduler.next(residentSlots, residentPriority, dmax)) {
      if (budgeted && stats.depthMapsThisFrame > 0 &&
          std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - depthStart).count() >=
              settings.depthBudgetMs)
        break;
      renderDepthMap(slot);
      if (budgeted) glFinish();  // the budget is about GPU time: wait for the map to be drawn
    }
    // The depth-map debug view's photograph, outside the schedule: one map, when it is shown.
    if (debugSlot >= 0 && depthScheduler.isDirty(debugSlot)) renderDepthMap(debugSlot);
    debugWaiting = settings.debug.view == DebugView::DepthMap && debugSlot < 0 && settings.debug.photo >= 0 &&
                   loader->isPending(settings.debug.photo);

    // Per-image parameters (DESIGN.md §2 step 4): one row of the data texture per image. An image
    // whose depth map is not current yet (progressive frames) waits, unless occlusion is off.
    params.clear();
    std::vector<float> packed;
    const double biasAbs = depthBiasAbsolute();
    stats.imagesWaiting = stats.decodesWaiting = stats.depthMapsWaiting = 0;
    for (size_t i = 0; i < plan.images.size(); ++i) {
      if (slots[i] < 0 || (blend.occlusion && depthScheduler.isDirty(slots[i]))) {
        ++stats.imagesWaiting;
        ++(slots[i] < 0 ? stats.decodesWaiting : stats.depthMapsWaiting);
        continue;
      }
      const Camera cam = photoCamera(plan.images[size_t(i)].photo);
      const ibr::PinholeFrustum& fr = slotFrustum[size_t(slots[i])];
      const double texel = std::max((fr.pxMax.x - fr.pxMin.x) / (depthSize * cam.focal.x),
                                    (fr.pxMax.y - fr.pxMin.y) / (depthSize * cam.focal.y));
      const ibr::DepthBias bias{biasAbs, settings.depthBiasTexels * texel};
      params.push_back(ibr::makeImageParams(cam, scene.origin, ibr::sliceLayout(cam, sliceSize, slots[i]),
                                            plan.images[i].weight, fr, bias));
      params.back().photo = plan.images[i].photo;
      params.back().date = photoDate(scene.photos[size_t(plan.images[i].photo)]);
      packed.resize(packed.size() + ibr::kTexelsPerImage * 4);
      ibr::packImageParams(params.back(), packed.data() + packed.size() - ibr::kTexelsPerImage * 4);
    }
    stats.residentImages = cache.residentCount();
    stats.debugSlot = debugSlot >= 0 ? debugSlot : cache.slotOf(settings.debug.photo);
    stats.debugImage = -1;
    for (size_t i = 0; i < params.size(); ++i)
      if (params[i].photo == settings.debug.photo) stats.debugImage = int(i);
    ensureParamsTexture(int(params.size()));
    if (!params.empty()) {
      glBindTexture(GL_TEXTURE_2D, paramsTexture.id());
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, ibr::kTexelsPerImage, GLsizei(params.size()), GL_RGBA, GL_FLOAT,
                      packed.data());
    }

    // View geometry pass: linear depth over the pinhole rectangle covering the (distorted) view.
    const bool distorted = view.distortion && !view.distortion->isIdentity();
    ibr::PinholeFrustum vf = ibr::idealRectCoveringImage(view, 0.0);
    ibr::setDepthRange(vf, view, bounds);
    glm::ivec2 depthSz(view.width, view.height);
    if (distorted) {
      // Same pixel density as the output over the (larger) undistorted rectangle.
      depthSz = glm::ivec2(std::ceil(vf.pxMax.x - vf.pxMin.x), std::ceil(vf.pxMax.y - vf.pxMin.y));
      depthSz = glm::min(depthSz, glm::ivec2(limits.maxTextureSize));
    }
    ensureViewTargets(depthSz, {view.width, view.height});
    glBindFramebuffer(GL_FRAMEBUFFER, viewFbo.id());
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, viewBuilding.id(), 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, viewDepth.id(), 0);
    const GLenum color0 = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &color0);
    gpu::checkFramebuffer("view depth");
    glViewport(0, 0, depthSz.x, depthSz.y);
    const GLfloat noBuilding[4] = {0, 0, 0, 0};
    glClearBufferfv(GL_COLOR, 0, noBuilding);
    // The view shows today's geometry: every surface, whatever its dates.
    drawDepth(viewDepthProgram, ibr::clipFromRender(view, vf, scene.origin), vf.near, vf.far, DateInterval{});
    pointsThisFrame = pointsActive();
    stats.pointsDrawn = 0;
    if (pointsThisFrame) renderViewPoints(view, vf, depthSz, blend);

    if (distorted) uploadIdealLookup(view);
    // The naive binding walks every selected image (it is the baseline without culling).
    // Tile lists come from the geometry's depth: pixels on the background sphere have none.
    cullingThisFrame = settings.tileCulling && !naive() && !params.empty() && sphereRadius() <= 0.0;
    if (cullingThisFrame) buildTileLists(view, vf, depthSz);

    // Shading pass into the colour target.
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, 0, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, viewColor.id(), 0);
    glDrawBuffers(1, &color0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    gpu::checkFramebuffer("view colour");
    glViewport(0, 0, view.width, view.height);
    shadeProgram.use();
    bindShadeInputs(view, vf, depthSz, distorted, blend);

    RenderOutput out;
    // The debug counts first and the picture last, so the colour target ends up holding the picture
    // (colorTexture()).
    if (withCounts) {
      out.counts = decodeCounts(shade(kShadeCount, view.width, view.height, true));
      out.loopLengths = decodeCounts(shade(kShadeLoopLength, view.width, view.height, true));
    }
    if (settings.debug.view == DebugView::None)
      shade(kShadeColour, view.width, view.height, false);
    else
      out.debugValues = renderDebugView(view, debugSlot);
    // Not over the depth-map view: that picture is in the photograph's image, not the view's.
    if (settings.debug.frusta && settings.debug.view != DebugView::DepthMap) drawFrusta(view, vf, depthSz, distorted);
    if (settings.readBackColour) out.rgba = readColour(view.width, view.height);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    checkGlError("render");
    stats.lastFrameMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }

  static Image16 decodeCounts(const Image8& enc) {
    Image16 out(enc.width, enc.height, 1);
    for (int y = 0; y < enc.height; ++y)
      for (int x = 0; x < enc.width; ++x) out.at(x, y, 0) = std::uint16_t(enc.at(x, y, 0) + 256 * enc.at(x, y, 1));
    return out;
  }

  // Per-tile culling (ibr/tile_culling.h): the GPU reduces each tile of the view depth to its depth
  // range, the CPU lists the images whose frustum may cover each tile's slab, the list goes to an
  // R16UI texture that the shading loop walks. Leaves viewFbo bound.
  void buildTileLists(const Camera& view, const ibr::PinholeFrustum& vf, glm::ivec2 depthSz) {
    ibr::TileGrid grid;
    grid.tileSize = std::max(1, settings.tileSize);
    grid.depthSize = depthSz;
    grid.rect = vf;
    const glm::ivec2 tiles(grid.tilesX(), grid.tilesY());
    if (tiles != tileRangeSize) {
      tileRange = makeRgba8Target(tiles.x, tiles.y);
      tileRangeSize = tiles;
    }
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, 0, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tileRange.id(), 0);
    const GLenum color0 = GL_COLOR_ATTACHMENT0;
    glDrawBuffers(1, &color0);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    gpu::checkFramebuffer("tile depth ranges");
    glViewport(0, 0, tiles.x, tiles.y);
    tileDepthProgram.use();
    bindUnit(kUnitViewDepth, GL_TEXTURE_2D, viewDepth.id());
    glUniform1i(tileDepthProgram.uniform("u_viewDepth"), kUnitViewDepth);
    glUniform2i(tileDepthProgram.uniform("u_depthSize"), depthSz.x, depthSz.y);
    glUniform1i(tileDepthProgram.uniform("u_tileSize"), grid.tileSize);
    glBindVertexArray(emptyVao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    std::vector<std::uint8_t> rgba(size_t(tiles.x) * tiles.y * 4);
    glReadPixels(0, 0, tiles.x, tiles.y, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    checkGlError("tile depth ranges");

    const ibr::TileLists lists =
        ibr::buildTileLists(view, scene.origin, grid, ibr::decodeTileDepth(rgba, grid), params);
    stats.meanTileList = lists.meanCount();
    stats.maxTileList = lists.maxCount();
    const int width = lists.maxCount() + 1, rows = tiles.x * tiles.y;
    if (width > limits.maxTextureSize || rows > limits.maxTextureSize) {
      diag.warn("per-tile culling needs a " + std::to_string(width) + "x" + std::to_string(rows) +
                " list texture, beyond MAX_TEXTURE_SIZE; this frame loops over every image");
      cullingThisFrame = false;
      return;
    }
    std::vector<std::uint16_t> table(size_t(width) * rows, 0);
    for (int t = 0; t < rows; ++t) {
      const auto& l = lists.lists[size_t(t)];
      table[size_t(t) * width] = std::uint16_t(l.size());
      std::copy(l.begin(), l.end(), table.begin() + std::ptrdiff_t(size_t(t) * width + 1));
    }
    tileLists = gpu::makeTexture();
    glBindTexture(GL_TEXTURE_2D, tileLists.id());  // uploaded on unit 0, bound to its unit for the shading pass
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R16UI, width, rows, 0, GL_RED_INTEGER, GL_UNSIGNED_SHORT, table.data());
    setNearestClamp(GL_TEXTURE_2D);
    tilesX = tiles.x;
    checkGlError("tile lists");
  }

  void uploadIdealLookup(const Camera& view) {
    std::vector<float> lookup(size_t(view.width) * view.height * 4, 0.0f);
    for (int y = 0; y < view.height; ++y)
      for (int x = 0; x < view.width; ++x) {
        float* o = &lookup[(size_t(y) * view.width + x) * 4];
        if (auto p = view.undistort({x + 0.5, y + 0.5})) {
          o[0] = float(p->x);
          o[1] = float(p->y);
          o[2] = 1.0f;
        }
      }
    lookupTexture = gpu::makeTexture();
    glBindTexture(GL_TEXTURE_2D, lookupTexture.id());  // uploaded on unit 0, bound to its unit for the shading pass
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, view.width, view.height, 0, GL_RGBA, GL_FLOAT, lookup.data());
    setNearestClamp(GL_TEXTURE_2D);
  }

  // The background sphere's radius this frame; 0 when there is none (RenderSettings::backgroundSphere).
  double sphereRadius() const {
    if (settings.backgroundSphere > 0.0) return settings.backgroundSphere;
    if (settings.backgroundSphere < 0.0 && geometryBounds.empty()) return kDefaultSphereRadius;
    return 0.0;
  }

  void bindShadeInputs(const Camera& view, const ibr::PinholeFrustum& vf, glm::ivec2 depthSz, bool distorted,
                       const ibr::BlendSettings& blend) {
    const gpu::Program& p = shadeProgram;
    if (naive()) {
      // The k-th selected image on the k-th sampler pair: the unrolled shader needs no indexing.
      for (int k = 0; k < slotCount; ++k) {
        const GLint imageUnit = naiveUnits[size_t(2 * k)], depthUnit = naiveUnits[size_t(2 * k + 1)];
        const int slot = k < int(params.size()) ? params[size_t(k)].layout.slice : 0;
        bindUnit(imageUnit, GL_TEXTURE_2D, naiveImages[size_t(slot)].id());
        bindUnit(depthUnit, GL_TEXTURE_2D, naiveDepths[size_t(slot)].id());
        glUniform1i(p.uniform(("u_image" + std::to_string(k)).c_str()), imageUnit);
        glUniform1i(p.uniform(("u_depth" + std::to_string(k)).c_str()), depthUnit);
      }
    } else {
      bindUnit(kUnitImages, GL_TEXTURE_2D_ARRAY, imageArray.id());
      bindUnit(kUnitDepthMaps, GL_TEXTURE_2D_ARRAY, depthArray.id());
    }
    bindUnit(kUnitParams, GL_TEXTURE_2D, paramsTexture.id());
    bindUnit(kUnitViewDepth, GL_TEXTURE_2D, viewDepth.id());
    bindUnit(kUnitLookup, GL_TEXTURE_2D, distorted ? lookupTexture.id() : 0);
    if (!naive()) {
      glUniform1i(p.uniform("u_images"), kUnitImages);
      glUniform1i(p.uniform("u_depthMaps"), kUnitDepthMaps);
    }
    glUniform1i(p.uniform("u_params"), kUnitParams);
    glUniform1i(p.uniform("u_viewDepth"), kUnitViewDepth);
    glUniform1i(p.uniform("u_idealLookup"), kUnitLookup);
    glUniform1i(p.uniform("u_useLookup"), distorted ? 1 : 0);
    bindUnit(kUnitTileLists, GL_TEXTURE_2D, cullingThisFrame ? tileLists.id() : 0);
    glUniform1i(p.uniform("u_tileLists"), kUnitTileLists);
    bindUnit(kUnitViewBuilding, GL_TEXTURE_2D, viewBuilding.id());
    bindUnit(kUnitValidity, GL_TEXTURE_2D, validityTexture.id());
    glUniform1i(p.uniform("u_viewBuilding"), kUnitViewBuilding);
    if (pointsThisFrame) {  // (the naive binding has its photographs on units from 8 up)
      bindUnit(kUnitPointColor, GL_TEXTURE_2D, pointColor.id());
    }
    // Without points the sampler points at a unit of the same type that is never read.
    glUniform1i(p.uniform("u_pointColor"), pointsThisFrame ? kUnitPointColor : kUnitLookup);
    glUniform1i(p.uniform("u_points"), pointsThisFrame ? 1 : 0);
    glUniform1f(p.uniform("u_meshPushBack"), float(meshPushBack()));
    glUniform1i(p.uniform("u_validity"), kUnitValidity);
    glUniform1i(p.uniform("u_validityWidth"), validityWidth);
    glUniform1i(p.uniform("u_culling"), cullingThisFrame ? 1 : 0);
    glUniform1i(p.uniform("u_tileSize"), std::max(1, settings.tileSize));
    glUniform1i(p.uniform("u_tilesX"), tilesX);
    glUniform2f(p.uniform("u_viewRectMin"), float(vf.pxMin.x), float(vf.pxMin.y));
    glUniform2f(p.uniform("u_viewRectInvSize"), float(1.0 / (vf.pxMax.x - vf.pxMin.x)),
                float(1.0 / (vf.pxMax.y - vf.pxMin.y)));
    glUniform2i(p.uniform("u_viewDepthSize"), depthSz.x, depthSz.y);
    glUniform1f(p.uniform("u_viewNear"), float(vf.near));
    glUniform1f(p.uniform("u_viewFar"), float(vf.far));
    glUniform1f(p.uniform("u_sphereRadius"), float(sphereRadius()));
    const glm::dvec3 c = view.center - scene.origin;
    glUniform3f(p.uniform("u_viewCenter"), float(c.x), float(c.y), float(c.z));
    uploadMat3(p.uniform("u_viewDirFromPix"), glm::transpose(view.camFromWorld) * view.camFromPix());
    glUniform1i(p.uniform("u_imageCount"), GLint(params.size()));
    glUniform1i(p.uniform("u_method"), blend.method == ibr::BlendMethod::Nearest ? 1 : 0);
    glUniform1i(p.uniform("u_occlusion"), blend.occlusion ? 1 : 0);
    glUniform1i(p.uniform("u_debugImage"), stats.debugImage);
    glUniform3f(p.uniform("u_background"), float(settings.background.r), float(settings.background.g),
                float(settings.background.b));
  }

  // Runs the shading pass in `mode` (ShadeMode) into the colour target; reads it back when asked
  // (else returns an empty image).
  Image8 shade(ShadeMode mode, int w, int h, bool readBack) {
    glUniform1i(shadeProgram.uniform("u_mode"), mode);
    glBindVertexArray(emptyVao.id());
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    if (!readBack) return {};
    return readColour(w, h);
  }

  // The bound colour target, RGBA8.
  static Image8 readColour(int w, int h) {
    Image8 img(w, h, 4);
    // Offscreen rows are stored top row first (docs/conventions.md): no flip.
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, img.data.data());
    checkGlError("colour read-back");
    return img;
  }

  static gpu::Program linkProgram(int index) {
    const ProgramSource& src = programSources()[size_t(index)];
    return gpu::Program(src.vertex, src.fragment, src.defines);
  }

  // ---- Debug views and overlays (issue 6) ----

  // Draws settings.debug.view into the colour target (viewFbo bound, the shading program's inputs
  // set). Returns its raw values when the colour is read back.
  Image16 renderDebugView(const Camera& view, int debugSlot) {
    const int w = view.width, h = view.height;
    const bool raw = settings.readBackColour;
    switch (settings.debug.view) {
      case DebugView::Counts: {
        Image16 values = raw ? decodeCounts(shade(kShadeCount, w, h, true)) : Image16{};
        shade(kShadeCountColour, w, h, false);
        return values;
      }
      case DebugView::Weight: {
        Image16 values = raw ? decodeCounts(shade(kShadeShare, w, h, true)) : Image16{};
        shade(kShadeShareColour, w, h, false);
        return values;
      }
      case DebugView::DepthMap: {
        Image16 values = depthMapView(w, h, debugSlot);
        return raw ? values : Image16{};
      }
      case DebugView::None:
        break;
    }
    return {};
  }

  // DebugView::DepthMap: the slot's depth map letterboxed into the w x h colour target. The raw
  // values are read back (always: the colours span the nearest to the farthest stored depth, a
  // range only a reduction finds) and the coloured picture uploaded over them.
  Image16 depthMapView(int w, int h, int slot) {
    stats.debugDepthNear = stats.debugDepthFar = 0.0;
    if (slot >= 0 && naive()) {
      if (!warnedDebugNaive) diag.warn("the depth-map debug view needs the texture-array binding");
      warnedDebugNaive = true;
      slot = -1;
    }
    Image16 values(w, h, 1, 65535);
    std::vector<bool> inside(size_t(w) * h, false);
    if (slot >= 0) {
      if (!debugDepthProgram.id()) debugDepthProgram = linkProgram(kProgramDebugDepth);
      // The map covers the frustum's ideal rectangle: shown with that aspect ratio, centred.
      const ibr::PinholeFrustum& fr = slotFrustum[size_t(slot)];
      const double aspect = (fr.pxMax.x - fr.pxMin.x) / (fr.pxMax.y - fr.pxMin.y);
      const glm::dvec2 rect = aspect * h > w ? glm::dvec2(w, w / aspect) : glm::dvec2(h * aspect, h);
      const glm::dvec2 rectMin = (glm::dvec2(w, h) - rect) / 2.0;
      const gpu::Program& p = debugDepthProgram;
      p.use();
      bindUnit(kUnitDepthMaps, GL_TEXTURE_2D_ARRAY, depthArray.id());
      glUniform1i(p.uniform("u_depthMaps"), kUnitDepthMaps);
      glUniform1f(p.uniform("u_slice"), float(slot));
      glUniform2f(p.uniform("u_rectMin"), float(rectMin.x), float(rectMin.y));
      glUniform2f(p.uniform("u_rectSize"), float(rect.x), float(rect.y));
      glBindVertexArray(emptyVao.id());
      glDrawArrays(GL_TRIANGLES, 0, 3);
      glBindVertexArray(0);
      const Image8 enc = readColour(w, h);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          values.at(x, y, 0) = std::uint16_t(enc.at(x, y, 0) + 256 * enc.at(x, y, 1));
          inside[size_t(y) * w + x] = enc.at(x, y, 2) > 127;
        }
      shadeProgram.use();
    }
    int lo = 65535, hi = 0;
    for (size_t i = 0; i < inside.size(); ++i)
      if (inside[i] && values.data[i] < 65535) {
        lo = std::min<int>(lo, values.data[i]);
        hi = std::max<int>(hi, values.data[i]);
      }
    if (lo <= hi) {
      const ibr::PinholeFrustum& fr = slotFrustum[size_t(slot)];
      stats.debugDepthNear = fr.near + lo / 65535.0 * (fr.far - fr.near);
      stats.debugDepthFar = fr.near + hi / 65535.0 * (fr.far - fr.near);
    }
    // Near bright (yellow), far dark; black where the photograph sees nothing; the background
    // colour outside the map.
    Image8 rgba(w, h, 4, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const size_t i = size_t(y) * w + x;
        std::uint8_t* o = rgba.px(x, y);
        glm::dvec3 c = settings.background;
        if (inside[i]) c = glm::dvec3(0.0);
        if (inside[i] && values.data[i] < 65535) {
          c = colorRamp(hi > lo ? double(hi - values.data[i]) / (hi - lo) : 1.0);
          o[3] = 255;
        }
        for (int k = 0; k < 3; ++k) o[k] = std::uint8_t(std::lround(255.0 * std::clamp(c[k], 0.0, 1.0)));
      }
    glBindTexture(GL_TEXTURE_2D, viewColor.id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data.data());
    checkGlError("depth-map debug view");
    return values;
  }

  // The frusta of every photograph (frustumOutline, truncated at the frustum depth) as one line
  // buffer, a range per photograph; rebuilt when the depth or the lens setting changes.
  void buildFrustumLines() {
    const double depth = settings.debug.frustumDepth > 0.0 ? settings.debug.frustumDepth : scene.cameraSpacing();
    if (frustumVao && depth == frustumDepthBuilt && settings.layers.lensDistortion == frustumLensBuilt) return;
    std::vector<float> xyz;
    frustumRange.clear();
    for (size_t i = 0; i < scene.photos.size(); ++i) {
      const Camera cam = photoCamera(int(i));
      // A distorted border is curved: 8 segments per side follow it well at debug-view sizes.
      const bool curved = cam.distortion && !cam.distortion->isIdentity();
      const std::vector<glm::dvec3> lines = frustumLineSegments(frustumOutline(cam, depth, curved ? 8 : 1));
      frustumRange.push_back({GLsizei(xyz.size() / 3), GLsizei(lines.size())});
      for (const glm::dvec3& p : lines) {
        const glm::dvec3 r = p - scene.origin;  // render frame (DESIGN.md §1)
        xyz.insert(xyz.end(), {float(r.x), float(r.y), float(r.z)});
      }
    }
    if (!frustumVao) {
      frustumVao = gpu::makeVertexArray();
      frustumBuffer = gpu::makeBuffer();
    }
    glBindVertexArray(frustumVao.id());
    glBindBuffer(GL_ARRAY_BUFFER, frustumBuffer.id());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(xyz.size() * sizeof(float)), xyz.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 3 * sizeof(float), nullptr);
    glBindVertexArray(0);
    frustumDepthBuilt = depth;
    frustumLensBuilt = settings.layers.lensDistortion;
    checkGlError("frustum lines");
  }

  // DebugSettings::frusta over the picture in the colour target (viewFbo bound), depth-tested
  // against the view's depth: visible parts opaque, hidden ones faint. Pinhole views only: the
  // lines go through the view's pinhole transform, which a distorted picture does not follow.
  void drawFrusta(const Camera& view, const ibr::PinholeFrustum& vf, glm::ivec2 depthSz, bool distorted) {
    if (distorted || scene.photos.empty() || depthSz != glm::ivec2(view.width, view.height)) return;
    buildFrustumLines();
    if (!linesProgram.id()) linesProgram = linkProgram(kProgramLines);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, viewDepth.id(), 0);
    gpu::checkFramebuffer("frusta");
    const gpu::Program& p = linesProgram;
    p.use();
    uploadMat4(p.uniform("u_clipFromRender"), ibr::clipFromRender(view, vf, scene.origin));
    glUniform1f(p.uniform("u_near"), float(vf.near));
    glUniform1f(p.uniform("u_far"), float(vf.far));
    const GLint colorLoc = p.uniform("u_color");
    glEnable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    glEnable(GL_BLEND);
    // Alpha accumulates as coverage: a line pixel counts as covered.
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    glBindVertexArray(frustumVao.id());
    const DrawRange all{0, frustumRange.back().first + frustumRange.back().count};
    auto draw = [&](const float* rgba, float alphaScale, int photo) {
      if (photo >= int(frustumRange.size())) return;
      const DrawRange& r = photo < 0 ? all : frustumRange[size_t(photo)];
      glUniform4f(colorLoc, rgba[0], rgba[1], rgba[2], rgba[3] * alphaScale);
      glDrawArrays(GL_LINES, r.first, r.count);
    };
    // Complementary depth tests, so each line pixel is drawn once: behind the geometry, then in front.
    for (const bool hidden : {true, false}) {
      glDepthFunc(hidden ? GL_GREATER : GL_LEQUAL);
      const float alpha = hidden ? kHiddenLineAlpha : 1.0f;
      draw(kFrustumOther, alpha, -1);
      for (const ibr::SelectedImage& im : plan.images) draw(kFrustumInFrame, alpha, im.photo);
      if (settings.debug.photo >= 0) draw(kFrustumDebug, alpha, settings.debug.photo);
    }
    glBindVertexArray(0);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glDisable(GL_DEPTH_TEST);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, 0, 0);
    checkGlError("frusta");
  }

  PhotoState photoState(int photo) const {
    if (photo < 0 || photo >= int(scene.photos.size())) return PhotoState::Absent;
    if (photoBroken[size_t(photo)]) return PhotoState::Broken;
    const int slot = cache.slotOf(photo);
    if (slot < 0) return loader->isPending(photo) ? PhotoState::Decoding : PhotoState::Absent;
    return depthScheduler.isDirty(slot) ? PhotoState::DepthMapPending : PhotoState::Ready;
  }
};

int probeMat3SpriteImages(int upTo) {
  int best = 0;
  // Not beyond the varying limit: some compilers crash there instead of failing to link.
  upTo = std::min(upTo, gpu::queryLimits().maxVaryingComponents / 9);
  for (int k = 1; k <= upTo; ++k) {
    try {
      gpu::Program p("points.vert", "points.frag", {"HV_MAT3_K=" + std::to_string(k)});
      best = k;
    } catch (const std::runtime_error&) {
      break;
    }
  }
  gpu::clearGlErrors();
  return best;
}

Renderer::Renderer(const Scene& scene, RenderSettings settings, Diagnostics& diag)
    : impl_(std::make_unique<Impl>(scene, settings, diag)) {
  impl_->init();
}
Renderer::~Renderer() = default;
RenderOutput Renderer::render(const Camera& view, bool withCounts, FrameMode mode) {
  return impl_->render(view, withCounts, mode);
}
bool Renderer::converged() const { return impl_->stats.imagesWaiting == 0 && !impl_->debugWaiting; }
void Renderer::preload(const Camera& view) { impl_->preload(view); }
const ibr::FramePlan& Renderer::lastPlan() const { return impl_->plan; }
const std::vector<ibr::ImageParams>& Renderer::lastImageParams() const { return impl_->params; }
const RenderSettings& Renderer::settings() const { return impl_->settings; }
RenderSettings& Renderer::settings() { return impl_->settings; }
ibr::SliceSize Renderer::sliceSize() const { return impl_->sliceSize; }
int Renderer::sliceCount() const { return impl_->slotCount; }
const RenderStats& Renderer::stats() const { return impl_->stats; }
PhotoState Renderer::photoState(int photo) const { return impl_->photoState(photo); }
int Renderer::slotOf(int photo) const { return impl_->cache.slotOf(photo); }
unsigned int Renderer::colorTexture() const { return impl_->viewColor.id(); }

}  // namespace hv::render
