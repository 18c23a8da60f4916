#include "hv/io/iiif.h"

#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

namespace hv {
namespace {

// Shaped after the examples of the IIIF Image API 3.0 and 2.1 specifications (section 5).
const char* kV3 = R"({
  "@context": "http://iiif.io/api/image/3/context.json",
  "id": "https://example.org/iiif/photo", "type": "ImageService3", "protocol": "http://iiif.io/api/image",
  "profile": "level1", "width": 6000, "height": 4000,
  "tiles": [{"width": 512, "scaleFactors": [1, 2, 4, 8]}]})";
const char* kV2 = R"({
  "@context": "http://iiif.io/api/image/2/context.json", "@id": "http://iip.local/fcgi?IIIF=/p.tif",
  "protocol": "http://iiif.io/api/image", "width": 1000, "height": 750,
  "sizes": [{"width": 125, "height": 94}, {"width": 250, "height": 188}, {"width": 500, "height": 375}],
  "profile": ["http://iiif.io/api/image/2/level1.json", {"formats": ["jpg"], "maxWidth": 800}]})";

TEST(Iiif, RecognisesDescriptionUrls) {
  EXPECT_TRUE(isIiifInfoUrl("https://example.org/iiif/photo/info.json"));
  EXPECT_TRUE(isIiifInfoUrl("http://h:8080/fcgi-bin/iipsrv.fcgi?IIIF=/a/p.tif/info.json"));
  EXPECT_TRUE(isIiifInfoUrl("http://h/iiif/p/info.json#x"));
  EXPECT_FALSE(isIiifInfoUrl("http://h/iiif/p/info.json.bak"));
  EXPECT_FALSE(isIiifInfoUrl("http://h/p.jpg"));
  EXPECT_FALSE(isIiifInfoUrl("/data/iiif/p/info.json"));  // a local file is not a service
  EXPECT_FALSE(isIiifInfoUrl("http://h/info.json2"));
}

TEST(Iiif, ReadsVersion3AndAsksForTheCameraSize) {
  const IiifImageInfo info = parseIiifInfo(kV3, "https://example.org/iiif/photo/info.json");
  EXPECT_EQ(info.version, 3);
  EXPECT_EQ(info.base, "https://example.org/iiif/photo");
  EXPECT_EQ(info.id, "https://example.org/iiif/photo");
  EXPECT_EQ(info.width, 6000);
  EXPECT_EQ(info.height, 4000);
  EXPECT_FALSE(info.level0);
  EXPECT_EQ(iiifSizeMismatch(info, 3000, 2000), "");
  const IiifRequest r = iiifRequest(info, 3000);
  EXPECT_EQ(r.url, "https://example.org/iiif/photo/full/3000,2000/0/default.jpg");
  EXPECT_EQ(r.width, 3000);
  EXPECT_EQ(r.height, 2000);
  // Never larger than the image: the camera of a larger size gets the full resolution.
  EXPECT_EQ(iiifRequest(info, 9000).url, "https://example.org/iiif/photo/full/6000,4000/0/default.jpg");
  // A preview: 256 px wide, 4000 * 256 / 6000 = 170.67 rounds to 171.
  EXPECT_EQ(iiifRequest(info, 256).url, "https://example.org/iiif/photo/full/256,171/0/default.jpg");
}

TEST(Iiif, ReadsVersion2FromAQueryAndAsksByWidth) {
  const std::string url = "http://127.0.0.1:8080/fcgi-bin/iipsrv.fcgi?IIIF=/city/p.tif/info.json";
  const IiifImageInfo info = parseIiifInfo(kV2, url);
  EXPECT_EQ(info.version, 2);
  EXPECT_EQ(info.base, "http://127.0.0.1:8080/fcgi-bin/iipsrv.fcgi?IIIF=/city/p.tif");
  EXPECT_EQ(info.sizes.size(), 3u);
  EXPECT_FALSE(info.level0);
  const IiifRequest r = iiifRequest(info, 640);
  // Level 1 of the Image API 2 has sizeByW ("w,"), not "w,h".
  EXPECT_EQ(r.url, "http://127.0.0.1:8080/fcgi-bin/iipsrv.fcgi?IIIF=/city/p.tif/full/640,/0/default.jpg");
  EXPECT_EQ(r.height, 480);
  // The Image API 2 gives its limits in the profile: 800 px wide at most, so 800 x 600.
  EXPECT_EQ(iiifRequest(info, 1000).width, 800);
  EXPECT_EQ(iiifRequest(info, 1000).height, 600);
}

