#include "hv/io/native/las_reader.h"

#include "hv/util/log.h"

#include "hv/io/native/private/byte_io.h"
#include "hv/io/native/private/las_layout.h"
#include "hv/util/diagnostics.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <vector>

namespace hv {
namespace {

const char* kLazAdvice =
    "LAZ (compressed LAS) is not supported; convert it to LAS first, e.g. `pdal translate in.laz out.las` "
    "or `las2las -i in.laz -o out.las` (LAStools / laszip)";

class LasParser {
 public:
  LasParser(const std::uint8_t* data, std::size_t size, std::string name) : d_(data), n_(size), name_(std::move(name)) {}

  PointCloud parse() {
    if (n_ < 4 || std::string(reinterpret_cast<const char*>(d_), 4) != "LASF")
      fail("file signature", "expected \"LASF\" (not a LAS file)");
    need(las::kHeaderSize12, "public header block", "a header of at least 227 bytes");
    const int major = d_[las::kVersionMajor], minor = d_[las::kVersionMinor];
    if (major != 1 || minor > 4)
      fail("version", "expected LAS 1.0-1.4, got " + std::to_string(major) + "." + std::to_string(minor));
    const int formatByte = d_[las::kPointFormat];
    if (formatByte & 0xC0) fail("point data format", kLazAdvice);  // LASzip sets bit 7 (and 6)

    const auto headerSize = u16(las::kHeaderSize);
    const int minHeader = minor <= 2 ? las::kHeaderSize12 : minor == 3 ? las::kHeaderSize13 : las::kHeaderSize14;
    if (headerSize < minHeader)
      fail("header size", "expected at least " + std::to_string(minHeader) + " bytes for LAS 1." +
                              std::to_string(minor) + ", got " + std::to_string(headerSize));
    need(headerSize, "header size", std::to_string(headerSize) + " bytes of header");
    const std::uint32_t pointOffset = u32(las::kOffsetToPoints);
    if (pointOffset < headerSize)
      fail("offset to point data", "expected at least the header size " + std::to_string(headerSize) + ", got " +
                                       std::to_string(pointOffset));
    if (pointOffset > n_)
      fail("offset to point data", std::to_string(pointOffset) + " is past the end of the file (" +
                                       std::to_string(n_) + " bytes): truncated file?");

    if (formatByte > 10) fail("point data format", "expected 0-10, got " + std::to_string(formatByte));
    const las::PointLayout& layout = las::kPointLayouts[formatByte];
    if (layout.extended && minor < 4)
      fail("point data format", "format " + std::to_string(formatByte) + " needs LAS 1.4, the file is 1." +
                                    std::to_string(minor));
    const std::uint16_t recordLength = u16(las::kPointRecordLength);
    if (recordLength < layout.minLength)
      fail("point data record length", "expected at least " + std::to_string(layout.minLength) +
                                           " bytes for point format " + std::to_string(formatByte) + ", got " +
                                           std::to_string(recordLength));

    // LAS 1.4 keeps the 64-bit count; the legacy 32-bit one is 0 for formats 6-10 or large files.
    std::uint64_t count = u32(las::kLegacyPointCount);
    if (minor >= 4) {
      const std::uint64_t count64 = u64(las::kPointCount);
      if (count64 != 0 || layout.extended) count = count64;
    }
    if (count > 0xFFFFFFFFull)
      fail("number of point records", "more than 2^32 - 1 points are not supported, got " + std::to_string(count));
    const std::uint64_t room = (n_ - pointOffset) / recordLength;
    if (count > room)
      fail(minor >= 4 ? "number of point records" : "legacy number of point records",
           std::to_string(count) + " records of " + std::to_string(recordLength) + " bytes do not fit in the " +
               std::to_string(n_ - pointOffset) + " bytes after the offset to point data (room for " +
               std::to_string(room) + "): truncated file?");

    glm::dvec3 scale, offset;
    for (int i = 0; i < 3; ++i) {
      scale[i] = f64(las::kScale + 8 * i);
      offset[i] = f64(las::kOffset + 8 * i);
      const char* axis[] = {"x", "y", "z"};
      if (!std::isfinite(scale[i]) || scale[i] == 0.0)
        fail(std::string(axis[i]) + " scale factor", "expected a finite non-zero number");
      if (!std::isfinite(offset[i])) fail(std::string(axis[i]) + " offset", "expected a finite number");
    }

    PointCloud cloud;
    cloud.sourcePath = name_;
    readVlrs(headerSize, pointOffset, cloud);
    if (minor >= 4) readEvlrs(cloud);

    const bool hasRgb = layout.rgbOffset >= 0;
    cloud.resize(std::size_t(count), {.intensity = true, .classification = true, .rgb = hasRgb, .normals = false});
    const std::uint8_t* rec = d_ + pointOffset;
    for (std::size_t i = 0; i < count; ++i, rec += recordLength) {
      cloud.positions[i] = glm::dvec3(bytes::load<std::int32_t>(rec), bytes::load<std::int32_t>(rec + 4),
                                      bytes::load<std::int32_t>(rec + 8)) * scale + offset;
      if (!std::isfinite(cloud.positions[i].x + cloud.positions[i].y + cloud.positions[i].z))
        fail("point " + std::to_string(i), "the scale and offset give a non-finite coordinate");
      cloud.intensity[i] = bytes::load<std::uint16_t>(rec + las::kIntensityOffset);
      const std::uint8_t c = rec[layout.classOffset];
      cloud.classification[i] = layout.extended ? c : std::uint8_t(c & 0x1F);
      if (hasRgb) {
        const std::uint8_t* p = rec + layout.rgbOffset;
        cloud.rgb[i] = {bytes::load<std::uint16_t>(p), bytes::load<std::uint16_t>(p + 2),
                        bytes::load<std::uint16_t>(p + 4)};
      }
    }
    if (hasRgb) widenEightBitColours(cloud);
    return cloud;
  }

