// The point pass (de Castro & Brédif 2022 §2.3-2.4; the hybrid of 2016 §4.2): sprites' depths into
// the view depth, depth-tested against the mesh, then the winners' colours blended from the
// photographs (with eye-dome lighting on untextured points) into their own target.
#include "hv/render/gl/gl_backend.h"

#include "hv/gpu/textures.h"
#include "hv/ibr/sprite_homography.h"

#include <algorithm>

namespace hv::render::gl {

// Draws `pass`'s sprites with `program` into a target of `size` texels covering `fr`. The caller
// sets the depth state and the program's own uniforms.
void GlBackend::drawPoints(const PointProgram& program, const PointPass& pass, const Camera& cam,
                           const hv::PinholeFrustum& fr, glm::ivec2 size, glm::dvec3 centerRender) {
  const glm::dmat3 M = ibr::targetCameraMatrix(cam, fr, size);
  const glm::dmat3 Minv = glm::inverse(M);
  const glm::dvec3 c = centerRender;
  program.program.use();
  gpu::uploadMat3(program.M, M);
  gpu::uploadMat3(program.MinvT, glm::transpose(Minv));
  gpu::uploadMat3(program.Minv, Minv);
  glUniform3f(program.C, float(c.x), float(c.y), float(c.z));
  glUniform2f(program.targetSize, float(size.x), float(size.y));
  glUniform1f(program.near, float(fr.near));
  glUniform1f(program.far, float(fr.far));
  glUniform1f(program.maxPointSize, maxPointSize_);
  glUniform1f(program.depthOffset, float(pass.depthOffset));
  glUniform1i(program.classify, pass.classify ? 1 : 0);
  glUniform1i(program.dropTransient, pass.dropTransient ? 1 : 0);
  glUniform1uiv(program.keptClasses, 8, pass.keptClasses.data());
  const GLint radiusLoc = program.radius;
  glBindVertexArray(pointVao_.id());
  for (const PointDraw& d : pass.draws) {
    glUniform1f(radiusLoc, d.radius);
    glDrawArrays(GL_POINTS, GLint(d.first), GLsizei(d.count));
  }
  glBindVertexArray(0);
}

// H'_i and E_i of every image of the frame for the view's target (2022 §2.3): 3 texels per image.
void GlBackend::uploadPointParams(const Frame& f, const glm::dmat3& viewM) {
  const glm::dvec3 viewC = f.view.center - f.origin;
  const int rows = std::max<int>(1, int(f.params.size()));
  if (!pointParamsTexture_ || rows > pointParamsRows_) {
    pointParamsRows_ = std::max(rows, 64);
    pointParamsTexture_ = gpu::makeFloatData(3, pointParamsRows_);
  }
  std::vector<float> packed;
  for (const ibr::ImageParams& im : f.params) {
    const ibr::SpriteImage si = ibr::spriteImage(viewM, viewC, im.pixFromWorld, im.centerRender);
    for (int r = 0; r < 3; ++r)
      packed.insert(packed.end(), {float(si.hPrime[0][r]), float(si.hPrime[1][r]), float(si.hPrime[2][r]),
                                   float(si.e[r])});
  }
  if (!f.params.empty()) {
    glBindTexture(GL_TEXTURE_2D, pointParamsTexture_.id());
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, 3, GLsizei(f.params.size()), GL_RGBA, GL_FLOAT, packed.data());
  }
}

// After the mesh's depth pass, in the view-depth target (the ideal rectangle covering the view,
// so distorted views resample it as they do the mesh's depth). Leaves viewFbo bound.
void GlBackend::viewPointsPass(const Frame& f) {
  const ViewPoints& vp = f.points;
  const Camera& view = f.view;
  const hv::PinholeFrustum& vf = f.rect.frustum;
  const glm::ivec2 depthSz = f.rect.depthSize;
  const glm::dvec3 center = view.center - f.origin;
  gpu::drawToNoColour();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  drawPoints(pointDepthProgram_, vp.pass, view, vf, depthSz, center);
  glDisable(GL_DEPTH_TEST);

  if (depthSz != pointColorSize_) {
    pointColor_ = gpu::makeRgba8Target(depthSz.x, depthSz.y);
    pointColorSize_ = depthSz;
  }
  gpu::attachDepth(0);
  gpu::attachColour(pointColor_.id());
  gpu::drawToColour();
  gpu::checkFramebuffer("point colour");
  const GLfloat clear[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, clear);
  uploadPointParams(f, ibr::targetCameraMatrix(view, vf, depthSz));
  const PointProgram& p = pointColorProgram_;
  p.program.use();
  gpu::bindUnit(kUnitImages, GL_TEXTURE_2D_ARRAY, imageArray_.id());
  gpu::bindUnit(kUnitDepthMaps, GL_TEXTURE_2D_ARRAY, depthArray_.id());
  gpu::bindUnit(kUnitParams, GL_TEXTURE_2D, paramsTexture_.id());
  gpu::bindUnit(kUnitViewDepth, GL_TEXTURE_2D, viewDepth_.id());
  gpu::bindUnit(kUnitPointParams, GL_TEXTURE_2D, pointParamsTexture_.id());
  glUniform1i(p.images, kUnitImages);
  glUniform1i(p.depthMaps, kUnitDepthMaps);
  glUniform1i(p.params, kUnitParams);
  glUniform1i(p.viewDepth, kUnitViewDepth);
  glUniform1i(p.pointParams, kUnitPointParams);
  // The date test as in the mesh pass: the building the view's geometry pass drew under each
  // pixel, and its validity (shaders/image_test.glsl, hv_surfaceExisted).
  gpu::bindUnit(kUnitViewBuilding, GL_TEXTURE_2D, viewBuilding_.id());
  gpu::bindUnit(kUnitValidity, GL_TEXTURE_2D, validityTexture_.id());
  glUniform1i(p.viewBuilding, kUnitViewBuilding);
  glUniform1i(p.validity, kUnitValidity);
  glUniform1i(p.validityWidth, validityWidth_);
  glUniform1i(p.imageCount, int(f.params.size()));
  glUniform1i(p.method, f.blend.method == ibr::BlendMethod::Nearest ? 1 : 0);
  glUniform1i(p.region, f.blend.selection == ibr::Selection::Region ? 1 : 0);
  glUniform1i(p.blendK, std::max(f.blend.k, 1));
  glUniform1i(p.occlusion, f.blend.occlusion ? 1 : 0);
  glUniform1i(p.epsilonTest, vp.epsilonTest ? 1 : 0);
  glUniform1f(p.epsilon, float(vp.epsilon));
  glUniform1i(p.eyeDome, vp.eyeDome ? 1 : 0);
  glUniform1f(p.edlStrength, float(vp.eyeDomeStrength));
  glUniform1f(p.edlRadius, float(vp.eyeDomeRadiusPx));
  // Both passes compute the same float expression; the tolerance only absorbs compilers that
  // evaluate it differently in the two programs (1e-6 of the depth range).
  glUniform1f(p.depthTolerance, 1e-6f);
  drawPoints(p, vp.pass, view, vf, depthSz, center);
  gpu::checkGlError("point passes");
}

}  // namespace hv::render::gl
