#include "hv/layers/native/openraster.h"

#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>
#include <zip.h>
#include <pugixml.hpp>

#include <unistd.h>
#include <filesystem>
#include <fstream>

namespace hv::layers {
namespace {

namespace fs = std::filesystem;

Image8 solid(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a) {
  Image8 img(w, h, 4);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = img.px(x, y);
      p[0] = r, p[1] = g, p[2] = b, p[3] = a;
    }
  return img;
}

std::vector<std::uint8_t> entry(zip_t* z, const char* name) {
  zip_stat_t st;
  EXPECT_EQ(zip_stat(z, name, 0, &st), 0) << name;
  zip_file_t* f = zip_fopen(z, name, 0);
  EXPECT_NE(f, nullptr) << name;
  std::vector<std::uint8_t> b(st.size);
  if (f) {
    EXPECT_EQ(zip_fread(f, b.data(), st.size), zip_int64_t(st.size));
    zip_fclose(f);
  }
  return b;
}

class OpenRaster : public ::testing::Test {
 protected:
  void SetUp() override {
    path_ = fs::temp_directory_path() / ("hv_ora_test_" + std::to_string(::getpid()) + ".ora");
    doc_.width = 300;
    doc_.height = 200;
    doc_.layers.push_back({"guide & <outline>", 0, 0, false, solid(300, 200, 255, 0, 0, 255), ""});
    doc_.layers.push_back({"L1 building 3", 10, 20, true, solid(40, 30, 0, 0, 255, 255), ""});
    doc_.layers.push_back({"L2 building 7", 30, 40, true, solid(50, 60, 0, 255, 0, 128), ""});
    doc_.layers.push_back({"background", 0, 0, true, solid(300, 200, 10, 20, 30, 255), ""});
    writeOpenRaster(path_.string(), doc_);
  }
  void TearDown() override { fs::remove(path_); }
  fs::path path_;
  OraDocument doc_;
};

TEST_F(OpenRaster, MimetypeIsTheFirstEntryAndStored) {
  // The specification: "mimetype" first, uncompressed, so its content sits at byte 38 of the file
  // (a 30-byte local header, then the 8-byte name, no extra field).
  std::ifstream f(path_, std::ios::binary);
  std::string head(54, '\0');
  f.read(head.data(), 54);
  EXPECT_EQ(head.substr(0, 4), std::string("PK\x03\x04", 4));
  EXPECT_EQ(head.substr(30, 8), "mimetype");
  EXPECT_EQ(head.substr(38, 16), "image/openraster");
  int err = 0;
  zip_t* z = zip_open(path_.c_str(), ZIP_RDONLY, &err);
  ASSERT_NE(z, nullptr);
  EXPECT_STREQ(zip_get_name(z, 0, 0), "mimetype");
  zip_stat_t st;
  ASSERT_EQ(zip_stat_index(z, 0, 0, &st), 0);
  EXPECT_EQ(st.comp_method, ZIP_CM_STORE);
  for (const char* name : {"stack.xml", "mergedimage.png", "Thumbnails/thumbnail.png"})
    EXPECT_GE(zip_name_locate(z, name, 0), 0) << name;
  zip_close(z);
}

TEST_F(OpenRaster, StackXmlIsWellFormedWithTheLayerAttributes) {
  int err = 0;
  zip_t* z = zip_open(path_.c_str(), ZIP_RDONLY, &err);
  ASSERT_NE(z, nullptr);
  const std::vector<std::uint8_t> xml = entry(z, "stack.xml");
  pugi::xml_document d;
  ASSERT_TRUE(d.load_buffer(xml.data(), xml.size()));
  const pugi::xml_node image = d.child("image");
  EXPECT_EQ(image.attribute("w").as_int(), 300);
  EXPECT_EQ(image.attribute("h").as_int(), 200);
  std::vector<pugi::xml_node> layers;
  for (pugi::xml_node l : image.child("stack").children("layer")) layers.push_back(l);
  ASSERT_EQ(layers.size(), 4u);
  EXPECT_STREQ(layers[0].attribute("name").value(), "guide & <outline>");  // escaped and read back
  EXPECT_STREQ(layers[0].attribute("visibility").value(), "hidden");
  EXPECT_STREQ(layers[1].attribute("visibility").value(), "visible");
  EXPECT_EQ(layers[2].attribute("x").as_int(), 30);
  EXPECT_EQ(layers[2].attribute("y").as_int(), 40);
  const int sizes[4][2] = {{300, 200}, {40, 30}, {50, 60}, {300, 200}};
  for (std::size_t i = 0; i < 4; ++i) {
    const std::vector<std::uint8_t> png = entry(z, layers[i].attribute("src").value());
    const Image8 img = decodeImage(png.data(), png.size(), "layer", 0);
    EXPECT_EQ(img.width, sizes[i][0]);
    EXPECT_EQ(img.height, sizes[i][1]);
    EXPECT_EQ(img.channels, 4);
  }
  const std::vector<std::uint8_t> thumb = entry(z, "Thumbnails/thumbnail.png");
  const Image8 t = decodeImage(thumb.data(), thumb.size(), "thumbnail", 0);
  EXPECT_EQ(t.width, 256);  // 300 x 200 -> at most 256 on the longer side
  EXPECT_LE(t.height, 256);
  zip_close(z);
}

TEST_F(OpenRaster, MergedImageCompositesTheVisibleLayers) {
  const OraDocument back = readOpenRaster(path_.string());
  ASSERT_EQ(back.layers.size(), 4u);
  const Image8 merged = compositeLayers(back);
  // The hidden red guide is not there; the blue L1 over the background; half-transparent green L2
  // over the background: (0.5 * 255 + 0.5 * 20) for green, 128/255 weights.
  EXPECT_EQ(merged.px(0, 0)[2], 30);
  EXPECT_EQ(merged.px(15, 25)[2], 255);
  const double a = 128.0 / 255.0;
  EXPECT_NEAR(merged.px(70, 90)[1], a * 255 + (1 - a) * 20, 1.0);
  EXPECT_NEAR(merged.px(70, 90)[0], (1 - a) * 10, 1.0);
  EXPECT_EQ(merged.px(70, 90)[3], 255);
}

TEST_F(OpenRaster, RoundTrip) {
  const OraDocument back = readOpenRaster(path_.string());
  EXPECT_EQ(back.width, 300);
  EXPECT_EQ(back.height, 200);
  for (std::size_t i = 0; i < doc_.layers.size(); ++i) {
    EXPECT_EQ(back.layers[i].name, doc_.layers[i].name);
    EXPECT_EQ(back.layers[i].x, doc_.layers[i].x);
    EXPECT_EQ(back.layers[i].y, doc_.layers[i].y);
    EXPECT_EQ(back.layers[i].visible, doc_.layers[i].visible);
    EXPECT_EQ(back.layers[i].rgba.data, doc_.layers[i].rgba.data);
  }
}

TEST(OpenRasterRead, BadFilesAreNamed) {
  const fs::path p = fs::temp_directory_path() / ("hv_ora_bad_" + std::to_string(::getpid()) + ".ora");
  std::ofstream(p) << "not a zip";
  try {
    readOpenRaster(p.string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
  }
  // A zip without stack.xml.
  int err = 0;
  zip_t* z = zip_open(p.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  ASSERT_NE(z, nullptr);
  static const char mime[] = "image/openraster";
  zip_file_add(z, "mimetype", zip_source_buffer(z, mime, sizeof(mime) - 1, 0), 0);
  ASSERT_EQ(zip_close(z), 0);
  try {
    readOpenRaster(p.string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("stack.xml"), std::string::npos) << e.what();
  }
  fs::remove(p);
}

}  // namespace
}  // namespace hv::layers
