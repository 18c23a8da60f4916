// The traffic over the picture (the 2013 paper, §3: a traffic simulation composited into the
// image-based view): each vehicle an instance of its class's model (hv/traffic/vehicle_model.h: a
// glTF file, or the built-in box with wheels), one instanced draw per class, depth-tested
// against the view's depth (the geometry the picture shows, points included; rewritten in the
// rasteriser's encoding, so that the vehicles draw with early depth testing), so that a building
// in front hides it; a contact shadow on the ground under each. Pinhole views only, like the
// frusta: the models go through the view's pinhole transform.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/render/gl/programs.h"
#include "hv/render/untextured.h"
#include "hv/render/vehicles.h"

#include <algorithm>
#include <cstddef>

namespace hv::render::gl {

namespace {

// Vertex attributes of the models (ModelVertex) and of the instances (VehicleInstance).
void modelAttributes() {
  const GLsizei stride = sizeof(ModelVertex);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(ModelVertex, local)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(ModelVertex, normal)));
  // colour and paint, contiguous: one vec4.
  static_assert(offsetof(ModelVertex, paint) == offsetof(ModelVertex, colour) + 3 * sizeof(float));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(ModelVertex, colour)));
}

// The instance attributes from the `first` instance of the bound buffer on (GLES 3.0 has no base
// instance: each class's draw points them at its own range).
void instanceAttributes(std::size_t first) {
  const GLsizei stride = sizeof(VehicleInstance);
  const std::size_t offsets[6] = {offsetof(VehicleInstance, position), offsetof(VehicleInstance, right),
                                  offsetof(VehicleInstance, forward),  offsetof(VehicleInstance, up),
                                  offsetof(VehicleInstance, size),     offsetof(VehicleInstance, colour)};
  for (GLuint k = 0; k < 6; ++k) {
    glEnableVertexAttribArray(3 + k);
    glVertexAttribPointer(3 + k, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(first * sizeof(VehicleInstance) + offsets[k]));
    glVertexAttribDivisor(3 + k, 1);
  }
}

// The contact shadow: a quad on the ground, kShadowScale times the footprint.
std::vector<ModelVertex> shadowQuad() {
  const float h = 0.5f * kShadowScale;
  const glm::vec3 n(0.0f, 0.0f, 1.0f), c(0.0f);
  const ModelVertex s[4] = {
      {{-h, -h, 0}, n, c, 0.0f}, {{h, -h, 0}, n, c, 0.0f}, {{h, h, 0}, n, c, 0.0f}, {{-h, h, 0}, n, c, 0.0f}};
  return {s[0], s[1], s[2], s[0], s[2], s[3]};
}

}  // namespace

// The models' vertex arrays, (re)built when the scene's models change.
void GlBackend::vehicleShapes(const std::shared_ptr<const VehicleModels>& models) {
  if (vehicleShapesBuilt_ && models == vehicleModels_) return;
  if (!vehicleInstances_.id()) vehicleInstances_ = gpu::makeBuffer();
  for (int k = 0; k <= kVehicleClasses; ++k) {
    const std::vector<ModelVertex> shape =
        k == kVehicleClasses ? shadowQuad() : (models ? models->of(VehicleClass(k)) : boxWithWheelsModel()).vertices;
    if (!vehicleVaos_[std::size_t(k)].id()) {
      vehicleVaos_[std::size_t(k)] = gpu::makeVertexArray();
      vehicleShapes_[std::size_t(k)] = gpu::makeBuffer();
    }
    vehicleShapeVertices_[std::size_t(k)] = int(shape.size());
    glBindVertexArray(vehicleVaos_[std::size_t(k)].id());
    glBindBuffer(GL_ARRAY_BUFFER, vehicleShapes_[std::size_t(k)].id());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(shape.size() * sizeof(ModelVertex)), shape.data(), GL_STATIC_DRAW);
    modelAttributes();
    glBindBuffer(GL_ARRAY_BUFFER, vehicleInstances_.id());
    instanceAttributes(0);
  }
  glBindVertexArray(0);
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  vehicleModels_ = models;
  vehicleShapesBuilt_ = true;
  gpu::checkGlError("vehicle models");
}

