#include "hv/io/native/las_writer.h"

#include "hv/io/native/private/byte_io.h"
#include "hv/io/native/private/las_layout.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace hv {
namespace {

void putText(std::string& out, std::size_t at, const std::string& text, std::size_t width) {
  std::memcpy(out.data() + at, text.data(), std::min(text.size(), width));
}

template <typename T>
void put(std::string& out, std::size_t at, T v) {
  bytes::storeLE(reinterpret_cast<std::uint8_t*>(out.data() + at), v);
}

std::string vlr(const std::string& user, std::uint16_t id, const std::string& description, const std::string& data) {
  std::string h(las::kVlrHeaderSize, '\0');
  putText(h, las::kVlrUserId, user, 16);
  put<std::uint16_t>(h, las::kVlrRecordId, id);
  put<std::uint16_t>(h, las::kVlrLength, std::uint16_t(data.size()));
  putText(h, 22, description, 32);
  return h + data;
}

// The code of "EPSG:<n>" when it fits a GeoTIFF key; 0 otherwise.
std::uint16_t epsgCode(const std::string& crs) {
  if (crs.rfind("EPSG:", 0) != 0 || crs.size() < 6 || crs.size() > 10 ||
      crs.find_first_not_of("0123456789", 5) != std::string::npos)
    return 0;
  const unsigned long code = std::stoul(crs.substr(5));
  return code < las::kGeoUserDefined ? std::uint16_t(code) : 0;
}

// "EPSG:<n>" as GeoTIFF keys (a projected CRS); anything else as OGC WKT (null-terminated).
std::string crsVlr(const std::string& crs) {
  {
    if (const std::uint16_t code = epsgCode(crs)) {
      std::string keys;
      const std::uint16_t entries[][4] = {{1, 1, 0, 3},
                                          {las::kGeoModelTypeKey, 0, 1, 1},   // projected
                                          {las::kGeoRasterTypeKey, 0, 1, 1},  // pixel is area
                                          {las::kProjectedCsTypeKey, 0, 1, std::uint16_t(code)}};
      for (const auto& e : entries)
        for (std::uint16_t v : e) bytes::appendLE(keys, v);
      return vlr("LASF_Projection", las::kGeoKeysRecordId, "GeoKeyDirectoryTag", keys);
    }
  }
  if (crs.size() + 1 > std::numeric_limits<std::uint16_t>::max())
    throw std::invalid_argument("writeLas: the CRS WKT does not fit in a VLR");
  return vlr("LASF_Projection", las::kWktRecordId, "OGC WKT", crs + '\0');
}

}  // namespace

