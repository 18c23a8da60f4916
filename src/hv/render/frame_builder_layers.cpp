// The frame builder's layered photographs (Layered projective texture maps, 2003, §5;
// docs/layers.md, "Rendering in the GL renderer"): a photograph given edited layers is expanded
// into its sub-images, each in an image slot of its own, with its peeled depth map uploaded.
#include "hv/render/frame_builder.h"

#include "hv/ibr/slice_image.h"
#include "hv/layers/sub_image.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace hv::render {

namespace {

// A sub-image shows when its photograph does (the time window): the photograph's date.
DateInterval photoDate(const Photo& p) {
  if (p.date.empty()) return {};
  return parseDate(p.date).value_or(DateInterval{});
}

}  // namespace

void FrameBuilder::setLayeredPhotograph(int photo, std::shared_ptr<const layers::LayeredPhotograph> layered) {
  if (photo < 0 || photo >= int(scene_.photos.size()))
    throw std::invalid_argument("layered photograph: photo index " + std::to_string(photo) + " out of range (" +
                                std::to_string(scene_.photos.size()) + " photographs)");
  if (layered)
    for (const layers::LayeredSubImage& s : layered->subImages) {
      const glm::dvec2 size = s.window.size();
      if (s.rgba.width <= 0 || s.rgba.height <= 0 || s.rgba.channels != 4 || !(size.x > 0.0) || !(size.y > 0.0) ||
          s.visibilityLayer < 1 || s.visibilityLayer > int(layered->depthMaps.size()))
        throw std::invalid_argument("layered photograph '" + scene_.photos[size_t(photo)].camera.id +
                                    "': a sub-image of layer " + std::to_string(s.visibilityLayer) +
                                    " without RGBA pixels, window or peeled depth map");
    }
  layered_[size_t(photo)] = std::move(layered);
  // Keys again for every photograph: photos.size() and up, each photograph's in blending order.
  subImages_.clear();
  for (size_t p = 0; p < scene_.photos.size(); ++p) {
    subKeys_[p].clear();
    if (!layered_[p]) continue;
    std::vector<int> order(layered_[p]->subImages.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return layered_[p]->subImages[size_t(a)].visibilityLayer < layered_[p]->subImages[size_t(b)].visibilityLayer;
    });
    for (int i : order) {
      subKeys_[p].push_back(int(scene_.photos.size() + subImages_.size()));
      subImages_.push_back({int(p), i});
    }
  }
  // The slots again (a sub-image takes one as a photograph does; the arrays are sized for what may
  // be resident), which empties them. The naive binding's units are fixed at its first allocation.
  if (naive()) {
    cache_.clear();
    depthScheduler_.markAllDirty();
  } else {
    allocateSlots();
  }
}

int FrameBuilder::layeredSlot(int photo) const {
  int first = -1;
  for (int key : subKeys_[size_t(photo)]) {
    const int slot = cache_.slotOf(key);
    if (slot < 0) return -1;
    if (first < 0) first = slot;
  }
  return first;
}

void FrameBuilder::installSubImage(int key) {
  const ibr::SlotCache::Grant grant = cache_.acquire(key, true);
  if (!grant || !grant.isNew) return;  // every slot pinned (the photograph waits), or already there
  depthScheduler_.markDirty(grant.slot);
  slotFrustum_[size_t(grant.slot)] = subImageDepthFrustum(key);
  slotPreview_[size_t(grant.slot)] = false;
  slotCut_[size_t(grant.slot)].clear();
  slotCutDrawn_[size_t(grant.slot)].clear();
  backend_.uploadImage(grant.slot, subImageSlice(key));
  ++stats_.imagesLoaded;
}

// The sheared frustum of the sub-image's window (layers::subImageFrustum) with the photograph's
// depth range.
hv::PinholeFrustum FrameBuilder::subImageDepthFrustum(int key) const {
  const SubImageRef& r = subImage(key);
  const hv::PinholeFrustum whole = depthFrustum(r.photo);
  const layers::SubImageWindow& w = layered_[size_t(r.photo)]->subImages[size_t(r.index)].window;
  return layers::subImageFrustum(photoCamera(r.photo), w, whole.near, whole.far);
}

// The sub-image stretched over the whole slice (so that the slice's uv [0, 1]^2 is the window and
// its clamp to edge is the sub-image's), premultiplied: each slice texel is the GL_LINEAR lookup
// of the sub-image's premultiplied texels at its centre (hv::layers::layeredTexel's filter).
Image8 FrameBuilder::subImageSlice(int key) const {
  const SubImageRef& r = subImage(key);
  const Image8& img = layered_[size_t(r.photo)]->subImages[size_t(r.index)].rgba;
  const int w = layout_.slice.width, h = layout_.slice.height;
  Image8 out(w, h, 4);
  auto texel = [&](int x, int y) {
    x = std::clamp(x, 0, img.width - 1);
    y = std::clamp(y, 0, img.height - 1);
    const double a = img.at(x, y, 3) / 255.0;
    return glm::dvec4(a * img.at(x, y, 0) / 255.0, a * img.at(x, y, 1) / 255.0, a * img.at(x, y, 2) / 255.0, a);
  };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const double fx = (x + 0.5) / w * img.width - 0.5, fy = (y + 0.5) / h * img.height - 0.5;
      const double x0 = std::floor(fx), y0 = std::floor(fy), tx = fx - x0, ty = fy - y0;
      const int ix = int(x0), iy = int(y0);
      const glm::dvec4 v = glm::mix(glm::mix(texel(ix, iy), texel(ix + 1, iy), tx),
                                    glm::mix(texel(ix, iy + 1), texel(ix + 1, iy + 1), tx), ty);
      for (int c = 0; c < 4; ++c) out.at(x, y, c) = std::uint8_t(std::lround(std::clamp(v[c], 0.0, 1.0) * 255.0));
    }
  return out;
}

