// GL tests of Renderer::colorTexture() and RenderSettings::readBackColour: what a window presents
// without a CPU readback is the same picture that render() returns.
#include "hv/render/renderer.h"

#include "hv/render/testing/gl_test_support.h"
#include "hv/image/native/png_write.h"

#include <gtest/gtest.h>

namespace hv::render {
namespace {

using testing::glContext;
using testing::kStreetOrigin;

// Reads an RGBA8 texture back through a framebuffer (rows as stored: top row first).
Image8 readTexture(GLuint texture, int w, int h) {
  gpu::Framebuffer fbo = gpu::makeFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, fbo.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  gpu::checkFramebuffer("colour texture readback");
  Image8 img(w, h, 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, img.data.data());
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return img;
}

class ColorTextureGlTest : public ::testing::Test {
 protected:
  void SetUp() override {
    glContext();
    gpu::clearGlErrors();
    dir_ = testing::makeTempDir("color-texture");
    scene_ = testing::streetScene();
    const glm::dvec3 o = kStreetOrigin;
    const Camera a = testing::lookAt("a", o + glm::dvec3(-6, -12, 2), o + glm::dvec3(0, 30, 8), 160, 120, 130);
    const Camera b = testing::lookAt("b", o + glm::dvec3(5, -10, 2), o + glm::dvec3(0, 30, 8), 160, 120, 130);
    for (const Camera* c : {&a, &b}) {
      Photo p;
      p.camera = *c;
      p.imagePath = dir_ + "/" + c->id + ".png";
      writePng(p.imagePath, testing::patternImage(160, 120, int(scene_.photos.size()) + 1));
      scene_.photos.push_back(p);
    }
    view_ = testing::lookAt("v", o + glm::dvec3(0, -11, 1.8), o + glm::dvec3(0, 30, 8), 96, 72, 80);
  }
  void TearDown() override { EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR)) << "a GL error was left behind"; }

  static RenderSettings settings() {
    RenderSettings s;
    s.blend.k = 2;  // both photographs
    return s;
  }

  std::string dir_;
  Scene scene_;
  Camera view_;
};

TEST_F(ColorTextureGlTest, NoTextureBeforeTheFirstFrame) {
  Diagnostics diag;
  Renderer r(scene_, settings(), diag);
  EXPECT_EQ(r.colorTexture(), 0u);
}

TEST_F(ColorTextureGlTest, TextureHoldsTheColourThatRenderReturns) {
  Diagnostics diag;
  Renderer r(scene_, settings(), diag);
  const RenderOutput out = r.render(view_);
  ASSERT_NE(r.colorTexture(), 0u);
  EXPECT_EQ(readTexture(r.colorTexture(), view_.width, view_.height).data, out.rgba.data);
}

TEST_F(ColorTextureGlTest, CountsDoNotOverwriteTheColour) {
  // The debug passes share the colour target; it must end the frame holding the colour.
  Diagnostics diag;
  Renderer r(scene_, settings(), diag);
  const RenderOutput out = r.render(view_, true);
  ASSERT_FALSE(out.counts.empty());
  EXPECT_EQ(readTexture(r.colorTexture(), view_.width, view_.height).data, out.rgba.data);
}

TEST_F(ColorTextureGlTest, WithoutReadbackTheColourStaysInTheTexture) {
  Diagnostics diag;
  Renderer withReadback(scene_, settings(), diag);
  const Image8 expected = withReadback.render(view_).rgba;
  RenderSettings s = settings();
  s.readBackColour = false;
  Renderer r(scene_, s, diag);
  const RenderOutput out = r.render(view_, true);
  EXPECT_TRUE(out.rgba.empty());
  EXPECT_FALSE(out.counts.empty()) << "counts are read back whatever readBackColour says";
  EXPECT_EQ(readTexture(r.colorTexture(), view_.width, view_.height).data, expected.data);
  EXPECT_TRUE(diag.ok());
}

}  // namespace
}  // namespace hv::render
