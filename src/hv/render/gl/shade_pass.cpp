// The shading pass: per pixel, the photographs that see its surface point blended with their
// weights (Brédif 2013 eq. 2), each behind its depth test and its date (shaders/ibr_shade.frag).
// Its inputs: the per-image parameters (one data-texture row per image, ibr::packImageParams), the
// view depth, the lookup from distorted to ideal pixels, the tile lists and the points' colours.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/render/gl/shade_config.h"
#include "hv/render/untextured.h"

#include <algorithm>
#include <stdexcept>

namespace hv::render::gl {

void GlBackend::uploadParams(const Frame& f) {
  const int rows = int(f.params.size());
  if (!paramsTexture_ || rows > paramsRows_) {
    paramsRows_ = std::max(rows, 64);
    if (paramsRows_ > limits_.maxTextureSize)
      throw std::runtime_error("more images per pass than MAX_TEXTURE_SIZE rows of parameters");
    paramsTexture_ = gpu::makeFloatData(ibr::kTexelsPerImage, paramsRows_);
  }
  if (!f.params.empty()) {
    glBindTexture(GL_TEXTURE_2D, paramsTexture_.id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, ibr::kTexelsPerImage, GLsizei(f.params.size()), GL_RGBA, GL_FLOAT,
                    f.packedParams.data());
  }
}

// A distorted view: each output pixel's ideal (undistorted) position, where the view depth is read.
void GlBackend::uploadIdealLookup(const Camera& view) {
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
  // Uploaded on unit 0, bound to its unit for the shading pass.
  lookupTexture_ = gpu::makeFloatData(view.width, view.height, lookup.data());
}

void GlBackend::selectShadeProgram(const Frame& f, const ViewPassStats& stats) {
  shade_ = &shadeProgram_;
  if (naive() || !shadeSpecialisation()) return;
  const int candidates = cullingThisFrame_ && stats.tileListsBuilt ? stats.maxTileList : int(f.params.size());
  const std::vector<std::string> defines = shadeConfigDefines(f, candidates, limits_.maxAnisotropy);
  const std::string key = shadeConfigKey(defines);
  auto it = shadePrograms_.find(key);
  if (it == shadePrograms_.end()) it = shadePrograms_.emplace(key, ShadeProgram(programs().shade, 0, defines)).first;
  shade_ = &it->second;
}

void GlBackend::bindShadeInputs(const Frame& f) {
  const ShadeProgram& p = *shade_;
  const Camera& view = f.view;
  const hv::PinholeFrustum& vf = f.rect.frustum;
  const bool distorted = f.rect.distorted;
  const bool points = f.points.enabled;
  if (naive()) {
    // The k-th selected image on the k-th sampler pair: the unrolled shader needs no indexing.
    for (int k = 0; k < layout_.slots; ++k) {
      const GLint imageUnit = naiveUnits_[size_t(2 * k)], depthUnit = naiveUnits_[size_t(2 * k + 1)];
      const int slot = k < int(f.params.size()) ? f.params[size_t(k)].layout.slice : 0;
      gpu::bindUnit(imageUnit, GL_TEXTURE_2D, naiveImages_[size_t(slot)].id());
      gpu::bindUnit(depthUnit, GL_TEXTURE_2D, naiveDepths_[size_t(slot)].id());
      glUniform1i(p.naiveImages[size_t(k)], imageUnit);
      glUniform1i(p.naiveDepths[size_t(k)], depthUnit);
    }
  } else {
    gpu::bindUnit(kUnitImages, GL_TEXTURE_2D_ARRAY, imageArray_.id());
    // The slices' mip levels are read with mipmaps and by the mask feathering; anisotropic
    // filtering (where the context has it) with mipmaps only.
    const ibr::BlendSettings& b = f.blend;
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER,
                    b.mipmaps || b.featherPx > 0.0 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
    const bool anisotropic = b.mipmaps && limits_.maxAnisotropy > 1.0f && b.anisotropy > 1.0;
    if (limits_.maxAnisotropy > 0.0f)
      glTexParameterf(GL_TEXTURE_2D_ARRAY, gpu::kGlTextureMaxAnisotropy,
                      anisotropic ? std::clamp(float(b.anisotropy), 1.0f, limits_.maxAnisotropy) : 1.0f);
    gpu::bindUnit(kUnitDepthMaps, GL_TEXTURE_2D_ARRAY, depthArray_.id());
    glUniform1i(p.weighting, b.weighting == ibr::Weighting::Geometry ? 1 : 0);
    glUniform1f(p.resolutionWeight, float(b.resolutionWeight));
    glUniform1f(p.penaltyEpsilon, float(b.penaltyEpsilon));
    glUniform1i(p.geometryK, ibr::geometryBlendCount(b.k, b.geometryK));
    glUniform1f(p.viewFocal, float(0.5 * (view.focal.x + view.focal.y)));
    glUniform1f(p.feather, float(std::max(b.featherPx, 0.0)));
    glUniform1i(p.maskFeather, b.featherPx > 0.0 && b.masks ? 1 : 0);
    glUniform1f(p.consensus, float(std::max(b.consensus, 0.0)));
    glUniform1i(p.mipmaps, !b.mipmaps ? 0 : anisotropic ? 2 : 1);
    glUniform1f(p.sliceWidth, float(layout_.slice.width));
  }
  gpu::bindUnit(kUnitParams, GL_TEXTURE_2D, paramsTexture_.id());
  gpu::bindUnit(kUnitViewDepth, GL_TEXTURE_2D, viewDepth_.id());
  gpu::bindUnit(kUnitLookup, GL_TEXTURE_2D, distorted ? lookupTexture_.id() : 0);
  if (!naive()) {
    glUniform1i(p.images, kUnitImages);
    glUniform1i(p.depthMaps, kUnitDepthMaps);
  }
  glUniform1i(p.params, kUnitParams);
  glUniform1i(p.viewDepth, kUnitViewDepth);
  glUniform1i(p.idealLookup, kUnitLookup);
  glUniform1i(p.useLookup, distorted ? 1 : 0);
  gpu::bindUnit(kUnitTileLists, GL_TEXTURE_2D, cullingThisFrame_ ? tileLists_.id() : 0);
  glUniform1i(p.tileLists, kUnitTileLists);
  gpu::bindUnit(kUnitViewBuilding, GL_TEXTURE_2D, viewBuilding_.id());
  gpu::bindUnit(kUnitValidity, GL_TEXTURE_2D, validityTexture_.id());
  glUniform1i(p.viewBuilding, kUnitViewBuilding);
  if (points) gpu::bindUnit(kUnitPointColor, GL_TEXTURE_2D, pointColor_.id());  // naive: photographs from unit 8 up
  // Without points the sampler points at a unit of the same type that is never read.
  glUniform1i(p.pointColor, points ? kUnitPointColor : kUnitLookup);
  glUniform1i(p.points, points ? 1 : 0);
  glUniform1f(p.meshPushBack, float(f.meshPushBack));
  glUniform1i(p.validity, kUnitValidity);
  glUniform1i(p.validityWidth, validityWidth_);
  glUniform1i(p.culling, cullingThisFrame_ ? 1 : 0);
  glUniform1i(p.tileSize, f.tileSize);
  glUniform1i(p.tilesX, tilesX_);
  glUniform2f(p.viewRectMin, float(vf.pxMin.x), float(vf.pxMin.y));
  glUniform2f(p.viewRectInvSize, float(1.0 / (vf.pxMax.x - vf.pxMin.x)), float(1.0 / (vf.pxMax.y - vf.pxMin.y)));
  glUniform2i(p.viewDepthSize, f.rect.depthSize.x, f.rect.depthSize.y);
  glUniform1f(p.viewNear, float(vf.near));
  glUniform1f(p.viewFar, float(vf.far));
  glUniform1f(p.sphereRadius, float(f.sphereRadius));
  const glm::dvec3 c = view.center - f.origin;
  glUniform3f(p.viewCenter, float(c.x), float(c.y), float(c.z));
  gpu::uploadMat3(p.viewDirFromPix, glm::transpose(view.camFromWorld) * view.camFromPix());
  glUniform1i(p.imageCount, GLint(f.params.size()));
  glUniform1i(p.method, f.blend.method == ibr::BlendMethod::Nearest ? 1 : 0);
  glUniform1i(p.region, f.blend.selection == ibr::Selection::Region ? 1 : 0);
  glUniform1i(p.blendK, std::max(f.blend.k, 1));
  glUniform1i(p.occlusion, f.blend.occlusion ? 1 : 0);
  glUniform1i(p.debugImage, f.debug.image);
  glUniform3f(p.background, float(f.background.r), float(f.background.g), float(f.background.b));
  // Where no photograph contributes (shaders/untextured.glsl, render/untextured.h).
  const UntexturedSettings& u = f.untextured;
  auto vec3 = [](GLint location, const glm::dvec3& v) { glUniform3f(location, float(v.x), float(v.y), float(v.z)); };
  glUniform1i(p.shading, u.shading ? 1 : 0);
  glUniform1i(p.sky, u.sky ? 1 : 0);
  vec3(p.up, glm::normalize(f.up));
  vec3(p.sunDir, sunDirection(f.up, u));
  vec3(p.albedo, u.albedo);
  vec3(p.skyLight, u.skyLight);
  vec3(p.groundLight, u.groundLight);
  vec3(p.sunLight, u.sunLight);
  vec3(p.horizon, u.horizon);
  vec3(p.zenith, u.zenith);
  // The orthophoto on untextured terrain: the array binding only (the naive one's photographs hold
  // the units above kUnitValidity); the sampler otherwise points at a sampler2D unit never read.
  const bool ortho = u.orthophoto && orthophoto_ && !naive();
  if (ortho) gpu::bindUnit(kUnitOrthophoto, GL_TEXTURE_2D, orthophoto_.id());
  glUniform1i(p.orthophoto, ortho ? kUnitOrthophoto : kUnitLookup);
  glUniform1i(p.orthophotoOn, ortho ? 1 : 0);
  vec3(p.orthoU, orthophotoAffine_.uRow);
  vec3(p.orthoV, orthophotoAffine_.vRow);
}

}  // namespace hv::render::gl