// D_k of the sub-image's layer in the depth maps' encoding over its frustum: at each texel centre
// (ideal pixel p), the distance D_k gives at distort(p) (bilinear over its texels that hold a
// surface, texel centres at i + 0.5), turned into depth along the axis (the distance over the
// length of K^-1 (p, 1)), then (z - near) / (far - near); 1 where D_k holds no surface.
std::vector<float> FrameBuilder::subImageDepth(int key, const hv::PinholeFrustum& fr) const {
  const SubImageRef& r = subImage(key);
  const layers::LayeredPhotograph& L = *layered_[size_t(r.photo)];
  const layers::PeeledDepthMap& d = L.depthMaps[size_t(L.subImages[size_t(r.index)].visibilityLayer - 1)];
  const Camera cam = photoCamera(r.photo);
  const glm::dmat3 camFromPix = cam.camFromPix();
  const int n = layout_.depthSize;
  const float belowOne = std::nextafter(1.0f, 0.0f);
  std::vector<float> out(size_t(n) * size_t(n), 1.0f);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const glm::dvec2 p = fr.pxMin + (glm::dvec2(i, j) + 0.5) / double(n) * (fr.pxMax - fr.pxMin);
      const glm::dvec2 pd = cam.distort(p);
      const double fx = pd.x * d.width / cam.width - 0.5, fy = pd.y * d.height / cam.height - 0.5;
      if (fx < -0.5 || fy < -0.5 || fx > d.width - 0.5 || fy > d.height - 0.5) continue;
      const int x0 = int(std::floor(fx)), y0 = int(std::floor(fy));
      const double tx = fx - x0, ty = fy - y0;
      double sum = 0.0, weight = 0.0;
      for (int dy = 0; dy <= 1; ++dy)
        for (int dx = 0; dx <= 1; ++dx) {
          const int x = std::clamp(x0 + dx, 0, d.width - 1), y = std::clamp(y0 + dy, 0, d.height - 1);
          const double v = d.distance[size_t(y) * size_t(d.width) + size_t(x)];
          const double wgt = (dx ? tx : 1.0 - tx) * (dy ? ty : 1.0 - ty);
          if (!std::isfinite(v) || wgt <= 0.0) continue;
          sum += wgt * v;
          weight += wgt;
        }
      if (weight <= 0.0) continue;
      const double z = (sum / weight) / glm::length(camFromPix * glm::dvec3(p, 1.0));
      out[size_t(j) * size_t(n) + size_t(i)] = std::clamp(float((z - fr.near) / (fr.far - fr.near)), 0.0f, belowOne);
    }
  return out;
}

// A layered photograph's rows: its sub-images, consecutive, each with its window's uv offset and
// scale, its layer and the photograph's group, the photograph's weight, date and colour; the
// tolerance of the two-sided depth test in the bias terms. Every sub-image resident with its map
// current, or the photograph waits.
void FrameBuilder::packLayered(Frame& f, const ibr::SelectedImage& selected) {
  const int photo = selected.photo;
  const layers::LayeredPhotograph& L = *layered_[size_t(photo)];
  bool decoding = false, pending = false;
  for (int key : subKeys_[size_t(photo)]) {
    const int slot = cache_.slotOf(key);
    decoding = decoding || slot < 0;
    pending = pending || (slot >= 0 && depthScheduler_.isDirty(slot));
  }
  if (decoding || pending) {
    ++stats_.imagesWaiting;
    ++(decoding ? stats_.decodesWaiting : stats_.depthMapsWaiting);
    return;
  }
  const Camera cam = photoCamera(photo);
  for (int key : subKeys_[size_t(photo)]) {
    const int slot = cache_.slotOf(key);
    const layers::LayeredSubImage& sub = L.subImages[size_t(subImage(key).index)];
    ibr::SliceLayout layout;
    layout.slice = slot;
    layout.uvScale = 1.0 / sub.window.size();
    const ibr::DepthBias tolerance{L.tolerance.metres, L.tolerance.relative};
    params_.push_back(
        ibr::makeImageParams(cam, scene_.origin, layout, selected.weight, slotFrustum_[size_t(slot)], tolerance));
    ibr::ImageParams& im = params_.back();
    im.photo = photo;
    im.date = photoDate(scene_.photos[size_t(photo)]);
    if (settings_.blend.colourCorrection) im.colour = scene_.photos[size_t(photo)].colour;
    im.uvOffset = sub.window.pxMin;
    im.layer = sub.visibilityLayer;
    im.group = photo + 1;
    f.packedParams.resize(f.packedParams.size() + ibr::kTexelsPerImage * 4);
    ibr::packImageParams(im, f.packedParams.data() + f.packedParams.size() - ibr::kTexelsPerImage * 4);
  }
}

}  // namespace hv::render
