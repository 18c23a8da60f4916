// The photographs' images in their slots: a decoded photograph installed into a slot, a preview
// replaced in place by the full image (ibr::ImageLoader's previews), and an image replaced by a
// larger one (Renderer::replaceImage: the page's IIIF photographs, docs/services.md).
#include "hv/render/frame_builder.h"

#include "hv/util/log.h"

#include <stdexcept>
#include <string>

namespace hv::render {

// Puts a decoded photograph into a slot (a free one, else the least recently used one that this
// frame does not need) and marks its depth map dirty. A decoding error marks the photo broken,
// unless its slot shows a smaller image of it (a preview, or the image replaceImage replaces):
// that one stays, named in the error.
void FrameBuilder::install(ibr::LoadResult&& r, bool neededNow) {
  const Photo& p = scene_.photos[size_t(r.photo)];
  if (!r.ok()) {
    if (const int slot = cache_.slotOf(r.photo); slot >= 0 && slotPreview_[size_t(slot)]) {
      diag_.error(r.error + " (camera '" + p.camera.id + "' keeps the smaller image it shows)");
      if (scene_.missing) scene_.missing->add({"photograph", p.imagePath, r.error + " (the smaller image shown)"});
      slotPreview_[size_t(slot)] = false;
      return;
    }
    diag_.error(r.error + " (camera '" + p.camera.id + "' skipped)");
    if (scene_.missing) scene_.missing->add({"photograph", p.imagePath, r.error});
    photoBroken_[size_t(r.photo)] = true;
    return;
  }
  const ibr::SlotCache::Grant grant = cache_.acquire(r.photo, neededNow);
  if (!grant) return;  // every slot pinned (it will be asked for again)
  const std::string size = std::to_string(r.imageWidth) + "x" + std::to_string(r.imageHeight);
  if (!grant.isNew) {
    // Already there: the full image replaces its preview. A preview is the same image scaled
    // down uniformly, made into the same slice layout, so the projection and the depth map stay;
    // the upload redoes the slice's mip levels.
    if (!r.preview && slotPreview_[size_t(grant.slot)]) {
      backend_.uploadImage(grant.slot, r.slice);
      slotPreview_[size_t(grant.slot)] = false;
      log::debug("camera '" + p.camera.id + "': image " + size + " replaces its preview in slot " +
                 std::to_string(grant.slot));
    }
    return;
  }
  depthScheduler_.markDirty(grant.slot);
  slotFrustum_[size_t(grant.slot)] = depthFrustum(r.photo);
  backend_.uploadImage(grant.slot, r.slice);
  slotPreview_[size_t(grant.slot)] = r.preview;
  if (r.preview) log::debug("camera '" + p.camera.id + "': preview " + size + " in slot " + std::to_string(grant.slot));
  ++stats_.imagesLoaded;
}

void FrameBuilder::replaceImage(int photo) {
  if (photo < 0 || photo >= int(scene_.photos.size()))
    throw std::invalid_argument("replaceImage: photograph " + std::to_string(photo) + " out of range (" +
                                std::to_string(scene_.photos.size()) + " photographs)");
  // A decode of the image it had is not wanted any more; a photograph that could not be loaded
  // is tried again with the new one.
  loader_->cancel(photo);
  photoBroken_[size_t(photo)] = false;
  const int slot = cache_.slotOf(photo);
  // Not resident (or textured by its layers' sub-images): read from the new image when next needed.
  if (slot < 0 || layeredPhoto(photo)) return;
  // Shown as it is until the new image replaces it in place (install): the frames are not
  // converged meanwhile. Asked ahead of the frame's other decodes, the full image only.
  slotPreview_[size_t(slot)] = true;
  loader_->request(photo, scene_.photos[size_t(photo)], 0.0, false);
}

}  // namespace hv::render
