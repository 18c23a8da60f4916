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

// The preview (a small size first) and the sizes a level-0 service serves, computed by hand.
TEST(Iiif, PreviewFitsTheBoxAndTheServiceLimits) {
  const IiifImageInfo v3 = parseIiifInfo(kV3, "https://example.org/iiif/photo/info.json");
  // 6000 x 4000 in 256 x 256: 256 wide, 4000 * 256 / 6000 = 170.67 -> 171 high.
  IiifRequest p = iiifPreviewRequest(v3);
  EXPECT_EQ(p.url, "https://example.org/iiif/photo/full/256,171/0/default.jpg");
  EXPECT_EQ(p.width, 256);
  EXPECT_EQ(p.height, 171);
  // Portrait 3000 x 4000: 256 high, 3000 * 256 / 4000 = 192 wide.
  const IiifImageInfo portrait = parseIiifInfo(
      R"({"@context": "http://iiif.io/api/image/3/context.json", "profile": "level1", "width": 3000, "height": 4000})",
      "http://h/p/info.json");
  p = iiifPreviewRequest(portrait);
  EXPECT_EQ(p.url, "http://h/p/full/192,256/0/default.jpg");
  // The Image API 2 asks by width: 1000 x 750 gives 256 x 192 ("256,").
  const IiifImageInfo v2 = parseIiifInfo(kV2, "http://h/q/info.json");
  p = iiifPreviewRequest(v2);
  EXPECT_EQ(p.url, "http://h/q/full/256,/0/default.jpg");
  EXPECT_EQ(p.height, 192);
  // maxWidth 100 below the box: 100 x 67 (4000 * 100 / 6000 = 66.67).
  std::string limited = kV3;
  limited.insert(limited.rfind('}'), R"(, "maxWidth": 100)");
  p = iiifPreviewRequest(parseIiifInfo(limited, "http://h/p/info.json"));
  EXPECT_EQ(p.url, "http://h/p/full/100,67/0/default.jpg");
  // maxArea 10000 (a 122 x 81 image: 122 * 81 = 9882; 123 * 82 = 10086 is over).
  limited = kV3;
  limited.insert(limited.rfind('}'), R"(, "maxArea": 10000)");
  p = iiifPreviewRequest(parseIiifInfo(limited, "http://h/p/info.json"));
  EXPECT_EQ(p.width, 122);
  EXPECT_EQ(p.height, 81);
  // An image smaller than the box: the preview is the full size (nothing worth fetching first).
  const IiifImageInfo small = parseIiifInfo(
      R"({"@context": "http://iiif.io/api/image/3/context.json", "profile": "level2", "width": 200, "height": 100})",
      "http://h/s/info.json");
  EXPECT_EQ(iiifPreviewRequest(small).width, 200);
}

TEST(Iiif, Level0ServesListedSizesAndSingleTiles) {
  // 6000 x 4000 in 512-pixel tiles at scale factors 1..16: one tile covers the image at 16
  // (512 * 16 = 8192 >= 6000), not at 8 (4096 < 6000): ceil(6000 / 16) x ceil(4000 / 16) = 375 x 250.
  std::string tiled = R"({"@context": "http://iiif.io/api/image/3/context.json", "profile": "level0",
                          "width": 6000, "height": 4000,
                          "tiles": [{"width": 512, "scaleFactors": [1, 2, 4, 8, 16]}]})";
  IiifImageInfo info = parseIiifInfo(tiled, "http://h/t/info.json");
  ASSERT_EQ(info.tiles.size(), 1u);
  EXPECT_EQ(info.tiles[0].height, 512);  // the width when not given
  EXPECT_EQ(iiifLevel0Sizes(info), (std::vector<std::pair<int, int>>{{375, 250}}));
  EXPECT_EQ(iiifPreviewRequest(info).url, "http://h/t/full/375,250/0/default.jpg");
  // Wider than any size served, within no limit: the full size.
  EXPECT_EQ(iiifRequest(info, 3000).url, "http://h/t/full/max/0/default.jpg");
  // Tiles of 256 x 200 at 32: 256 * 32 = 8192 >= 6000 and 200 * 32 = 6400 >= 4000, at 16 not
  // (200 * 16 = 3200 < 4000): ceil(6000 / 32) = 188, ceil(4000 / 32) = 125; listed sizes join them.
  tiled =
      R"({"@context": "http://iiif.io/api/image/2/context.json", "profile": ["http://iiif.io/api/image/2/level0.json"],
              "width": 6000, "height": 4000, "sizes": [{"width": 750, "height": 500}],
              "tiles": [{"width": 256, "height": 200, "scaleFactors": [1, 4, 16, 32]}]})";
  info = parseIiifInfo(tiled, "http://h/u/info.json");
  EXPECT_EQ(iiifLevel0Sizes(info), (std::vector<std::pair<int, int>>{{188, 125}, {750, 500}}));
  // The preview (256 wide wanted): the smallest served size at least 256 wide, 750 x 500.
  EXPECT_EQ(iiifPreviewRequest(info).url, "http://h/u/full/750,/0/default.jpg");
  EXPECT_EQ(iiifRequest(info, 100).url, "http://h/u/full/188,/0/default.jpg");
  EXPECT_EQ(iiifRequest(info, 1000).url, "http://h/u/full/full/0/default.jpg");
  // Bad tiles name the field.
  try {
    parseIiifInfo(R"({"@context": "http://iiif.io/api/image/3/context.json", "width": 4, "height": 3,
                      "tiles": [{"width": 2, "scaleFactors": [1, 0]}]})",
                  "http://h/b/info.json");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find("http://h/b/info.json: tiles: scaleFactors: expected positive integers, got 0"),
        std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace hv
