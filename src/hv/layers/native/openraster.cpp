#include "hv/layers/native/openraster.h"

#include "hv/image/native/png_write.h"
#include "hv/util/diagnostics.h"

#include <zip.h>
#include <pugixml.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace hv::layers {

namespace {

constexpr char kMimetype[] = "image/openraster";
constexpr int kThumbnailSide = 256;  // the specification's maximum

std::string xmlEscape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

struct ZipCloser {
  void operator()(zip_t* z) const {
    if (z) zip_discard(z);
  }
};

}  // namespace

Image8 compositeLayers(const OraDocument& doc) {
  Image8 out(doc.width, doc.height, 4, 0);
  for (auto it = doc.layers.rbegin(); it != doc.layers.rend(); ++it) {
    const OraLayer& l = *it;
    if (!l.visible || l.rgba.channels != 4) continue;
    for (int y = 0; y < l.rgba.height; ++y) {
      const int ty = y + l.y;
      if (ty < 0 || ty >= doc.height) continue;
      for (int x = 0; x < l.rgba.width; ++x) {
        const int tx = x + l.x;
        if (tx < 0 || tx >= doc.width) continue;
        const std::uint8_t* s = l.rgba.px(x, y);
        std::uint8_t* d = out.px(tx, ty);
        const double sa = s[3] / 255.0, da = d[3] / 255.0;
        const double oa = sa + da * (1.0 - sa);
        if (oa <= 0.0) continue;
        for (int c = 0; c < 3; ++c) d[c] = std::uint8_t(std::lround((s[c] * sa + d[c] * da * (1.0 - sa)) / oa));
        d[3] = std::uint8_t(std::lround(oa * 255.0));
      }
    }
  }
  return out;
}

void writeOpenRaster(const std::string& path, const OraDocument& doc) {
  if (doc.width <= 0 || doc.height <= 0)
    throw std::runtime_error(path + ": an OpenRaster image needs a positive size, got " + std::to_string(doc.width) +
                             " x " + std::to_string(doc.height));
  // libzip reads the buffers when the archive is closed: they live here until then.
  std::vector<std::vector<std::uint8_t>> buffers;
  int err = 0;
  std::unique_ptr<zip_t, ZipCloser> z(zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err));
  if (!z) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, err);
    const std::string why = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    throw std::runtime_error(path + ": cannot create the archive: " + why);
  }
  auto add = [&](const std::string& name, std::vector<std::uint8_t> bytes, bool compress) {
    buffers.push_back(std::move(bytes));
    const std::vector<std::uint8_t>& b = buffers.back();
    zip_source_t* src = zip_source_buffer(z.get(), b.data(), b.size(), 0);
    if (!src) throw std::runtime_error(path + ": " + name + ": " + zip_strerror(z.get()));
    const zip_int64_t index = zip_file_add(z.get(), name.c_str(), src, ZIP_FL_ENC_UTF_8 | ZIP_FL_OVERWRITE);
    if (index < 0) {
      zip_source_free(src);
      throw std::runtime_error(path + ": " + name + ": " + zip_strerror(z.get()));
    }
    if (zip_set_file_compression(z.get(), zip_uint64_t(index), compress ? ZIP_CM_DEFLATE : ZIP_CM_STORE, 0) != 0)
      throw std::runtime_error(path + ": " + name + ": " + zip_strerror(z.get()));
  };
  // The mimetype first and stored, so that a reader finds "image/openraster" at byte 38.
  add("mimetype", std::vector<std::uint8_t>(kMimetype, kMimetype + sizeof(kMimetype) - 1), false);

  std::ostringstream xml;
  xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<image version=\"0.0.5\" w=\"" << doc.width << "\" h=\"" << doc.height << "\">\n  <stack>\n";
  for (std::size_t i = 0; i < doc.layers.size(); ++i) {
    const OraLayer& l = doc.layers[i];
    if (l.rgba.channels != 4 || l.rgba.empty())
      throw std::runtime_error(path + ": layer '" + l.name + "': expected an RGBA image");
    const std::string src = "data/layer" + std::to_string(i) + ".png";
    xml << "    <layer name=\"" << xmlEscape(l.name) << "\" src=\"" << src << "\" x=\"" << l.x << "\" y=\"" << l.y
        << "\" opacity=\"1.0\" visibility=\"" << (l.visible ? "visible" : "hidden") << "\"/>\n";
    add(src, encodePng(l.rgba, path + ": " + src), false);  // PNG is compressed already
  }
  xml << "  </stack>\n</image>\n";
  const std::string x = xml.str();
  add("stack.xml", std::vector<std::uint8_t>(x.begin(), x.end()), true);

  const Image8 merged = compositeLayers(doc);
  add("mergedimage.png", encodePng(merged, path + ": mergedimage.png"), false);
  const double s = std::min(1.0, double(kThumbnailSide) / std::max(doc.width, doc.height));
  const int tw = std::max(1, int(std::lround(doc.width * s))), th = std::max(1, int(std::lround(doc.height * s)));
  add("Thumbnails/thumbnail.png", encodePng(s < 1.0 ? resizeImage(merged, tw, th) : merged, path + ": thumbnail"),
      false);

  zip_t* raw = z.release();
  if (zip_close(raw) != 0) {
    const std::string why = zip_strerror(raw);
    zip_discard(raw);
    throw std::runtime_error(path + ": cannot write the archive: " + why);
  }
}

