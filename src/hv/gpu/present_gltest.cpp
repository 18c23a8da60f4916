// GL tests of hv::gpu::Presenter: a picture stored top row first comes out of a window-like
// framebuffer (rows bottom-up) upright.
#include "hv/gpu/present.h"

#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

namespace hv::gpu {
namespace {

TEST(PresenterGlTest, BlitFlipsAndReadbackFlipsBack) {
  hv::testing::glContext();
  clearGlErrors();
  const int w = 37, h = 23;  // odd sizes: a flip off by one row shows
  const Image8 picture = hv::testing::patternImage(w, h, 5);
  ImageTexture source;
  source.upload(picture);
  // A stand-in for the window: an RGBA8 framebuffer, bound for drawing and reading.
  Texture target = makeTexture();
  glBindTexture(GL_TEXTURE_2D, target.id());
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  Framebuffer window = makeFramebuffer();
  glBindFramebuffer(GL_FRAMEBUFFER, window.id());
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target.id(), 0);
  checkFramebuffer("test window");
  Presenter presenter;
  presenter.blitFlipped(source.id(), {w, h}, {w, h});
  // GL's first row is the window's bottom: it must hold the picture's last row.
  Image8 raw(w, h, 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, raw.data.data());
  for (int x = 0; x < w; ++x)
    for (int c = 0; c < 3; ++c) ASSERT_EQ(raw.at(x, 0, c), picture.at(x, h - 1, c)) << "x " << x;
  EXPECT_EQ(readFramebufferFlipped({w, h}).data, picture.data);
  // The same through presentImage (upload + blit).
  glClearColor(0, 0, 0, 0);
  glClear(GL_COLOR_BUFFER_BIT);
  presenter.presentImage(picture, {w, h});
  EXPECT_EQ(readFramebufferFlipped({w, h}).data, picture.data);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

}  // namespace
}  // namespace hv::gpu
