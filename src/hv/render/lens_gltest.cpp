// The GLSL lens models (hv_distort in shaders/ibr_common.glsl) against their C++ twin
// (hv::LensDistortion::distort), model by model, through the same packed parameters the renderer
// uploads (ibr::packImageParams).
#include "hv/camera/camera.h"
#include "hv/gpu/gl.h"
#include "hv/gpu/shader_sources.h"
#include "hv/ibr/frame_plan.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

namespace hv::render {
namespace {

// Each fragment (i, j) distorts the ideal pixel u_origin + (i, j) * u_step of image 0 and writes
// (p_d, inside-the-domain, 1).
const char* kProbe = R"(#version 300 es
precision highp float;
precision highp int;
#include "ibr_common.glsl"
uniform vec2 u_origin;
uniform vec2 u_step;
out vec4 o_result;
void main() {
  HvImage im = hv_fetchImage(0);
  vec2 p = u_origin + floor(gl_FragCoord.xy) * u_step;
  vec2 pd;
  bool inside = hv_distort(im, p, pd);
  o_result = vec4(pd, inside ? 1.0 : 0.0, 1.0);
}
)";

constexpr int kGrid = 32;

struct Probe {
  std::vector<float> rgba;  // kGrid x kGrid results
};

Probe runProbe(const Camera& cam, glm::dvec2 origin, glm::dvec2 step) {
  const std::string* vs = gpu::findShaderSource("fullscreen.vert");
  gpu::Program program(gpu::ShaderText{"fullscreen.vert", *vs}, gpu::ShaderText{"lens_probe.frag", kProbe});

  std::vector<float> packed(ibr::kTexelsPerImage * 4);
  hv::PinholeFrustum fr;
  fr.pxMax = {double(cam.width), double(cam.height)};
  ibr::packImageParams(ibr::makeImageParams(cam, glm::dvec3(0.0), {}, 1.0, fr, {}), packed.data());
  gpu::Texture params = gpu::makeTexture();
  glBindTexture(GL_TEXTURE_2D, params.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, ibr::kTexelsPerImage, 1, 0, GL_RGBA, GL_FLOAT, packed.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);

  gpu::Texture target = gpu::makeTexture();
  glBindTexture(GL_TEXTURE_2D, target.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, kGrid, kGrid, 0, GL_RGBA, GL_FLOAT, nullptr);
  gpu::Framebuffer fbo = gpu::makeFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target.id(), 0);
  gpu::checkFramebuffer("lens probe");
  gpu::VertexArray vao = gpu::makeVertexArray();
  glBindVertexArray(vao.id());
  glViewport(0, 0, kGrid, kGrid);
  program.use();
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, params.id());
  glUniform1i(program.uniform("u_params"), 0);
  glUniform2f(program.uniform("u_origin"), float(origin.x), float(origin.y));
  glUniform2f(program.uniform("u_step"), float(step.x), float(step.y));
  glDrawArrays(GL_TRIANGLES, 0, 3);
  Probe out;
  out.rgba.resize(size_t(kGrid) * kGrid * 4);
  glReadPixels(0, 0, kGrid, kGrid, GL_RGBA, GL_FLOAT, out.rgba.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  gpu::checkGlError("lens probe");
  return out;
}

class LensGlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testing::glContext();
    gpu::clearGlErrors();
    const char* ext = reinterpret_cast<const char*>(glGetString(GL_EXTENSIONS));
    if (!ext || !std::strstr(ext, "GL_EXT_color_buffer_float"))
      GTEST_SKIP() << "the context cannot render to RGBA32F (no GL_EXT_color_buffer_float)";
  }

  // Every probed pixel: the same domain decision (away from its border) and the same distorted
  // pixel to float precision. Returns how many were compared.
  int compare(const Camera& cam) {
    const glm::dvec2 origin(-0.25 * cam.width, -0.25 * cam.height);
    const glm::dvec2 step(1.5 * cam.width / kGrid, 1.5 * cam.height / kGrid);
    const Probe probe = runProbe(cam, origin, step);
    const LensDistortion& d = *cam.distortion;
    int compared = 0;
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i) {
        const glm::dvec2 p = origin + glm::dvec2(i, j) * step;
        const float* g = &probe.rgba[(size_t(j) * kGrid + i) * 4];
        const glm::dvec2 x = (p - d.center) / d.scale;
        const double margin = glm::dot(x, x) / d.r2max;
        if (std::abs(margin - 1.0) < 1e-4) continue;  // float and double may disagree on the border
        const bool inside = d.inDomain(p);
        EXPECT_EQ(g[2] > 0.5f, inside) << cam.id << " at " << p.x << "," << p.y;
        if (!inside) continue;
        const glm::dvec2 pd = d.distort(p);
        // float32 relative precision over pixel coordinates of a few thousand.
        const double tol = 2e-3 + 2e-6 * glm::length(pd);
        EXPECT_NEAR(g[0], pd.x, tol) << cam.id << " at " << p.x << "," << p.y;
        EXPECT_NEAR(g[1], pd.y, tol) << cam.id << " at " << p.x << "," << p.y;
        ++compared;
      }
    return compared;
  }
};

Camera probeCamera(const std::string& id, int w, int h, double f) {
  Camera c;
  c.id = id;
  c.width = w;
  c.height = h;
  c.focal = {f, f};
  c.principal = {0.5 * w + 3.0, 0.5 * h - 2.0};
  return c;
}

TEST_F(LensGlTest, RadialPixelPolynomial) {
  Camera c = probeCamera("radial", 2048, 2048, 1200);
  LensDistortion d;
  d.center = {1030.0, 1010.0};
  d.c3 = -2.3e-8;
  d.c5 = 1.1e-15;
  d.c7 = -3e-23;
  d.r2max = 1300.0 * 1300.0;
  c.distortion = d;
  EXPECT_GT(compare(c), 500);
}

TEST_F(LensGlTest, OpenCvRadialAndTangential) {
  Camera c = probeCamera("opencv", 1600, 1200, 1000);
  LensDistortion d;
  d.center = c.principal;
  d.scale = {1000.0, 990.0};
  d.c3 = -0.12;
  d.c5 = 0.03;
  d.c7 = -0.002;
  d.p1 = 0.0012;
  d.p2 = -0.0008;
  d.r2max = 0.9;
  c.distortion = d;
  EXPECT_GT(compare(c), 500);
}

TEST_F(LensGlTest, EquilinearFisheye) {
  Camera c = probeCamera("fisheye", 2048, 2048, 700);
  LensDistortion d;
  d.model = LensDistortion::Model::Fisheye;
  d.center = {1030.0, 1010.0};
  d.scale = {700.0, 700.0};
  d.c3 = -0.02;
  d.c5 = 0.003;
  d.c7 = -1e-4;
  d.l1 = 2e-4;
  d.l2 = -3e-4;
  d.fitDomain();
  c.distortion = d;
  EXPECT_GT(compare(c), 500);
}

}  // namespace
}  // namespace hv::render
