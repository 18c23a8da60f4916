#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/ibr/slice_image.h"
#include "hv/render/gl/programs.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace hv::render::gl {

using gpu::checkGlError;

Image16 decodeCounts(const Image8& enc) {
  Image16 out(enc.width, enc.height, 1);
  for (int y = 0; y < enc.height; ++y)
    for (int x = 0; x < enc.width; ++x) out.at(x, y, 0) = std::uint16_t(enc.at(x, y, 0) + 256 * enc.at(x, y, 1));
  return out;
}

// Offscreen rows are stored top row first (docs/conventions.md): no flip.
Image8 readColour(int w, int h) {
  Image8 img(w, h, 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, img.data.data());
  checkGlError("colour read-back");
  return img;
}

GlBackend::GlBackend(Diagnostics& diag) : diag_(diag), limits_(gpu::queryLimits()) {
  depthProgram_ = DepthProgram(programs().depth);
  viewDepthProgram_ = DepthProgram(programs().viewDepth);
  shadeProgram_ = ShadeProgram(programs().shade);  // replaced in allocateSlots for the naive binding
  tileDepthProgram_ = TileDepthProgram(programs().tileDepth);
  depthFbo_ = gpu::makeFramebuffer();
  viewFbo_ = gpu::makeFramebuffer();
  emptyVao_ = gpu::makeVertexArray();
}

BackendLimits GlBackend::limits() const {
  BackendLimits l;
  l.maxTextureSize = limits_.maxTextureSize;
  l.maxArrayTextureLayers = limits_.maxArrayTextureLayers;
  l.maxVaryingComponents = limits_.maxVaryingComponents;
  l.maxTextureImageUnits = limits_.maxTextureImageUnits;
  l.shadingUnits = kUnitValidity - kUnitParams + 1;
  // The naive binding's images take the units the shading pass does not use itself (kUnitParams
  // .. kUnitValidity are its own).
  l.naiveImageUnits = 0;
  for (GLint u = 0; u < limits_.maxTextureImageUnits; ++u)
    if (u < kUnitParams || u > kUnitValidity) ++l.naiveImageUnits;
  return l;
}

namespace {

// The surfaces' vertex layout (GeometryBuffers: position, the days the surface existed, building), set
// on the bound vertex array for the bound GL_ARRAY_BUFFER: the static geometry and each streamed
// terrain tile share it.
void setSurfaceVertexLayout() {
  const GLsizei stride = GeometryBuffers::kStride * sizeof(float);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, nullptr);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(3 * sizeof(float)));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 1, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(5 * sizeof(float)));
}

}  // namespace

void GlBackend::uploadGeometry(const GeometryBuffers& g) {
  layerRange_ = g.layers;
  indexCount_ = int(g.indices.size());
  meshVao_ = gpu::makeVertexArray();
  vertexBuffer_ = gpu::makeBuffer();
  indexBuffer_ = gpu::makeBuffer();
  glBindVertexArray(meshVao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, vertexBuffer_.id());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(g.vertices.size() * sizeof(float)), g.vertices.data(), GL_STATIC_DRAW);
  setSurfaceVertexLayout();
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, indexBuffer_.id());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(g.indices.size() * sizeof(std::uint32_t)), g.indices.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);
  validityWidth_ = g.validityWidth;
  validityTexture_ = gpu::makeFloatData(g.validityWidth, g.validityRows, g.validity.data());
  checkGlError("geometry upload");
}

void GlBackend::uploadValidity(const std::vector<float>& validity, int width, int rows) {
  validityWidth_ = width;
  validityTexture_ = gpu::makeFloatData(width, rows, validity.data());
  checkGlError("validity upload");
}

void GlBackend::uploadOrthophoto(const Orthophoto& o, const OrthophotoAffine& affine) {
  orthophotoAffine_ = affine;
  if (o.empty()) {
    orthophoto_ = {};
    return;
  }
  // Made on its own unit, so that no other unit's GL_TEXTURE_2D binding changes (the passes bind
  // some textures once); the active unit restored.
  GLint active = GL_TEXTURE0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  glActiveTexture(GL_TEXTURE0 + kUnitOrthophoto);
  orthophoto_ = gpu::makeRgba8Image(o.width, o.height);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, o.width, o.height, GL_RGBA, GL_UNSIGNED_BYTE, o.rgba.data());
  glActiveTexture(GLenum(active));
  checkGlError("orthophoto upload");
}

