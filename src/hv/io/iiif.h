// Photographs from a IIIF Image API service (docs/services.md, "Photographs by URL and IIIF"):
// a camera's "image" names the service's description, "https://host/prefix/identifier/info.json"
// (Image API 2 or 3), and histoview asks the service for a small preview first, then for the
// photograph at the size the renderer's image slot needs. Parsing and request building only; the
// fetching is native (hv/io/native/remote.h) and the image loader's (hv/ibr/image_loader.h).
//
// Conventions: sizes are in pixels, width then height; "the full image" is the region `full`, the
// whole image as the service holds it (info.json's width x height). Requests are made against the
// URL the description was read from (its folder), not against the description's `id`: a service
// behind a proxy or reached by another host name often writes an `id` the client cannot reach.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace hv {

struct IiifImageInfo {
  int version = 0;   // 2 or 3
  std::string base;  // the URL the description was read from, without "/info.json" (and fragment)
  std::string id;    // the description's own "id" (3) or "@id" (2), for messages
  int width = 0, height = 0;
  std::vector<std::pair<int, int>> sizes;  // "sizes": the sizes a level-0 service offers
  // "tiles": the tile sizes and their scale factors. A level-0 service also serves, whole, the
  // image at a scale factor s whose single tile covers it (ceil(width / s) x ceil(height / s)).
  struct Tiles {
    int width = 0, height = 0;  // height: the width when not given
    std::vector<int> scaleFactors;
  };
  std::vector<Tiles> tiles;
  bool level0 = false;              // compliance level 0: only the listed sizes (and the full size)
  int maxWidth = 0, maxHeight = 0;  // 0: no limit
  long long maxArea = 0;            // 0: no limit
};

struct IiifRequest {
  std::string url;
  int width = 0, height = 0;  // the size asked for (the service may round a level-0 size)
};

// True for an http(s):// URL that ends in "/info.json" (its path, or its query as in iipsrv's
// "…/iipsrv.fcgi?IIIF=/photo.tif/info.json"; a fragment is ignored): a IIIF image service.
bool isIiifInfoUrl(const std::string& url);

// Reads an info.json of the Image API 2 or 3 (`url`: where it was read from, for the base and the
// messages). Throws InputError naming the URL and the field: not JSON, not a IIIF image
// description (no IIIF context), no positive width or height.
IiifImageInfo parseIiifInfo(const std::string& text, const std::string& url);

// "" when the service's image can texture a camera of `cameraWidth` x `cameraHeight` pixels (the
// same aspect ratio within 1%, the image loader's tolerance), else why not.
std::string iiifSizeMismatch(const IiifImageInfo& info, int cameraWidth, int cameraHeight);

// The request for the whole image at most `wantWidth` pixels wide, aspect ratio kept: no larger
// than the full image or the service's maxWidth/maxHeight/maxArea. A level-0 service gets the
// smallest size it serves (iiifLevel0Sizes) at least `wantWidth` wide, else the full size ("max" /
// "full") when its limits allow it, else the largest size it serves.
// The format is JPEG ("default.jpg"), the only one every level offers.
IiifRequest iiifRequest(const IiifImageInfo& info, int wantWidth);

// The sizes a level-0 service serves whole, sorted by width: the listed `sizes`, and the image at
// each scale factor s > 1 whose single tile covers it (ceil(width / s) x ceil(height / s)). The
// full size is always served ("max" / "full") and is not added here.
std::vector<std::pair<int, int>> iiifLevel0Sizes(const IiifImageInfo& info);

// The side of the box a preview fits in (pixels): the small image shown first.
inline constexpr int kIiifPreviewBox = 256;

// The preview: the image fitted in `box` x `box` (aspect ratio kept; at most the full size), asked
// as iiifRequest does, so a level-0 service gets its smallest served size at least that wide and
// the service's limits hold. Its width is the full width when the service serves nothing smaller
// (then there is no preview worth fetching).
IiifRequest iiifPreviewRequest(const IiifImageInfo& info, int box = kIiifPreviewBox);

}  // namespace hv
