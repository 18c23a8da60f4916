// Visibility layers on the GPU (render/layer_peeling.h; Layered projective texture maps, 2003,
// §4.1): a terrain pass, then per layer an item buffer and one occlusion query per object of the
// working set. shaders/layer_peel.frag holds the tests.
#include "hv/render/layer_peeling.h"

#include "hv/camera/frustum.h"
#include "hv/gpu/program.h"
#include "hv/gpu/textures.h"
#include "hv/render/gl/layer_peel_programs.h"
#include "hv/render/gl/programs.h"

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>

namespace hv::render {

namespace {

struct PeelVertex {
  float position[3];
  float normal[3];
  std::uint32_t object;  // bit 31: terrain
};

constexpr std::uint32_t kTerrainBit = 0x80000000u;

std::uint32_t floatBits(float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// An RG32UI (or R32UI) texture of w x h, nearest (integer textures cannot be filtered).
gpu::Texture makeUintTarget(int w, int h, GLenum internal, GLenum format) {
  gpu::Texture t = gpu::makeTexture();
  glBindTexture(GL_TEXTURE_2D, t.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GLint(internal), w, h, 0, format, GL_UNSIGNED_INT, nullptr);
  gpu::setNearestClamp(GL_TEXTURE_2D);
  return t;
}

struct PeelProgram {
  gpu::Program program;
  GLint clipFromRender = -1, center = -1, backFaces = -1, working = -1, workingWidth = -1, terrain = -1,
        sameSurface = -1, item = -1, anyFragment = -1;
  explicit PeelProgram(const ProgramSource& src) : program(gl::linkProgram(src)) {
    const gpu::UniformResolver u(program, src.vertex + " + " + src.fragment);
    clipFromRender = u.required("u_clipFromRender");
    center = u.required("u_center");
    backFaces = u.optional("u_backFaces");
    working = u.optional("u_working");
    workingWidth = u.optional("u_workingWidth");
    terrain = u.optional("u_terrain");
    sameSurface = u.optional("u_sameSurface");
    item = u.optional("u_item");
    anyFragment = u.optional("u_anyFragment");
  }
};

constexpr int kUnitWorking = 0, kUnitTerrain = 1, kUnitItem = 2;

}  // namespace

namespace gl {

const LayerPeelSources& layerPeelPrograms() {
  static const LayerPeelSources p = {{"layer_peel.vert", "layer_peel.frag", {"HV_PEEL_TERRAIN"}},
                                     {"layer_peel.vert", "layer_peel.frag", {"HV_PEEL_ITEM"}},
                                     {"layer_peel.vert", "layer_peel.frag", {}}};
  return p;
}

}  // namespace gl

GpuObjectLayers peelObjectLayersGl(const Camera& camera, const Mesh& geometry,
                                   const std::vector<std::uint32_t>& objectOfTriangle,
                                   const std::vector<bool>& terrainTriangle, std::size_t objectCount,
                                   const GpuLayerPeelSettings& settings) {
  const std::size_t triangles = geometry.triangles.size();
  if (objectOfTriangle.size() != triangles || terrainTriangle.size() != triangles)
    throw std::invalid_argument("GPU layer peeling: " + std::to_string(objectOfTriangle.size()) + " object ids and " +
                                std::to_string(terrainTriangle.size()) + " terrain flags for " +
                                std::to_string(triangles) + " triangles");
  if (objectCount >= kTerrainBit) throw std::invalid_argument("GPU layer peeling: too many objects");
  for (std::uint32_t o : objectOfTriangle)
    if (o >= objectCount)
      throw std::invalid_argument("GPU layer peeling: object id " + std::to_string(o) + " out of " +
                                  std::to_string(objectCount) + " objects");
  const int w = camera.width, h = camera.height;
  if (w <= 0 || h <= 0) throw std::invalid_argument("GPU layer peeling: camera '" + camera.id + "' has no pixels");

  GpuObjectLayers out;
  out.layerOfObject.assign(objectCount, 0);
  if (triangles == 0 || objectCount == 0) return out;

  // Vertices grouped by object, so that each object is one range of one draw call.
  const Aabb bounds = geometry.bounds();
  const glm::dvec3 origin = bounds.center();
  std::vector<std::uint32_t> order(triangles);
  for (std::uint32_t t = 0; t < triangles; ++t) order[t] = t;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::uint32_t a, std::uint32_t b) { return objectOfTriangle[a] < objectOfTriangle[b]; });
  std::vector<PeelVertex> vertices;
  vertices.reserve(3 * triangles);
  std::vector<GLint> firstVertex(objectCount + 1, 0);
  std::vector<PeelVertex> terrainVertices;
  for (std::uint32_t t : order) {
    const glm::uvec3& tri = geometry.triangles[t];
    const glm::dvec3 p[3] = {geometry.positions[tri.x], geometry.positions[tri.y], geometry.positions[tri.z]};
    const glm::dvec3 n = glm::cross(p[1] - p[0], p[2] - p[0]);
    const std::uint32_t id = objectOfTriangle[t] | (terrainTriangle[t] ? kTerrainBit : 0u);
    for (const glm::dvec3& q : p) {
      const glm::dvec3 r = q - origin;
      const PeelVertex v{{float(r.x), float(r.y), float(r.z)}, {float(n.x), float(n.y), float(n.z)}, id};
      vertices.push_back(v);
      if (terrainTriangle[t]) terrainVertices.push_back(v);
    }
    firstVertex[objectOfTriangle[t] + 1] += 3;
  }
  for (std::size_t o = 0; o < objectCount; ++o) firstVertex[o + 1] += firstVertex[o];

