#include "web_services.h"

#include "hv/io/iiif.h"
#include "hv/util/diagnostics.h"
#include "hv/util/image_sizes.h"
#include "hv/util/input_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <string_view>
#include <vector>

namespace hv::web {

using json = nlohmann::json;

namespace {

std::string gRoot = "/scene/";  // the page's file system root (installPageRemoteReader)

std::string readPut(const std::string& url, std::uint64_t maxBytes, const std::string& what, RemoteCache) {
  const std::string file = remoteFilePath(gRoot, url);
  if (!isRegularFile(file)) throw InputError(inputMessage(url, what, "not fetched by the page (yet)"));
  const std::vector<std::uint8_t> bytes = readInputBytes(file, maxBytes, what);
  return std::string(bytes.begin(), bytes.end());
}

// The full request of a photograph read from its preview (iiifPlan), by its camera's id and the
// preview's URL.
std::map<std::string, std::string>& fullOfPreview() {
  static std::map<std::string, std::string> m;
  return m;
}

json sized(const IiifRequest& r) { return {{"url", r.url}, {"width", r.width}, {"height", r.height}}; }

}  // namespace

std::string remoteFilePath(const std::string& root, const std::string& url) {
  std::string out = root + "remote/";
  for (const unsigned char c : url) {
    if (std::isalnum(c) || std::string_view("-_.!~*'()").find(char(c)) != std::string_view::npos) {
      out += char(c);
    } else {
      char hex[4];
      std::snprintf(hex, sizeof hex, "%%%02X", c);
      out += hex;
    }
  }
  return out;
}

void installPageRemoteReader(const std::string& root) {
  gRoot = root;
  setRemoteReader(&readPut);
}

std::string iiifPlan(Photo& photo, const std::string& infoText, const std::string& url) {
  const Camera& camera = photo.camera;
  try {
    const IiifImageInfo info = parseIiifInfo(infoText, url);
    if (const std::string why = iiifSizeMismatch(info, camera.width, camera.height); !why.empty())
      throw InputError(inputMessage(url, "", why));
    const IiifRequest full = iiifRequest(info, camera.width);
    // As the native loader (hv/io/native/scene_loader.cpp): a preview near the full size would
    // save nothing.
    const int box = std::min(kIiifPreviewBox, std::max(1, std::max(camera.width, camera.height) / 4));
    const IiifRequest preview = iiifPreviewRequest(info, box);
    // The image at the camera's width, whatever the slice asks: the page fetched that one.
    ImageSizes sizes;
    if (preview.width < full.width) sizes.preview = {preview.url, preview.width, preview.height};
    sizes.atWidth = [full](int) { return SizedImageUrl{full.url, full.width, full.height}; };
    registerImageSizes(full.url, std::move(sizes));
    photo.imagePath = full.url;
    if (preview.width < full.width) {
      // Joins with the preview, read as the photograph's image until iiifFullArrived.
      photo.imagePath = preview.url;
      fullOfPreview()[camera.id + "\n" + preview.url] = full.url;
    }
    return json{{"full", sized(full)}, {"preview", preview.width < full.width ? sized(preview) : json(nullptr)}}.dump();
  } catch (const std::exception& e) {
    return json{{"error", e.what()}}.dump();
  }
}

bool iiifFullArrived(Photo& photo) {
  const auto it = fullOfPreview().find(photo.camera.id + "\n" + photo.imagePath);
  if (it == fullOfPreview().end()) return false;
  photo.imagePath = it->second;
  return true;
}

}  // namespace hv::web
