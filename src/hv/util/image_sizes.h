// Photographs a server offers at several sizes (a IIIF image service; docs/services.md,
// "Photographs by URL and IIIF"). The scene loader registers, under the URL a photograph is read
// from (Photo::imagePath), a small preview and the URL of the image at any width; the renderer's
// image loader (hv/ibr/image_loader.h) then fetches the preview first, shows it, and replaces it
// with the image at the width its slot needs. Other readers of the photograph (evaluation,
// harmonisation) read Photo::imagePath as it is. Process-wide and thread-safe.
//
// Also the counts of photograph bytes the image loader read, previews and full images apart
// (`histoview render`, `fly` and `eval` print them; docs/services.md).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>

namespace hv {

struct SizedImageUrl {
  std::string url;
  int width = 0, height = 0;  // what the server is asked for
};

struct ImageSizes {
  SizedImageUrl preview;  // fetched first; url "" when there is none
  // The image at least `width` pixels wide where the server serves that, never larger than its full
  // size or the server's limits.
  std::function<SizedImageUrl(int width)> atWidth;
};

// Registers (or replaces) the sizes of the photograph read from `url`.
void registerImageSizes(const std::string& url, ImageSizes sizes);
// The sizes registered for `url`; null when the photograph is read as it is.
std::shared_ptr<const ImageSizes> imageSizes(const std::string& url);
void clearImageSizes();

// Photograph responses the image loader read (from the server or the response cache): how many
// and their bytes, previews apart from the images shown once converged.
struct ImageFetchCounts {
  std::uint64_t previews = 0, previewBytes = 0;
  std::uint64_t images = 0, imageBytes = 0;
};
void countImageFetch(bool preview, std::uint64_t bytes);
ImageFetchCounts imageFetchCounts();
void resetImageFetchCounts();

}  // namespace hv