TEST(Iiif, RespectsTheServiceLimits) {
  std::string v3 = kV3;
  v3.insert(v3.rfind('}'), R"(, "maxWidth": 2000)");
  EXPECT_EQ(iiifRequest(parseIiifInfo(v3, "http://h/p/info.json"), 3000).url,
            "http://h/p/full/2000,1333/0/default.jpg");
  v3 = kV3;
  v3.insert(v3.rfind('}'), R"(, "maxHeight": 1000)");
  EXPECT_EQ(iiifRequest(parseIiifInfo(v3, "http://h/p/info.json"), 3000).url,
            "http://h/p/full/1500,1000/0/default.jpg");
  v3 = kV3;
  // 1.5 Mpx: w * w / 1.5 <= 1500000 gives w <= 1500.
  v3.insert(v3.rfind('}'), R"(, "maxArea": 1500000)");
  const IiifRequest r = iiifRequest(parseIiifInfo(v3, "http://h/p/info.json"), 3000);
  EXPECT_EQ(r.width, 1500);
  EXPECT_EQ(r.height, 1000);
}

TEST(Iiif, Level0TakesAListedSize) {
  std::string v2 = kV2;
  v2.replace(v2.find("level1"), 6, "level0");
  const IiifImageInfo info = parseIiifInfo(v2, "http://h/p/info.json");
  EXPECT_TRUE(info.level0);
  EXPECT_EQ(iiifRequest(info, 200).url, "http://h/p/full/250,/0/default.jpg");
  EXPECT_EQ(iiifRequest(info, 900).url, "http://h/p/full/500,/0/default.jpg");  // the largest listed
  std::string bare = R"({"@context": "http://iiif.io/api/image/3/context.json", "profile": "level0",
                         "width": 40, "height": 30})";
  EXPECT_EQ(iiifRequest(parseIiifInfo(bare, "http://h/q/info.json"), 20).url, "http://h/q/full/max/0/default.jpg");
}

TEST(Iiif, RefusesAnotherAspectRatio) {
  const IiifImageInfo info = parseIiifInfo(kV3, "https://example.org/iiif/photo/info.json");
  const std::string why = iiifSizeMismatch(info, 640, 480);
  EXPECT_NE(why.find("6000x4000"), std::string::npos) << why;
  EXPECT_NE(why.find("640x480"), std::string::npos) << why;
  EXPECT_NE(why.find("aspect ratios disagree"), std::string::npos) << why;
  EXPECT_EQ(iiifSizeMismatch(info, 601, 400), "");  // 1.5025 against 1.5: within 1%
}

TEST(Iiif, BadDescriptionsNameTheUrlAndField) {
  const std::string url = "http://h/p/info.json";
  const auto message = [&](const std::string& text) {
    try {
      parseIiifInfo(text, url);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("<html>404</html>").find(url + ": not a IIIF image description (not JSON"), std::string::npos);
  EXPECT_NE(message(R"({"width": 4, "height": 3})").find(url + ": @context: expected the IIIF Image API 2 or 3"),
            std::string::npos);
  EXPECT_NE(
      message(R"({"@context": "http://iiif.io/api/image/3/context.json", "width": 4})").find(url + ": height: missing"),
      std::string::npos);
  EXPECT_NE(message(R"({"@context": "http://iiif.io/api/image/2/context.json", "width": -4, "height": 3})")
                .find(url + ": width: expected a positive integer, got -4"),
            std::string::npos);
}

}  // namespace
}  // namespace hv
