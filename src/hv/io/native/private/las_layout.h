// The byte layout of LAS files (ASPRS LAS 1.4 R15, with the 1.0-1.3 differences), shared by the
// reader and the writer. Offsets are in bytes from the start of the header or of a point record.
#pragma once

#include <cstdint>

namespace hv::las {

// Public header block (R15 table 3). 1.0-1.2 end at 227, 1.3 adds the waveform offset (235),
// 1.4 the EVLRs and the 64-bit counts (375).
inline constexpr int kVersionMajor = 24, kVersionMinor = 25;
inline constexpr int kGlobalEncoding = 6;
inline constexpr int kHeaderSize = 94, kOffsetToPoints = 96, kVlrCount = 100;
inline constexpr int kPointFormat = 104, kPointRecordLength = 105;
inline constexpr int kLegacyPointCount = 107, kLegacyPointsByReturn = 111;
inline constexpr int kScale = 131, kOffset = 155;
inline constexpr int kMaxX = 179;  // then min x, max y, min y, max z, min z
inline constexpr int kFirstEvlr = 235, kEvlrCount = 243, kPointCount = 247, kPointsByReturn = 255;
inline constexpr int kHeaderSize12 = 227, kHeaderSize13 = 235, kHeaderSize14 = 375;

inline constexpr int kVlrHeaderSize = 54;   // reserved, user id[16], record id, length, description[32]
inline constexpr int kEvlrHeaderSize = 60;  // the same with a 64-bit length
inline constexpr int kVlrUserId = 2, kVlrRecordId = 18, kVlrLength = 20;

inline constexpr std::uint16_t kWktRecordId = 2112;       // OGC coordinate system WKT
inline constexpr std::uint16_t kGeoKeysRecordId = 34735;  // GeoKeyDirectoryTag
inline constexpr std::uint16_t kLaszipRecordId = 22204;   // "laszip encoded"
inline constexpr std::uint16_t kGlobalEncodingWkt = 1u << 4;

// Point data record formats 0-10 (R15 tables 7-16, 27-31). Every format starts with
// X, Y, Z (int32 at 0, 4, 8) and the intensity (uint16 at 12).
struct PointLayout {
  int minLength;       // the record length without extra bytes
  int classOffset;     // classification byte
  bool extended;       // formats 6-10: 8-bit class, 4-bit return numbers
  int gpsTimeOffset;   // -1: none
  int rgbOffset;       // -1: none
};
inline constexpr PointLayout kPointLayouts[11] = {
    {20, 15, false, -1, -1}, {28, 15, false, 20, -1}, {26, 15, false, -1, 20}, {34, 15, false, 20, 28},
    {57, 15, false, 20, -1}, {63, 15, false, 20, 28}, {30, 16, true, 22, -1},  {36, 16, true, 22, 30},
    {38, 16, true, 22, 30},  {59, 16, true, 22, -1},  {67, 16, true, 22, 30}};
inline constexpr int kIntensityOffset = 12, kReturnOffset = 14;

// GeoTIFF keys (GeoTIFF 1.0 §6.2) read from the GeoKeyDirectory VLR.
inline constexpr std::uint16_t kGeoModelTypeKey = 1024, kGeoRasterTypeKey = 1025;
inline constexpr std::uint16_t kGeographicTypeKey = 2048, kProjectedCsTypeKey = 3072;
inline constexpr std::uint16_t kGeoUserDefined = 32767;

}  // namespace hv::las