namespace {

std::vector<std::uint8_t> readEntry(zip_t* z, const std::string& path, const std::string& name) {
  zip_stat_t st;
  zip_stat_init(&st);
  if (zip_stat(z, name.c_str(), 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
    throw InputError(path + ": entry '" + name + "': missing from the archive");
  if (st.size > (zip_uint64_t(1) << 31)) throw InputError(path + ": entry '" + name + "': larger than 2 GiB");
  std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> f(zip_fopen(z, name.c_str(), 0), &zip_fclose);
  if (!f) throw InputError(path + ": entry '" + name + "': cannot open: " + zip_strerror(z));
  std::vector<std::uint8_t> bytes(st.size);
  if (st.size > 0 && zip_fread(f.get(), bytes.data(), st.size) != zip_int64_t(st.size))
    throw InputError(path + ": entry '" + name + "': cannot read: " + zip_file_strerror(f.get()));
  return bytes;
}

int intAttribute(const pugi::xml_node& n, const char* name, int fallback, const std::string& where) {
  const pugi::xml_attribute a = n.attribute(name);
  if (!a) return fallback;
  const std::string text = a.value();
  std::size_t used = 0;
  try {
    const long v = std::stol(text, &used);
    if (used == text.size() && v >= -(1L << 24) && v <= (1L << 24)) return int(v);
  } catch (const std::exception&) {
  }
  throw InputError(where + ": attribute '" + name + "': expected an integer, got '" + text + "'");
}

void collectLayers(const pugi::xml_node& stack, zip_t* z, const std::string& path, OraDocument& doc) {
  for (const pugi::xml_node& n : stack.children()) {
    const std::string tag = n.name();
    if (tag == "stack") {
      collectLayers(n, z, path, doc);
      continue;
    }
    if (tag != "layer") continue;  // text and unknown elements are skipped, as the spec allows
    OraLayer l;
    l.name = n.attribute("name").value();
    l.src = n.attribute("src").value();
    const std::string where = path + ": stack.xml: layer '" + l.name + "'";
    if (l.src.empty()) throw InputError(where + ": attribute 'src': missing");
    l.x = intAttribute(n, "x", 0, where);
    l.y = intAttribute(n, "y", 0, where);
    const std::string visibility = n.attribute("visibility").as_string("visible");
    if (visibility != "visible" && visibility != "hidden")
      throw InputError(where + ": attribute 'visibility': expected 'visible' or 'hidden', got '" + visibility + "'");
    l.visible = visibility == "visible";
    const std::vector<std::uint8_t> png = readEntry(z, path, l.src);
    l.rgba = decodeImage(png.data(), png.size(), path + ": " + l.src, 4);
    doc.layers.push_back(std::move(l));
  }
}

}  // namespace

OraDocument readOpenRaster(const std::string& path) {
  int err = 0;
  std::unique_ptr<zip_t, ZipCloser> z(zip_open(path.c_str(), ZIP_RDONLY, &err));
  if (!z) {
    zip_error_t ze;
    zip_error_init_with_code(&ze, err);
    const std::string why = zip_error_strerror(&ze);
    zip_error_fini(&ze);
    throw InputError(path + ": not a readable zip archive (" + why + ")");
  }
  const std::vector<std::uint8_t> mime = readEntry(z.get(), path, "mimetype");
  if (std::string(mime.begin(), mime.end()) != kMimetype)
    throw InputError(path + ": entry 'mimetype': expected '" + std::string(kMimetype) + "'");
  const std::vector<std::uint8_t> xml = readEntry(z.get(), path, "stack.xml");
  pugi::xml_document d;
  const pugi::xml_parse_result r = d.load_buffer(xml.data(), xml.size());
  if (!r)
    throw InputError(path + ": stack.xml: not well-formed XML at byte " + std::to_string(r.offset) + ": " +
                     r.description());
  const pugi::xml_node image = d.child("image");
  if (!image) throw InputError(path + ": stack.xml: expected an <image> root element");
  OraDocument doc;
  doc.width = intAttribute(image, "w", 0, path + ": stack.xml: <image>");
  doc.height = intAttribute(image, "h", 0, path + ": stack.xml: <image>");
  if (doc.width <= 0 || doc.height <= 0)
    throw InputError(path + ": stack.xml: <image>: attributes 'w' and 'h': expected positive sizes");
  const pugi::xml_node stack = image.child("stack");
  if (!stack) throw InputError(path + ": stack.xml: expected a <stack> in <image>");
  collectLayers(stack, z.get(), path, doc);
  return doc;
}

}  // namespace hv::layers