void GlBackend::uploadStreamedTile(std::uint64_t id, const std::vector<float>& vertices,
                                  const std::vector<std::uint32_t>& indices) {
  StreamedTileBuffers t;
  t.vao = gpu::makeVertexArray();
  t.vertices = gpu::makeBuffer();
  t.indices = gpu::makeBuffer();
  t.indexCount = int(indices.size());
  glBindVertexArray(t.vao.id());
  glBindBuffer(GL_ARRAY_BUFFER, t.vertices.id());
  glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(float)), vertices.data(), GL_STATIC_DRAW);
  setSurfaceVertexLayout();
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, t.indices.id());
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(indices.size() * sizeof(std::uint32_t)), indices.data(),
               GL_STATIC_DRAW);
  glBindVertexArray(0);
  checkGlError("streamed tile upload");
  streamedTiles_[id] = std::move(t);
}

PointProgramInfo GlBackend::uploadPoints(const std::vector<PointVertex>& vertices, const PointProgramRequest& req) {
  pointVao_ = gpu::makeVertexArray();
  pointBuffer_ = gpu::makeBuffer();
  glBindVertexArray(pointVao_.id());
  glBindBuffer(GL_ARRAY_BUFFER, pointBuffer_.id());
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

  PointProgramInfo info;
  GLfloat range[2] = {1.0f, 1.0f};
  glGetFloatv(GL_ALIASED_POINT_SIZE_RANGE, range);
  maxPointSize_ = float(std::max(1.0, std::min<double>(range[1], req.maxPointSizePx)));
  info.maxPointSize = maxPointSize_;
  pointDepthProgram_ = PointProgram(programs().pointDepth);
  if (req.form == SpriteForm::Mat3) {
    // Linking far beyond the varying limit can crash a driver's compiler (llvmpipe does at K = 40)
    // instead of failing: start from what the limit allows, 9 components per image.
    const int start = std::max(1, std::min(req.wantImages, limits_.maxVaryingComponents / 9));
    for (int k = start; k >= 1 && info.mat3Images == 0; --k) {
      try {
        pointColorProgram_ = PointProgram(programs().pointColor, {"HV_MAT3_K=" + std::to_string(k)});
        info.mat3Images = k;
      } catch (const std::runtime_error&) {
      }
    }
    if (info.mat3Images == 0) throw std::runtime_error("the mat3 sprite program links with no image at all");
  } else {
    pointColorProgram_ = PointProgram(programs().pointColor);
  }
  return info;
}

void GlBackend::allocateSlots(const SlotLayout& layout) {
  layout_ = layout;
  const int w = layout.slice.width, h = layout.slice.height, n = layout.slots;
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  if (naive()) {
    for (GLint u = 0; u < limits_.maxTextureImageUnits; ++u)
      if (u < kUnitParams || u > kUnitValidity) naiveUnits_.push_back(u);
    for (int i = 0; i < n; ++i) {
      naiveImages_.push_back(gpu::makeRgba8Image(w, h));
      naiveDepths_.push_back(gpu::makeDepthTarget(layout.depthSize, layout.depthSize));
    }
    checkGlError("naive slices");
    shadeProgram_ = ShadeProgram(programs().shade, n);
    depthLayers_ = n;
  } else {
    imageArray_ = gpu::makeRgba8Array(w, h, n, ibr::mipLevelCount(w, h));
    depthLayers_ = 0;
    depthArray_ = {};
    const int initial = layout.initialDepthLayers > 0 ? std::min(layout.initialDepthLayers, n) : n;
    ensureDepthLayer(initial - 1);
    checkGlError("slice arrays");
  }
  checkGlError("renderer initialisation");
}

void GlBackend::ensureDepthLayer(int slot) {
  if (naive() || slot < depthLayers_) return;
  const int size = layout_.depthSize;
  const int grown = std::min(layout_.slots, std::max(slot + 1, 2 * depthLayers_));
  // Made on the depth maps' own unit, where the new array belongs: no other unit's binding changes.
  GLint active = GL_TEXTURE0;
  glGetIntegerv(GL_ACTIVE_TEXTURE, &active);
  glActiveTexture(GL_TEXTURE0 + kUnitDepthMaps);
  gpu::Texture next = gpu::makeDepthArray(size, grown);
  glActiveTexture(GLenum(active));
  if (depthLayers_ > 0) {
    // The maps drawn so far, copied exactly (a depth blit, nearest, same format); blits bypass
    // the fragment operations but the scissor test.
    if (!depthCopyRead_.id()) {
      depthCopyRead_ = gpu::makeFramebuffer();
      depthCopyDraw_ = gpu::makeFramebuffer();
    }
    GLint readFbo = 0, drawFbo = 0;
    glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &readFbo);
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &drawFbo);
    const GLboolean scissor = glIsEnabled(GL_SCISSOR_TEST);
    glDisable(GL_SCISSOR_TEST);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, depthCopyRead_.id());
    glReadBuffer(GL_NONE);
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, depthCopyDraw_.id());
    gpu::drawToNoColour();
    for (int l = 0; l < depthLayers_; ++l) {
      glFramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, depthArray_.id(), 0, l);
      glFramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, next.id(), 0, l);
      glBlitFramebuffer(0, 0, size, size, 0, 0, size, size, GL_DEPTH_BUFFER_BIT, GL_NEAREST);
    }
    glFramebufferTextureLayer(GL_READ_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, 0, 0, 0);
    glFramebufferTextureLayer(GL_DRAW_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, 0, 0, 0);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(readFbo));
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(drawFbo));
    if (scissor) glEnable(GL_SCISSOR_TEST);
  }
  depthArray_ = std::move(next);
  depthLayers_ = grown;
  checkGlError("depth-map array growth");
}

