#include "hv/gpu/present.h"

#include <algorithm>
#include <stdexcept>

namespace hv::gpu {

namespace {

Image8 toRgba(const Image8& image) {
  if (image.channels == 4) return image;
  if (image.channels != 3) throw std::invalid_argument("expected an RGB or RGBA image");
  Image8 out(image.width, image.height, 4, 255);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) out.at(x, y, c) = image.at(x, y, c);
  return out;
}

void uploadRgba(Texture& texture, glm::ivec2& size, const Image8& image) {
  const Image8 rgba = toRgba(image);
  if (!texture || size != glm::ivec2(rgba.width, rgba.height)) {
    texture = makeTexture();
    glBindTexture(GL_TEXTURE_2D, texture.id());
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, rgba.width, rgba.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    size = {rgba.width, rgba.height};
  }
  glBindTexture(GL_TEXTURE_2D, texture.id());
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, rgba.width, rgba.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data.data());
  glBindTexture(GL_TEXTURE_2D, 0);
  checkGlError("image upload");
}

}  // namespace

Presenter::Presenter() : readFbo_(makeFramebuffer()) {}

void Presenter::blitFlipped(GLuint texture, glm::ivec2 srcSize, glm::ivec2 dstSize) {
  GLint draw = 0;
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, readFbo_.id());
  glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  if (glCheckFramebufferStatus(GL_READ_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("presenting a frame: the colour texture cannot be read");
  // Destination rows swapped: the texture's first row (the picture's top) lands at the top.
  const GLenum filter = srcSize == dstSize ? GL_NEAREST : GL_LINEAR;
  glBlitFramebuffer(0, 0, srcSize.x, srcSize.y, 0, dstSize.y, dstSize.x, 0, GL_COLOR_BUFFER_BIT, filter);
  glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, 0, 0);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, GLuint(draw));
  checkGlError("present");
}

void Presenter::presentImage(const Image8& image, glm::ivec2 dstSize) {
  uploadRgba(upload_, uploadSize_, image);
  blitFlipped(upload_.id(), uploadSize_, dstSize);
}

void ImageTexture::upload(const Image8& image) { uploadRgba(texture_, size_, image); }

Image8 readFramebufferFlipped(glm::ivec2 size) {
  Image8 rgba(size.x, size.y, 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, size.x, size.y, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data.data());
  checkGlError("framebuffer readback");
  Image8 rgb(size.x, size.y, 3);
  for (int y = 0; y < size.y; ++y)
    for (int x = 0; x < size.x; ++x)
      for (int c = 0; c < 3; ++c) rgb.at(x, y, c) = rgba.at(x, size.y - 1 - y, c);
  return rgb;
}

}  // namespace hv::gpu