  const PeelProgram terrainProgram(gl::layerPeelPrograms().terrain);
  const PeelProgram itemProgram(gl::layerPeelPrograms().item);
  const PeelProgram testProgram(gl::layerPeelPrograms().test);

  auto makeVao = [](const std::vector<PeelVertex>& v, gpu::Buffer& buffer) {
    gpu::VertexArray vao = gpu::makeVertexArray();
    buffer = gpu::makeBuffer();
    glBindVertexArray(vao.id());
    glBindBuffer(GL_ARRAY_BUFFER, buffer.id());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(v.size() * sizeof(PeelVertex)), v.data(), GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(PeelVertex), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(PeelVertex),
                          reinterpret_cast<const void*>(offsetof(PeelVertex, normal)));
    glEnableVertexAttribArray(2);
    glVertexAttribIPointer(2, 1, GL_UNSIGNED_INT, sizeof(PeelVertex),
                           reinterpret_cast<const void*>(offsetof(PeelVertex, object)));
    glBindVertexArray(0);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    return vao;
  };
  gpu::Buffer allBuffer, terrainBuffer;
  const gpu::VertexArray allVao = makeVao(vertices, allBuffer);
  const gpu::VertexArray terrainVao = makeVao(terrainVertices, terrainBuffer);

  PinholeFrustum frustum = idealRectCoveringImage(camera);
  setDepthRange(frustum, camera, bounds);
  const glm::dmat4 clip = clipFromRender(camera, frustum, origin);
  const glm::vec3 center(camera.center - origin);

  const gpu::Texture depth = gpu::makeDepthTarget(w, h);
  const gpu::Texture terrain = makeUintTarget(w, h, GL_RG32UI, GL_RG_INTEGER);
  const gpu::Texture item = makeUintTarget(w, h, GL_RG32UI, GL_RG_INTEGER);
  const int workingWidth = int(std::min<std::size_t>(objectCount, 1024));
  const int workingHeight = int((objectCount + std::size_t(workingWidth) - 1) / std::size_t(workingWidth));
  const gpu::Texture workingTexture = makeUintTarget(workingWidth, workingHeight, GL_R32UI, GL_RED_INTEGER);
  std::vector<std::uint32_t> working(std::size_t(workingWidth) * std::size_t(workingHeight), 0);
  auto uploadWorking = [&] {
    glBindTexture(GL_TEXTURE_2D, workingTexture.id());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, workingWidth, workingHeight, GL_RED_INTEGER, GL_UNSIGNED_INT,
                    working.data());
  };

  const gpu::Framebuffer terrainFbo = gpu::makeFramebuffer(), itemFbo = gpu::makeFramebuffer(),
                         testFbo = gpu::makeFramebuffer();
  glViewport(0, 0, w, h);
  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_SCISSOR_TEST);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  // "No surface": a distance beyond any (finite, where the shaders compare it).
  const GLuint none[4] = {floatBits(3.0e38f), floatBits(3.0e38f), 0u, 0u};

  // Where each ray enters the ground (r) and leaves it (g).
  glBindFramebuffer(GL_FRAMEBUFFER, terrainFbo.id());
  gpu::attachColour(terrain.id());
  gpu::attachDepth(depth.id());
  gpu::drawToColour();
  gpu::checkFramebuffer("layer peeling (terrain)");
  glClearBufferuiv(GL_COLOR, 0, none);
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  terrainProgram.program.use();
  gpu::uploadMat4(terrainProgram.clipFromRender, clip);
  glUniform3f(terrainProgram.center, center.x, center.y, center.z);
  for (int back = 0; back < 2; ++back) {
    glClear(GL_DEPTH_BUFFER_BIT);
    glColorMask(back == 0, back == 1, GL_FALSE, GL_FALSE);
    glUniform1i(terrainProgram.backFaces, back);
    glBindVertexArray(terrainVao.id());
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(terrainVertices.size()));
  }
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);

  auto bindCommon = [&](const PeelProgram& p) {
    p.program.use();
    gpu::uploadMat4(p.clipFromRender, clip);
    glUniform3f(p.center, center.x, center.y, center.z);
    gpu::bindUnit(kUnitWorking, GL_TEXTURE_2D, workingTexture.id());
    glUniform1i(p.working, kUnitWorking);
    glUniform1i(p.workingWidth, workingWidth);
    gpu::bindUnit(kUnitTerrain, GL_TEXTURE_2D, terrain.id());
    glUniform1i(p.terrain, kUnitTerrain);
    glUniform2f(p.sameSurface, float(settings.sameSurfaceMetres), float(settings.sameSurfaceRelative));
  };

  // One occlusion query per object of `objects`: does any fragment pass the test?
  std::vector<GLuint> queries(objectCount, 0);
  glGenQueries(GLsizei(objectCount), queries.data());
  auto anyPassing = [&](const std::vector<std::uint32_t>& objects, bool anyFragment) {
    glBindFramebuffer(GL_FRAMEBUFFER, testFbo.id());
    gpu::attachColour(0);
    gpu::attachDepth(depth.id());
    gpu::drawToNoColour();
    gpu::checkFramebuffer("layer peeling (occlusion test)");
    glDisable(GL_DEPTH_TEST);
    glDepthMask(GL_FALSE);
    bindCommon(testProgram);
    gpu::bindUnit(kUnitItem, GL_TEXTURE_2D, item.id());
    glUniform1i(testProgram.item, kUnitItem);
    glUniform1i(testProgram.anyFragment, anyFragment ? 1 : 0);
    glBindVertexArray(allVao.id());
    for (std::uint32_t o : objects) {
      glBeginQuery(GL_ANY_SAMPLES_PASSED, queries[o]);
      glDrawArrays(GL_TRIANGLES, firstVertex[o], firstVertex[o + 1] - firstVertex[o]);
      glEndQuery(GL_ANY_SAMPLES_PASSED);
    }
    out.queries += objects.size();
    std::vector<bool> passed(objects.size());
    for (std::size_t i = 0; i < objects.size(); ++i) {
      GLuint r = 0;
      glGetQueryObjectuiv(queries[objects[i]], GL_QUERY_RESULT, &r);
      passed[i] = r != 0;
    }
    glDepthMask(GL_TRUE);
    return passed;
  };

  // The first working set: every object some pixel sees (hidden or not).
  std::vector<std::uint32_t> all;
  for (std::uint32_t o = 0; o < objectCount; ++o)
    if (firstVertex[o + 1] > firstVertex[o]) all.push_back(o), working[o] = 1;
  uploadWorking();
  const std::vector<bool> seen = anyPassing(all, true);
  std::vector<std::uint32_t> set;
  std::fill(working.begin(), working.end(), 0u);
  for (std::size_t i = 0; i < all.size(); ++i)
    if (seen[i]) set.push_back(all[i]), working[all[i]] = 1;
  out.objectsSeen = set.size();

  while (!set.empty()) {
    if (out.layers >= std::numeric_limits<std::uint16_t>::max())
      throw std::runtime_error("GPU layer peeling: more than 65535 layers");
    uploadWorking();
    // The item buffer of the working set.
    glBindFramebuffer(GL_FRAMEBUFFER, itemFbo.id());
    gpu::attachColour(item.id());
    gpu::attachDepth(depth.id());
    gpu::drawToColour();
    gpu::checkFramebuffer("layer peeling (item buffer)");
    const GLuint empty[4] = {0u, none[1], 0u, 0u};
    glClearBufferuiv(GL_COLOR, 0, empty);
    glClear(GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    bindCommon(itemProgram);
    glBindVertexArray(allVao.id());
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(vertices.size()));
    // Which objects are behind another one somewhere.
    const std::vector<bool> blocked = anyPassing(set, false);
    std::vector<std::uint32_t> rest;
    const auto layer = std::uint16_t(out.layers + 1);
    for (std::size_t i = 0; i < set.size(); ++i) {
      if (blocked[i])
        rest.push_back(set[i]);
      else
        out.layerOfObject[set[i]] = layer, working[set[i]] = 0;
    }
    if (rest.size() == set.size()) {
      out.stoppedAtCycle = true;
      break;
    }
    ++out.layers;
    set = std::move(rest);
  }

  glDeleteQueries(GLsizei(objectCount), queries.data());
  glBindVertexArray(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDisable(GL_DEPTH_TEST);
  for (int unit : {kUnitWorking, kUnitTerrain, kUnitItem}) gpu::bindUnit(unit, GL_TEXTURE_2D, 0);
  gpu::checkGlError("GPU layer peeling");
  return out;
}

}  // namespace hv::render
