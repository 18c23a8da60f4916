// The traffic over the picture (the 2013 paper, §3: a traffic simulation composited into the
// image-based view): each vehicle an instance of the box model of render/vehicles.h, depth-tested
// against the view's depth (the geometry the picture shows, points included), so that a building
// in front hides it; a contact shadow on the ground under each. Pinhole views only, like the
// frusta: the boxes go through the view's pinhole transform.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/render/gl/programs.h"
#include "hv/render/untextured.h"
#include "hv/render/vehicles.h"

#include <cstddef>

namespace hv::render::gl {

namespace {

// Per vertex of the model: position in fractions of the size, normal, kind (0 body, 1 glass, 2 shadow).
struct ShapeVertex {
  float local[3];
  float normal[3];
  float kind;
};

std::vector<ShapeVertex> vehicleShape() {
  std::vector<ShapeVertex> v;
  for (const VehiclePart& part : vehicleParts()) {
    const float kind = part.glass ? 1.0f : 0.0f;
    const glm::vec3 lo = part.lo, hi = part.hi;
    // Each face: axis a, side s (-1 lo, +1 hi); two triangles, wound counter-clockwise from outside.
    for (int a = 0; a < 3; ++a)
      for (const int s : {-1, 1}) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        glm::vec3 n(0.0f);
        n[a] = float(s);
        auto corner = [&](int ub, int uc) {
          glm::vec3 p;
          p[a] = s < 0 ? lo[a] : hi[a];
          p[b] = ub ? hi[b] : lo[b];
          p[c] = uc ? hi[c] : lo[c];
          return ShapeVertex{{p.x, p.y, p.z}, {n.x, n.y, n.z}, kind};
        };
        const ShapeVertex q[4] = {corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)};
        if (s > 0)
          v.insert(v.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
        else
          v.insert(v.end(), {q[0], q[2], q[1], q[0], q[3], q[2]});
      }
  }
  // The contact shadow: a quad on the ground, kShadowScale times the footprint.
  const float h = 0.5f * kShadowScale;
  const ShapeVertex s[4] = {{{-h, -h, 0}, {0, 0, 1}, 2.0f},
                            {{h, -h, 0}, {0, 0, 1}, 2.0f},
                            {{h, h, 0}, {0, 0, 1}, 2.0f},
                            {{-h, h, 0}, {0, 0, 1}, 2.0f}};
  v.insert(v.end(), {s[0], s[1], s[2], s[0], s[2], s[3]});
  return v;
}

}  // namespace

// Over the picture in the colour target (viewFbo bound, the colour attached).
void GlBackend::vehiclesPass(const Frame& f) {
  const std::vector<VehicleInstance>& vehicles = f.traffic.vehicles;
  if (vehicles.empty() || f.rect.distorted || f.rect.depthSize != glm::ivec2(f.view.width, f.view.height)) return;
  if (!vehicleVao_) {
    vehicleProgram_ = VehicleProgram(programs().vehicles);
    vehicleVao_ = gpu::makeVertexArray();
    vehicleShape_ = gpu::makeBuffer();
    vehicleInstances_ = gpu::makeBuffer();
    const std::vector<ShapeVertex> shape = vehicleShape();
    vehicleShapeVertices_ = int(shape.size());
    glBindVertexArray(vehicleVao_.id());
    glBindBuffer(GL_ARRAY_BUFFER, vehicleShape_.id());
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(shape.size() * sizeof(ShapeVertex)), shape.data(), GL_STATIC_DRAW);
    const GLsizei stride = sizeof(ShapeVertex);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(offsetof(ShapeVertex, normal)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(ShapeVertex, kind)));
    glBindBuffer(GL_ARRAY_BUFFER, vehicleInstances_.id());
    const GLsizei istride = sizeof(VehicleInstance);
    const std::size_t offsets[6] = {offsetof(VehicleInstance, position), offsetof(VehicleInstance, right),
                                    offsetof(VehicleInstance, forward),  offsetof(VehicleInstance, up),
                                    offsetof(VehicleInstance, size),     offsetof(VehicleInstance, colour)};
    for (GLuint k = 0; k < 6; ++k) {
      glEnableVertexAttribArray(3 + k);
      glVertexAttribPointer(3 + k, 3, GL_FLOAT, GL_FALSE, istride, reinterpret_cast<const void*>(offsets[k]));
      glVertexAttribDivisor(3 + k, 1);
    }
    glBindVertexArray(0);
    gpu::checkGlError("vehicle model");
  }
  glBindBuffer(GL_ARRAY_BUFFER, vehicleInstances_.id());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vehicles.size() * sizeof(VehicleInstance)), vehicles.data(), GL_STREAM_DRAW);
  glBindBuffer(GL_ARRAY_BUFFER, 0);

  gpu::attachDepth(viewDepth_.id());
  gpu::checkFramebuffer("vehicles");
  const VehicleProgram& p = vehicleProgram_;
  p.program.use();
  gpu::uploadMat4(p.clipFromRender, f.rect.clipFromRender);
  glUniform1f(p.near, float(f.rect.frustum.near));
  glUniform1f(p.far, float(f.rect.frustum.far));
  auto vec3 = [](GLint location, const glm::dvec3& v) { glUniform3f(location, float(v.x), float(v.y), float(v.z)); };
  const UntexturedSettings& u = f.untextured;
  vec3(p.sunDir, sunDirection(f.up, u));
  vec3(p.skyLight, u.skyLight);
  vec3(p.groundLight, u.groundLight);
  vec3(p.sunLight, u.sunLight);
  vec3(p.glass, glm::dvec3(kGlassColour));
  glUniform1f(p.shadowOpacity, kShadowOpacity);
  glUniform1f(p.shadowLift, kShadowLift);
  glBindVertexArray(vehicleVao_.id());
  const GLsizei instances = GLsizei(vehicles.size());
  const int boxVertices = vehicleShapeVertices_ - 6;
  glEnable(GL_DEPTH_TEST);
  // The shadows first, darkening the ground without writing depth or coverage (alpha kept) ...
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_LEQUAL);
  glEnable(GL_BLEND);
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  glDrawArraysInstanced(GL_TRIANGLES, boxVertices, 6, instances);
  glDisable(GL_BLEND);
  // ... then the boxes, hidden by the view's depth and by each other.
  glDepthMask(GL_TRUE);
  glDepthFunc(GL_LESS);
  glDrawArraysInstanced(GL_TRIANGLES, 0, boxVertices, instances);
  glBindVertexArray(0);
  glDisable(GL_DEPTH_TEST);
  gpu::attachDepth(0);
  gpu::checkGlError("vehicles");
}

}  // namespace hv::render::gl
