#include "hv/util/image_sizes.h"

#include <map>
#include <mutex>

namespace hv {

namespace {

std::mutex gMutex;
std::map<std::string, std::shared_ptr<const ImageSizes>>& registry() {
  static std::map<std::string, std::shared_ptr<const ImageSizes>> r;
  return r;
}
ImageFetchCounts gCounts;

}  // namespace

void registerImageSizes(const std::string& url, ImageSizes sizes) {
  auto shared = std::make_shared<const ImageSizes>(std::move(sizes));
  std::lock_guard lock(gMutex);
  registry()[url] = std::move(shared);
}

std::shared_ptr<const ImageSizes> imageSizes(const std::string& url) {
  std::lock_guard lock(gMutex);
  const auto it = registry().find(url);
  return it == registry().end() ? nullptr : it->second;
}

void clearImageSizes() {
  std::lock_guard lock(gMutex);
  registry().clear();
}

void countImageFetch(bool preview, std::uint64_t bytes) {
  std::lock_guard lock(gMutex);
  if (preview) {
    ++gCounts.previews;
    gCounts.previewBytes += bytes;
  } else {
    ++gCounts.images;
    gCounts.imageBytes += bytes;
  }
}

ImageFetchCounts imageFetchCounts() {
  std::lock_guard lock(gMutex);
  return gCounts;
}

void resetImageFetchCounts() {
  std::lock_guard lock(gMutex);
  gCounts = {};
}

}  // namespace hv
