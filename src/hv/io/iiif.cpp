#include "hv/io/iiif.h"

#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace hv {

namespace {

using json = nlohmann::json;

constexpr const char* kInfo = "/info.json";

// The URL without its fragment. "/info.json" may end the path or the query (iipsrv's
// "/fcgi-bin/iipsrv.fcgi?IIIF=/image.tif/info.json").
std::string withoutFragment(const std::string& url) { return url.substr(0, url.find('#')); }

bool mentions(const json& v, const std::string& what) {
  if (v.is_string()) return v.get<std::string>().find(what) != std::string::npos;
  if (v.is_array()) return std::any_of(v.begin(), v.end(), [&](const json& e) { return mentions(e, what); });
  return false;
}

int positiveInt(const json& j, const char* key, const std::string& url, bool required) {
  if (!j.contains(key)) {
    if (required) throw InputError(inputMessage(url, key, "missing (expected a positive integer)"));
    return 0;
  }
  const json& v = j[key];
  if (!v.is_number_integer() || v.get<long long>() <= 0 || v.get<long long>() > std::numeric_limits<int>::max())
    throw InputError(inputMessage(url, key, "expected a positive integer, got " + v.dump()));
  return v.get<int>();
}

}  // namespace

bool isIiifInfoUrl(const std::string& url) {
  if (!isHttpUrl(url)) return false;
  const std::string u = withoutFragment(url);
  const std::size_t n = std::char_traits<char>::length(kInfo);
  return u.size() > n && u.compare(u.size() - n, n, kInfo) == 0;
}

IiifImageInfo parseIiifInfo(const std::string& text, const std::string& url) {
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    throw InputError(inputMessage(url, "", std::string("not a IIIF image description (not JSON: ") + e.what() + ")"));
  }
  if (!j.is_object()) throw InputError(inputMessage(url, "", "not a IIIF image description (expected a JSON object)"));
  IiifImageInfo info;
  const json context = j.contains("@context") ? j["@context"] : json();
  if (mentions(context, "iiif.io/api/image/3"))
    info.version = 3;
  else if (mentions(context, "iiif.io/api/image/2"))
    info.version = 2;
  else
    throw InputError(inputMessage(url, "@context",
                                  "expected the IIIF Image API 2 or 3 context "
                                  "(\"http://iiif.io/api/image/3/context.json\"), got " +
                                      (context.is_null() ? std::string("none") : context.dump())));
  const char* idKey = info.version == 3 ? "id" : "@id";
  if (j.contains(idKey) && j[idKey].is_string()) info.id = j[idKey].get<std::string>();
  const std::string u = withoutFragment(url);
  info.base = isIiifInfoUrl(url) ? u.substr(0, u.size() - std::char_traits<char>::length(kInfo)) : u;
  info.width = positiveInt(j, "width", url, true);
  info.height = positiveInt(j, "height", url, true);
  // The limits are top-level in the Image API 3, in the profile's description object in 2.
  const auto limits = [&](const json& o, const std::string& where) {
    if (int v = positiveInt(o, "maxWidth", where, false)) info.maxWidth = v;
    if (int v = positiveInt(o, "maxHeight", where, false)) info.maxHeight = v;
    if (o.contains("maxArea")) {
      if (!o["maxArea"].is_number_integer() || o["maxArea"].get<long long>() <= 0)
        throw InputError(inputMessage(where, "maxArea", "expected a positive integer, got " + o["maxArea"].dump()));
      info.maxArea = o["maxArea"].get<long long>();
    }
  };
  limits(j, url);
  if (info.version == 2 && j.contains("profile") && j["profile"].is_array())
    for (const json& o : j["profile"])
      if (o.is_object()) limits(o, url + ": profile");
  if (j.contains("sizes")) {
    if (!j["sizes"].is_array()) throw InputError(inputMessage(url, "sizes", "expected an array of {width, height}"));
    for (const json& s : j["sizes"]) {
      if (!s.is_object()) throw InputError(inputMessage(url, "sizes", "expected objects {width, height}"));
      info.sizes.emplace_back(positiveInt(s, "width", url + ": sizes", true),
                              positiveInt(s, "height", url + ": sizes", true));
    }
    std::sort(info.sizes.begin(), info.sizes.end());
  }
  if (j.contains("tiles")) {
    const std::string where = url + ": tiles";
    if (!j["tiles"].is_array())
      throw InputError(inputMessage(url, "tiles", "expected an array of {width, scaleFactors}"));
    for (const json& t : j["tiles"]) {
      if (!t.is_object()) throw InputError(inputMessage(url, "tiles", "expected objects {width, scaleFactors}"));
      IiifImageInfo::Tiles tiles;
      tiles.width = positiveInt(t, "width", where, true);
      tiles.height = positiveInt(t, "height", where, false);
      if (tiles.height == 0) tiles.height = tiles.width;
      if (!t.contains("scaleFactors") || !t["scaleFactors"].is_array())
        throw InputError(inputMessage(where, "scaleFactors", "expected an array of positive integers"));
      for (const json& f : t["scaleFactors"]) {
        if (!f.is_number_integer() || f.get<long long>() <= 0 || f.get<long long>() > std::numeric_limits<int>::max())
          throw InputError(inputMessage(where, "scaleFactors", "expected positive integers, got " + f.dump()));
        tiles.scaleFactors.push_back(f.get<int>());
      }
      info.tiles.push_back(std::move(tiles));
    }
  }
  const json profile = j.contains("profile") ? j["profile"] : json();
  info.level0 = mentions(profile, "level0");
  return info;
}

