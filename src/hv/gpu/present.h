// Putting offscreen pictures on a window's framebuffer (the viewer). Offscreen targets and
// hv::Image rows are stored top row first (docs/conventions.md); a window's framebuffer is read
// and written bottom row first, so both directions flip here, and only here.
#pragma once

#include "hv/gpu/gl.h"
#include "hv/image/image.h"

#include <glm/glm.hpp>

namespace hv::gpu {

class Presenter {
 public:
  Presenter();
  // Copies the RGBA8 `texture` (srcSize, top row first) onto [0, dstSize) of the bound draw
  // framebuffer, flipped so the picture stands upright in a window; linear filtering when the
  // sizes differ.
  void blitFlipped(GLuint texture, glm::ivec2 srcSize, glm::ivec2 dstSize);
  // Uploads an RGB or RGBA image (top row first) and blits it the same way.
  void presentImage(const Image8& image, glm::ivec2 dstSize);

 private:
  Framebuffer readFbo_;
  Texture upload_;
  glm::ivec2 uploadSize_{0};
};

// An RGBA8 texture holding an image (e.g. a thumbnail for the UI), rows as given.
class ImageTexture {
 public:
  void upload(const Image8& image);  // RGB or RGBA
  GLuint id() const { return texture_.id(); }
  glm::ivec2 size() const { return size_; }

 private:
  Texture texture_;
  glm::ivec2 size_{0};
};

// The bound read framebuffer's [0, size) as RGB, top row first (flipped from GL's bottom-up rows).
Image8 readFramebufferFlipped(glm::ivec2 size);

}  // namespace hv::gpu