std::string lasBytes(const PointCloud& cloud, const LasWriteOptions& o) {
  if (o.minorVersion != 2 && o.minorVersion != 4) throw std::invalid_argument("writeLas: version must be 1.2 or 1.4");
  const int format = o.pointFormat >= 0 ? o.pointFormat : (cloud.rgb.empty() ? 1 : 3);
  if (format > 10) throw std::invalid_argument("writeLas: point format must be 0-10");
  const las::PointLayout& layout = las::kPointLayouts[format];
  if (layout.extended && o.minorVersion < 4)
    throw std::invalid_argument("writeLas: point format " + std::to_string(format) + " needs LAS 1.4");
  if (!cloud.consistent()) throw std::invalid_argument("writeLas: attribute sizes differ from the point count");

  const Aabb b = cloud.bounds();
  const glm::dvec3 offset = o.offset ? *o.offset : (b.empty() ? glm::dvec3(0.0) : glm::floor(b.lo));
  const std::size_t n = cloud.size();
  const bool legacyCountFits = n <= std::numeric_limits<std::uint32_t>::max() && !layout.extended;

  const std::string vlrs = cloud.crs.empty() ? std::string() : crsVlr(cloud.crs);
  const int headerSize = o.minorVersion == 4 ? las::kHeaderSize14 : las::kHeaderSize12;
  const std::size_t pointOffset = std::size_t(headerSize) + vlrs.size();

  std::string out(pointOffset + n * std::size_t(layout.minLength), '\0');
  putText(out, 0, "LASF", 4);
  if (o.minorVersion == 4 && !cloud.crs.empty() && epsgCode(cloud.crs) == 0)
    put<std::uint16_t>(out, las::kGlobalEncoding, las::kGlobalEncodingWkt);
  out[las::kVersionMajor] = 1;
  out[las::kVersionMinor] = char(o.minorVersion);
  putText(out, 26, "histoview", 32);
  putText(out, 58, "histoview", 32);
  put<std::uint16_t>(out, las::kHeaderSize, std::uint16_t(headerSize));
  put<std::uint32_t>(out, las::kOffsetToPoints, std::uint32_t(pointOffset));
  put<std::uint32_t>(out, las::kVlrCount, vlrs.empty() ? 0u : 1u);
  out[las::kPointFormat] = char(format);
  put<std::uint16_t>(out, las::kPointRecordLength, std::uint16_t(layout.minLength));
  if (legacyCountFits) {
    put<std::uint32_t>(out, las::kLegacyPointCount, std::uint32_t(n));
    put<std::uint32_t>(out, las::kLegacyPointsByReturn, std::uint32_t(n));  // every point is return 1 of 1
  }
  for (int i = 0; i < 3; ++i) {
    put<double>(out, las::kScale + 8 * i, o.scale[i]);
    put<double>(out, las::kOffset + 8 * i, offset[i]);
    put<double>(out, las::kMaxX + 16 * i, b.empty() ? 0.0 : b.hi[i]);
    put<double>(out, las::kMaxX + 16 * i + 8, b.empty() ? 0.0 : b.lo[i]);
  }
  if (o.minorVersion == 4) {
    put<std::uint64_t>(out, las::kPointCount, n);
    put<std::uint64_t>(out, las::kPointsByReturn, n);
  }
  out.replace(std::size_t(headerSize), vlrs.size(), vlrs);

  std::size_t at = pointOffset;
  for (std::size_t i = 0; i < n; ++i, at += std::size_t(layout.minLength)) {
    for (int k = 0; k < 3; ++k) {
      const double q = std::round((cloud.positions[i][k] - offset[k]) / o.scale[k]);
      if (!(q >= std::numeric_limits<std::int32_t>::min() && q <= std::numeric_limits<std::int32_t>::max()))
        throw std::invalid_argument("writeLas: point " + std::to_string(i) +
                                    " does not fit in 32-bit integers at this scale and offset");
      put<std::int32_t>(out, at + 4 * std::size_t(k), std::int32_t(q));
    }
    if (!cloud.intensity.empty()) put<std::uint16_t>(out, at + las::kIntensityOffset, cloud.intensity[i]);
    out[at + las::kReturnOffset] = char(layout.extended ? 0x11 : 0x09);  // return 1 of 1
    if (!cloud.classification.empty()) {
      const std::uint8_t c = cloud.classification[i];
      if (!layout.extended && c > 31)
        throw std::invalid_argument("writeLas: class " + std::to_string(c) + " needs point format 6-10");
      out[at + std::size_t(layout.classOffset)] = char(c);
    }
    if (layout.rgbOffset >= 0 && !cloud.rgb.empty())
      for (int k = 0; k < 3; ++k) put<std::uint16_t>(out, at + std::size_t(layout.rgbOffset + 2 * k), cloud.rgb[i][k]);
  }
  return out;
}

void writeLas(const std::string& path, const PointCloud& cloud, const LasWriteOptions& options) {
  const std::string bytes = lasBytes(cloud, options);
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(bytes.data(), std::streamsize(bytes.size()));
  f.close();
  if (!f) throw std::runtime_error("cannot write " + path);
}

}  // namespace hv