 private:
  // LAS colours are 16-bit (R15 §2.6: "normalized to 16 bits"), yet many writers store 8-bit
  // values in them (PDAL's Autzen sample: all under 256), which would show nearly black. As
  // Potree and CloudCompare do, a file whose every channel is under 256 is taken as 8-bit and
  // scaled by 257 (255 -> 65535), the convention of hv::PointCloud::rgb.
  void widenEightBitColours(PointCloud& cloud) const {
    std::uint16_t top = 0;
    for (const glm::u16vec3& c : cloud.rgb) top = std::max({top, c.r, c.g, c.b});
    if (top == 0 || top > 255) return;
    for (glm::u16vec3& c : cloud.rgb) c *= std::uint16_t(257);
    log::info(name_ + ": RGB values all under 256, taken as 8-bit colours");
  }

  [[noreturn]] void fail(const std::string& field, const std::string& message) const {
    throw InputError(inputMessage(name_, field, message));
  }
  void need(std::size_t end, const std::string& field, const std::string& what) const {
    if (end > n_) fail(field, "expected " + what + ", the file has " + std::to_string(n_) + " bytes: truncated file?");
  }
  std::uint16_t u16(std::size_t at) const { return bytes::load<std::uint16_t>(d_ + at); }
  std::uint32_t u32(std::size_t at) const { return bytes::load<std::uint32_t>(d_ + at); }
  std::uint64_t u64(std::size_t at) const { return bytes::load<std::uint64_t>(d_ + at); }
  double f64(std::size_t at) const { return bytes::load<double>(d_ + at); }

  std::string userId(std::size_t recordStart) const {
    const char* p = reinterpret_cast<const char*>(d_ + recordStart + las::kVlrUserId);
    return std::string(p, strnlen(p, 16));
  }