void GlBackend::uploadImage(int slot, const Image8& slice) {
  const int w = layout_.slice.width, h = layout_.slice.height;
  if (naive()) {
    glBindTexture(GL_TEXTURE_2D, naiveImages_[size_t(slot)].id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, slice.data.data());
  } else {
    // Every level of the slice's chain (ibr::sliceMipChain): mipmaps and mask feathering read them.
    glBindTexture(GL_TEXTURE_2D_ARRAY, imageArray_.id());
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, slot, w, h, 1, GL_RGBA, GL_UNSIGNED_BYTE, slice.data.data());
    const std::vector<Image8> chain = ibr::sliceMipChain(slice);
    for (size_t l = 1; l < chain.size(); ++l)
      glTexSubImage3D(GL_TEXTURE_2D_ARRAY, GLint(l), 0, 0, slot, chain[l].width, chain[l].height, 1, GL_RGBA,
                      GL_UNSIGNED_BYTE, chain[l].data.data());
  }
  checkGlError("image upload");
}

void GlBackend::uploadDepthMap(int slot, const std::vector<float>& depth) {
  const int n = layout_.depthSize;
  if (depth.size() != std::size_t(n) * std::size_t(n))
    throw std::invalid_argument("depth map upload: " + std::to_string(depth.size()) + " values for a " +
                                std::to_string(n) + "^2 map");
  if (naive()) {
    glBindTexture(GL_TEXTURE_2D, naiveDepths_[size_t(slot)].id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, n, n, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  } else {
    ensureDepthLayer(slot);
    glBindTexture(GL_TEXTURE_2D_ARRAY, depthArray_.id());
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, slot, n, n, 1, GL_DEPTH_COMPONENT, GL_FLOAT, depth.data());
  }
  checkGlError("depth map upload");
}

void GlBackend::finishDepthMaps() { glFinish(); }

Image8 GlBackend::shade(ShadeMode mode, int w, int h, bool readBack) {
  glUniform1i(shade_->mode, mode);
  gpu::drawFullscreen(emptyVao_);
  if (!readBack) return {};
  return readColour(w, h);
}

RenderOutput GlBackend::runViewPasses(const Frame& f, ViewPassStats& stats) {
  stats = {};
  const Camera& view = f.view;
  uploadParams(f);
  viewDepthPass(f);  // leaves viewFbo bound
  if (f.points.enabled) viewPointsPass(f);
  if (f.rect.distorted) uploadIdealLookup(view);
  cullingThisFrame_ = f.culling;
  if (cullingThisFrame_) tileListPass(f, stats);

  // Shading pass into the colour target.
  gpu::attachDepth(0);
  gpu::attachColour(viewColor_.id());
  gpu::drawToColour();
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  gpu::checkFramebuffer("view colour");
  glViewport(0, 0, view.width, view.height);
  selectShadeProgram(f, stats);
  shade_->program.use();
  bindShadeInputs(f);

  RenderOutput out;
  // The debug counts first and the picture last, so the colour target ends up holding the picture
  // (colorTexture()).
  if (f.withCounts) {
    out.counts = decodeCounts(shade(kShadeCount, view.width, view.height, true));
    out.loopLengths = decodeCounts(shade(kShadeLoopLength, view.width, view.height, true));
  }
  if (f.debug.view == DebugView::None) {
    shade(kShadeColour, view.width, view.height, false);
    vehiclesPass(f);
  } else {
    out.debugValues = debugViewPass(f, stats);
  }
  if (f.debug.frusta) frustaPass(f);
  if (f.readBackColour) out.rgba = readColour(view.width, view.height);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  checkGlError("render");
  return out;
}

}  // namespace hv::render::gl