// Over the picture in the colour target (viewFbo bound, the colour attached).
void GlBackend::vehiclesPass(const Frame& f) {
  const std::vector<VehicleInstance>& vehicles = f.traffic.vehicles;
  if (vehicles.empty() || f.rect.distorted || f.rect.depthSize != glm::ivec2(f.view.width, f.view.height)) return;
  if (!vehicleProgram_.program.id()) {
    vehicleProgram_ = VehicleProgram(programs().vehicles);
    vehicleDepthProgram_ = VehicleDepthProgram(programs().vehicleDepth);
  }
  vehicleShapes(f.traffic.models);
  // The vehicles by class (a counting sort), so that each class is one instanced draw.
  std::array<std::size_t, kVehicleClasses + 1> first{};
  for (const VehicleInstance& v : vehicles) ++first[std::size_t(std::clamp(v.model, 0, kVehicleClasses - 1)) + 1];
  for (int k = 0; k < kVehicleClasses; ++k) first[std::size_t(k) + 1] += first[std::size_t(k)];
  vehicleSorted_.resize(vehicles.size());
  std::array<std::size_t, kVehicleClasses> next{};
  std::copy(first.begin(), first.end() - 1, next.begin());
  for (const VehicleInstance& v : vehicles)
    vehicleSorted_[next[std::size_t(std::clamp(v.model, 0, kVehicleClasses - 1))]++] = v;
  glBindBuffer(GL_ARRAY_BUFFER, vehicleInstances_.id());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vehicleSorted_.size() * sizeof(VehicleInstance)), vehicleSorted_.data(),
               GL_STREAM_DRAW);

  // The view's linear depth (depth.frag) rewritten in the rasteriser's encoding for the same
  // projection, into a depth buffer of the traffic's own: the vehicles then leave gl_FragDepth
  // alone, and the rasteriser rejects their hidden fragments before shading them (early depth
  // test). The view's depth itself is left as the geometry made it.
  const glm::ivec2 size(f.view.width, f.view.height);
  if (!vehicleDepth_.id() || vehicleDepthSize_ != size) {
    vehicleDepth_ = gpu::makeDepthTarget(size.x, size.y);
    vehicleDepthSize_ = size;
  }
  gpu::attachDepth(vehicleDepth_.id());
  gpu::checkFramebuffer("vehicles");
  {
    const VehicleDepthProgram& d = vehicleDepthProgram_;
    d.program.use();
    gpu::bindUnit(kUnitViewDepth, GL_TEXTURE_2D, viewDepth_.id());
    glUniform1i(d.viewDepth, kUnitViewDepth);
    glUniform1f(d.near, float(f.rect.frustum.near));
    glUniform1f(d.far, float(f.rect.frustum.far));
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_ALWAYS);
    glDepthMask(GL_TRUE);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    gpu::drawFullscreen(emptyVao_);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  }
  const VehicleProgram& p = vehicleProgram_;
  p.program.use();
  gpu::uploadMat4(p.clipFromRender, f.rect.clipFromRender);
  auto vec3 = [](GLint location, const glm::dvec3& v) { glUniform3f(location, float(v.x), float(v.y), float(v.z)); };
  const UntexturedSettings& u = f.untextured;
  vec3(p.sunDir, sunDirection(f.up, u));
  vec3(p.skyLight, u.skyLight);
  vec3(p.groundLight, u.groundLight);
  vec3(p.sunLight, u.sunLight);
  glUniform1f(p.shadowOpacity, kShadowOpacity);
  glUniform1f(p.shadowLift, kShadowLift);
  glEnable(GL_DEPTH_TEST);
  // The shadows first, all in one draw, darkening the ground without writing depth or coverage
  // (alpha kept) ...
  glUniform1f(p.shadow, 1.0f);
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_LEQUAL);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  glBindVertexArray(vehicleVaos_[kVehicleClasses].id());
  glDrawArraysInstanced(GL_TRIANGLES, 0, vehicleShapeVertices_[kVehicleClasses], GLsizei(vehicles.size()));
  glDisable(GL_BLEND);
  // ... then each class's model, one instanced draw per class, hidden by the view's depth and by
  // each other.
  glUniform1f(p.shadow, 0.0f);
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  for (int k = 0; k < kVehicleClasses; ++k) {
    const std::size_t count = first[std::size_t(k) + 1] - first[std::size_t(k)];
    if (!count) continue;
    glBindVertexArray(vehicleVaos_[std::size_t(k)].id());
    instanceAttributes(first[std::size_t(k)]);
    glDrawArraysInstanced(GL_TRIANGLES, 0, vehicleShapeVertices_[std::size_t(k)], GLsizei(count));
  }
  glBindBuffer(GL_ARRAY_BUFFER, 0);
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
  gpu::attachDepth(0);
  gpu::checkGlError("vehicles");
}

}  // namespace hv::render::gl