  // One (E)VLR's payload: the CRS records and the LASzip marker matter; the rest is skipped.
  void record(const std::string& user, std::uint16_t id, const std::uint8_t* payload, std::size_t length,
              PointCloud& cloud, std::string& geoKeysCrs) {
    if (user == "laszip encoded" && id == las::kLaszipRecordId) fail("LASzip VLR", kLazAdvice);
    if (user != "LASF_Projection") return;
    if (id == las::kWktRecordId) {
      const char* text = reinterpret_cast<const char*>(payload);
      std::string wkt(text, strnlen(text, length));
      while (!wkt.empty() && (wkt.back() == ' ' || wkt.back() == '\n')) wkt.pop_back();
      if (!wkt.empty()) cloud.crs = wkt;
    } else if (id == las::kGeoKeysRecordId && length >= 8) {
      const std::size_t keys = std::min<std::size_t>(bytes::load<std::uint16_t>(payload + 6), (length - 8) / 8);
      std::uint16_t projected = 0, geographic = 0;
      for (std::size_t k = 0; k < keys; ++k) {
        const std::uint8_t* e = payload + 8 + 8 * k;
        const auto key = bytes::load<std::uint16_t>(e), location = bytes::load<std::uint16_t>(e + 2),
                   value = bytes::load<std::uint16_t>(e + 6);
        if (location != 0 || value == 0 || value == las::kGeoUserDefined) continue;  // not a plain code
        if (key == las::kProjectedCsTypeKey) projected = value;
        if (key == las::kGeographicTypeKey) geographic = value;
      }
      if (projected) geoKeysCrs = "EPSG:" + std::to_string(projected);
      else if (geographic) geoKeysCrs = "EPSG:" + std::to_string(geographic);
    }
  }

  void readVlrs(std::size_t headerSize, std::size_t pointOffset, PointCloud& cloud) {
    const std::uint32_t vlrs = u32(las::kVlrCount);
    std::size_t at = headerSize;
    for (std::uint32_t v = 0; v < vlrs; ++v) {
      const std::string field = "variable length record " + std::to_string(v + 1) + " of " + std::to_string(vlrs);
      if (at + las::kVlrHeaderSize > pointOffset)
        fail(field, "its 54-byte header runs past the offset to point data (" + std::to_string(pointOffset) + ")");
      const std::uint16_t length = u16(at + las::kVlrLength);
      if (at + las::kVlrHeaderSize + length > pointOffset)
        fail(field, "its " + std::to_string(length) + " bytes of data run past the offset to point data (" +
                        std::to_string(pointOffset) + ")");
      record(userId(at), u16(at + las::kVlrRecordId), d_ + at + las::kVlrHeaderSize, length, cloud, geoKeysCrs_);
      at += las::kVlrHeaderSize + length;
    }
    if (cloud.crs.empty()) cloud.crs = geoKeysCrs_;
  }

  void readEvlrs(PointCloud& cloud) {
    const std::uint64_t start = u64(las::kFirstEvlr);
    const std::uint32_t evlrs = u32(las::kEvlrCount);
    if (evlrs == 0) return;
    std::uint64_t at = start;
    std::string ignored;
    for (std::uint32_t v = 0; v < evlrs; ++v) {
      const std::string field =
          "extended variable length record " + std::to_string(v + 1) + " of " + std::to_string(evlrs);
      if (at > n_ || n_ - at < las::kEvlrHeaderSize) fail(field, "its 60-byte header runs past the end of the file");
      const std::uint64_t length = u64(at + las::kVlrLength);
      if (length > n_ - at - las::kEvlrHeaderSize) fail(field, "its data run past the end of the file");
      record(userId(at), u16(at + las::kVlrRecordId), d_ + at + las::kEvlrHeaderSize, std::size_t(length), cloud,
             ignored);
      at += las::kEvlrHeaderSize + length;
    }
  }

  const std::uint8_t* d_;
  std::size_t n_;
  std::string name_;
  std::string geoKeysCrs_;
};

}  // namespace

PointCloud parseLas(const std::uint8_t* data, std::size_t size, const std::string& name) {
  return LasParser(data, size, name).parse();
}

PointCloud readLas(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext == ".laz") throw InputError(inputMessage(path, "", kLazAdvice));
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  return parseLas(bytes.data(), bytes.size(), path);
}

}  // namespace hv
