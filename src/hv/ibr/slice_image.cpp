#include "hv/ibr/slice_image.h"

#include "hv/util/diagnostics.h"

#include <algorithm>
#include <cmath>

namespace hv::ibr {

namespace {
double fitScale(const Camera& cam, SliceSize s) {
  return std::min({1.0, double(s.width) / cam.width, double(s.height) / cam.height});
}
int scaledExtent(int n, double s) { return std::max(1, int(std::lround(n * s))); }
}  // namespace

SliceLayout sliceLayout(const Camera& cam, SliceSize s, int sliceIndex) {
  const double scale = fitScale(cam, s);
  const int w = scaledExtent(cam.width, scale), h = scaledExtent(cam.height, scale);
  SliceLayout l;
  l.slice = sliceIndex;
  // pixel p_d in [0, W] -> texel p_d * w / W in [0, w] -> uv = that / slice width.
  l.uvScale = {double(w) / cam.width / s.width, double(h) / cam.height / s.height};
  return l;
}

Image8 makeSliceImage(const Camera& cam, const Image8& photo, const Image8& mask, SliceSize s,
                      const std::string& name) {
  const double aspectCam = double(cam.width) / cam.height, aspectImg = double(photo.width) / photo.height;
  if (std::abs(aspectCam - aspectImg) > 0.01 * aspectCam)
    throw InputError(name + ": image is " + std::to_string(photo.width) + "x" + std::to_string(photo.height) +
                     ", expected the camera's " + std::to_string(cam.width) + "x" + std::to_string(cam.height) +
                     " (or the same aspect ratio)");
  const double scale = fitScale(cam, s);
  const int w = scaledExtent(cam.width, scale), h = scaledExtent(cam.height, scale);
  const Image8 colour = (photo.width == w && photo.height == h) ? photo : resizeImage(photo, w, h);
  Image8 alpha;
  if (!mask.empty()) {
    if (std::abs(double(mask.width) / mask.height - aspectCam) > 0.01 * aspectCam)
      throw InputError(name + ": mask is " + std::to_string(mask.width) + "x" + std::to_string(mask.height) +
                       ", expected the image's aspect ratio");
    alpha = (mask.width == w && mask.height == h) ? mask : resizeImage(mask, w, h);
  }
  Image8 out(s.width, s.height, 4, 0);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::uint8_t* c = colour.px(x, y);
      int a = colour.channels == 4 ? c[3] : 255;
      if (!alpha.empty()) a = (a * (alpha.at(x, y, 0) > 0 ? 255 : 0)) / 255;  // 0 = discard, >0 = keep
      std::uint8_t* o = out.px(x, y);
      for (int k = 0; k < 3; ++k) {
        const int v = colour.channels >= 3 ? c[k] : c[0];
        o[k] = std::uint8_t((v * a + 127) / 255);
      }
      o[3] = std::uint8_t(a);
    }
  }
  return out;
}

int mipLevelCount(int w, int h) {
  int levels = 1;
  for (int s = std::max(w, h); s > 1; s /= 2) ++levels;
  return levels;
}

std::size_t mipChainBytes(int w, int h) {
  std::size_t bytes = 0;
  for (int l = 0; l < mipLevelCount(w, h); ++l)
    bytes += std::size_t(std::max(1, w >> l)) * std::size_t(std::max(1, h >> l)) * 4;
  return bytes;
}

std::vector<Image8> sliceMipChain(const Image8& slice) {
  std::vector<Image8> chain;
  chain.push_back(slice);
  const int levels = mipLevelCount(slice.width, slice.height);
  for (int l = 1; l < levels; ++l) {
    const Image8& a = chain.back();
    Image8 b;
    b.width = std::max(1, a.width / 2);
    b.height = std::max(1, a.height / 2);
    b.channels = a.channels;
    b.data.assign(size_t(b.width) * b.height * b.channels, 0);
    for (int y = 0; y < b.height; ++y)
      for (int x = 0; x < b.width; ++x)
        for (int c = 0; c < b.channels; ++c) {
          int sum = 0;
          for (int dy = 0; dy < 2; ++dy)
            for (int dx = 0; dx < 2; ++dx)
              sum += a.at(std::min(2 * x + dx, a.width - 1), std::min(2 * y + dy, a.height - 1), c);
          b.data[(size_t(y) * b.width + x) * b.channels + c] = std::uint8_t((sum + 2) / 4);
        }
    chain.push_back(std::move(b));
  }
  return chain;
}

}  // namespace hv::ibr
