// GPU objects the renderer's passes are built from: render targets, texture arrays, data
// textures, and binding them to units. GLES 3.0 only: float depth is not filterable there, so
// depth targets sample with nearest filtering and no comparison (the shaders compare themselves).
#pragma once

#include "hv/gpu/gl.h"

#include <glm/glm.hpp>

namespace hv::gpu {

inline void setNearestClamp(GLenum target) {
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

inline void setLinearClamp(GLenum target) {
  glTexParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

// An RGBA8 texture of w x h with nearest filtering: a colour render target.
inline Texture makeRgba8Target(int w, int h) {
  Texture t = makeTexture();
  glBindTexture(GL_TEXTURE_2D, t.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  setNearestClamp(GL_TEXTURE_2D);
  return t;
}

// A DEPTH_COMPONENT32F texture of w x h: a depth render target the shaders sample.
inline Texture makeDepthTarget(int w, int h) {
  Texture t = makeTexture();
  glBindTexture(GL_TEXTURE_2D, t.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT32F, w, h, 0, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  setNearestClamp(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  return t;
}

// An RGBA8 photograph of w x h, bilinear.
inline Texture makeRgba8Image(int w, int h) {
  Texture t = makeTexture();
  glBindTexture(GL_TEXTURE_2D, t.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  setLinearClamp(GL_TEXTURE_2D);
  return t;
}

// `layers` RGBA8 photographs of w x h in one array, bilinear, with `levels` mip levels (immutable
// storage; the caller uploads every level and picks the minification filter).
inline Texture makeRgba8Array(int w, int h, int layers, int levels = 1) {
  Texture t = makeTexture();
  glBindTexture(GL_TEXTURE_2D_ARRAY, t.id());
  glTexStorage3D(GL_TEXTURE_2D_ARRAY, levels, GL_RGBA8, w, h, layers);
  setLinearClamp(GL_TEXTURE_2D_ARRAY);
  return t;
}

// `layers` DEPTH_COMPONENT32F depth maps of size x size in one array.
inline Texture makeDepthArray(int size, int layers) {
  Texture t = makeTexture();
  glBindTexture(GL_TEXTURE_2D_ARRAY, t.id());
  glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_DEPTH_COMPONENT32F, size, size, layers, 0, GL_DEPTH_COMPONENT, GL_FLOAT,
               nullptr);
  setNearestClamp(GL_TEXTURE_2D_ARRAY);
  glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_COMPARE_MODE, GL_NONE);
  return t;
}

// An RGBA32F data texture of w x h, nearest (per-image parameters, lookups), filled from `data`
// when given.
inline Texture makeFloatData(int w, int h, const float* data = nullptr) {
  Texture t = makeTexture();
  glBindTexture(GL_TEXTURE_2D, t.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, w, h, 0, GL_RGBA, GL_FLOAT, data);
  setNearestClamp(GL_TEXTURE_2D);
  return t;
}

// Attachments of the bound framebuffer (GL_FRAMEBUFFER): a 2D texture, or 0 to detach.
inline void attachColour(GLuint texture) {
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
}
inline void attachDepth(GLuint texture) {
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, texture, 0);
}
// Fragments write colour attachment 0, or no colour at all (depth-only passes).
inline void drawToColour() {
  const GLenum colour0 = GL_COLOR_ATTACHMENT0;
  glDrawBuffers(1, &colour0);
}
inline void drawToNoColour() {
  const GLenum none = GL_NONE;
  glDrawBuffers(1, &none);
}

// One full-screen triangle (shaders/fullscreen.vert makes its vertices from gl_VertexID), drawn
// with an empty vertex array.
inline void drawFullscreen(const VertexArray& emptyVao) {
  glBindVertexArray(emptyVao.id());
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindVertexArray(0);
}

// Binds `id` to texture unit `unit` and leaves unit 0 active (where uploads bind their textures).
inline void bindUnit(int unit, GLenum target, GLuint id) {
  glActiveTexture(GLenum(GL_TEXTURE0 + unit));
  glBindTexture(target, id);
  glActiveTexture(GL_TEXTURE0);
}

inline void uploadMat4(GLint loc, const glm::dmat4& m) {
  float f[16];
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) f[4 * c + r] = float(m[c][r]);
  glUniformMatrix4fv(loc, 1, GL_FALSE, f);
}

inline void uploadMat3(GLint loc, const glm::dmat3& m) {
  float f[9];
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) f[3 * c + r] = float(m[c][r]);
  glUniformMatrix3fv(loc, 1, GL_FALSE, f);
}

}  // namespace hv::gpu
