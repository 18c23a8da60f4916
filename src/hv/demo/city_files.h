// The large demo city's files through GDAL/OGR: the DTM as a Cloud-Optimized GeoTIFF and the
// footprints as a GeoPackage. Internal to the demo city (its sources include GDAL's headers).
#pragma once

#include <cstddef>
#include <memory>
#include <string>

#include "hv/scene/heightfield.h"
#include "hv/scene/native/lod1.h"

namespace hv::demo::detail {

// A single-band Float32 Cloud-Optimized GeoTIFF (GDAL's COG driver): 256 x 256 tiles, DEFLATE with
// the floating-point predictor, and overviews (average of 2 x 2 cells per level) halving down to
// 16 cells on the longer side. `crs`: anything OGRSpatialReference::SetFromUserInput accepts.
// Throws std::runtime_error naming the file.
void writeCog(const std::string& path, const Heightfield& field, const std::string& crs);

// Polygon footprints into a GeoPackage layer "buildings" (fields `id`, string, and `height`, real)
// with its R-tree spatial index, written in transactions. The file carries no time of writing
// (OGR_CURRENT_DATE fixed), so the same footprints give the same bytes.
class GeoPackageWriter {
 public:
  GeoPackageWriter(const std::string& path, const std::string& crs);  // throws std::runtime_error
  ~GeoPackageWriter();
  GeoPackageWriter(const GeoPackageWriter&) = delete;
  GeoPackageWriter& operator=(const GeoPackageWriter&) = delete;
  void add(const Footprint& footprint);  // rings as in Footprint (not closed); closed on writing
  void close();                          // commits, builds the index and closes; throws on failure
  std::size_t count() const { return count_; }

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string path_;
  std::size_t count_ = 0;
};

}  // namespace hv::demo::detail