std::string iiifSizeMismatch(const IiifImageInfo& info, int cameraWidth, int cameraHeight) {
  if (cameraWidth <= 0 || cameraHeight <= 0) return "the camera has no image size";
  const double aspect = double(cameraWidth) / cameraHeight;
  if (std::abs(double(info.width) / info.height - aspect) <= 0.01 * aspect) return "";
  return "the IIIF image is " + std::to_string(info.width) + "x" + std::to_string(info.height) +
         ", the camera's image " + std::to_string(cameraWidth) + "x" + std::to_string(cameraHeight) +
         ": the aspect ratios disagree (expected the same within 1%)";
}

std::vector<std::pair<int, int>> iiifLevel0Sizes(const IiifImageInfo& info) {
  std::vector<std::pair<int, int>> sizes = info.sizes;
  const auto up = [](int n, int s) { return int((static_cast<long long>(n) + s - 1) / s); };
  for (const IiifImageInfo::Tiles& t : info.tiles)
    for (int s : t.scaleFactors)
      // One tile covers the image at this scale: the tile request of its region `full` is the whole
      // image at ceil(width / s) x ceil(height / s). Scale factor 1 is the full size itself.
      if (s > 1 && static_cast<long long>(t.width) * s >= info.width &&
          static_cast<long long>(t.height) * s >= info.height)
        sizes.emplace_back(up(info.width, s), up(info.height, s));
  std::sort(sizes.begin(), sizes.end());
  sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
  return sizes;
}

IiifRequest iiifPreviewRequest(const IiifImageInfo& info, int box) {
  box = std::max(box, 1);
  // The image fitted in box x box: the longer side is `box` (never more than the full size).
  const int w = info.width >= info.height
                    ? std::min(box, info.width)
                    : std::max(1, int(std::lround(double(std::min(box, info.height)) * info.width / info.height)));
  return iiifRequest(info, w);
}

IiifRequest iiifRequest(const IiifImageInfo& info, int wantWidth) {
  const std::string region = info.base + "/full/";
  const std::string tail = "/0/default.jpg";
  IiifRequest r;
  const auto heightOf = [&](int w) { return std::max(1, int(std::lround(double(w) * info.height / info.width))); };
  if (info.level0) {
    // Only the sizes of iiifLevel0Sizes are served, and the full size ("max" / "full"), which the
    // service's limits may shrink: past the largest size that fits, the full size when the limits
    // allow it, else the largest size served.
    const std::vector<std::pair<int, int>> sizes = iiifLevel0Sizes(info);
    const auto fits =
        std::find_if(sizes.begin(), sizes.end(), [&](const std::pair<int, int>& s) { return s.first >= wantWidth; });
    const bool fullWithinLimits = (info.maxWidth == 0 || info.width <= info.maxWidth) &&
                                  (info.maxHeight == 0 || info.height <= info.maxHeight) &&
                                  (info.maxArea == 0 || (long long)info.width * info.height <= info.maxArea);
    if (fits != sizes.end() || (!sizes.empty() && !fullWithinLimits)) {
      const std::pair<int, int> s = fits != sizes.end() ? *fits : sizes.back();
      r.width = s.first, r.height = s.second;
      r.url = region + std::to_string(s.first) + "," + (info.version == 3 ? std::to_string(s.second) : "") + tail;
      return r;
    }
    r.width = info.width, r.height = info.height;
    r.url = region + (info.version == 3 ? "max" : "full") + tail;
    return r;
  }
  int w = std::clamp(wantWidth, 1, info.width);
  if (info.maxWidth > 0) w = std::min(w, info.maxWidth);
  if (info.maxHeight > 0 && heightOf(w) > info.maxHeight)
    w = std::max(1, int(std::floor(double(info.maxHeight) * info.width / info.height)));
  if (info.maxArea > 0 && (long long)w * heightOf(w) > info.maxArea) {
    w = std::max(1, int(std::floor(std::sqrt(double(info.maxArea) * info.width / info.height))));
    while (w > 1 && (long long)w * heightOf(w) > info.maxArea) --w;  // rounding of the height
  }
  r.width = w;
  r.height = heightOf(w);
  // Image API 2 level 1 offers "w," (sizeByW), not "w,h"; Image API 3 level 1 offers "w,h".
  r.url = region + std::to_string(w) + "," + (info.version == 3 ? std::to_string(r.height) : "") + tail;
  return r;
}

}  // namespace hv
