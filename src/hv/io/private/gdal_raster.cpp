#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "hv/io/private/gdal_init.h"
#include "hv/io/raster.h"

namespace hv {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(GDALDataset::ToHandle(ds)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

// "EPSG:n" when the CRS is an EPSG one (short, and what users write), else its WKT.
std::string describeCrs(const OGRSpatialReference* srs) {
  if (!srs) return {};
  const char* authority = srs->GetAuthorityName(nullptr);
  const char* code = srs->GetAuthorityCode(nullptr);
  if (authority && code && std::string(authority) == "EPSG") return std::string("EPSG:") + code;
  char* wkt = nullptr;
  std::string out;
  if (srs->exportToWkt(&wkt) == OGRERR_NONE && wkt) out = wkt;
  CPLFree(wkt);
  return out;
}

}  // namespace

Heightfield readHeightfield(const std::string& path) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  DatasetPtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds)
    throw InputError(inputMessage(path, "", "cannot open as a raster: " + gdal::lastError("unknown format")));
  if (ds->GetRasterCount() < 1) throw InputError(inputMessage(path, "", "has no raster band"));

  // Geotransform (GDAL data model): x = gt[0] + col * gt[1] + row * gt[2],
  //                                   y = gt[3] + col * gt[4] + row * gt[5].
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None)
    throw InputError(inputMessage(path, "geotransform", "missing: the elevations are not georeferenced"));
  if (gt[2] != 0.0 || gt[4] != 0.0)
    throw InputError(inputMessage(path, "geotransform", "rotated or sheared rasters are not supported"));
  if (gt[1] == 0.0 || gt[5] == 0.0) throw InputError(inputMessage(path, "geotransform", "zero pixel size"));

  Heightfield field;
  field.cols = ds->GetRasterXSize();
  field.rows = ds->GetRasterYSize();
  field.originX = gt[0];
  field.originY = gt[3];
  field.cellX = gt[1];
  field.cellY = gt[5];
  field.crs = describeCrs(ds->GetSpatialRef());

  GDALRasterBand* band = ds->GetRasterBand(1);
  field.z.resize(size_t(field.cols) * field.rows);
  if (band->RasterIO(GF_Read, 0, 0, field.cols, field.rows, field.z.data(), field.cols, field.rows,
                     GDT_Float32, 0, 0, nullptr) != CE_None)
    throw InputError(inputMessage(path, "band 1", "read failed: " + gdal::lastError("I/O error")));

  int hasNoData = 0;
  const double noData = band->GetNoDataValue(&hasNoData);
  // Compared after the conversion to float that RasterIO applied to the samples too.
  const float noDataF = float(noData);
  int hasScale = 0, hasOffset = 0;
  const double scale = band->GetScale(&hasScale), offset = band->GetOffset(&hasOffset);
  const bool rescale = (hasScale && scale != 1.0) || (hasOffset && offset != 0.0);
  for (float& v : field.z) {
    if (hasNoData && (v == noDataF || (std::isnan(noData) && std::isnan(v)))) {
      v = std::numeric_limits<float>::quiet_NaN();
    } else if (rescale) {
      // Integer DTMs (e.g. centimetres) carry their unit in scale/offset: value = raw * scale + offset.
      v = float(double(v) * (hasScale ? scale : 1.0) + (hasOffset ? offset : 0.0));
    }
  }
  return field;
}

void writeGeoTiff(const std::string& path, const Heightfield& field, const std::string& crs) {
  if (field.cols <= 0 || field.rows <= 0 || field.z.size() != size_t(field.cols) * field.rows)
    throw std::invalid_argument("writeGeoTiff: heightfield has " + std::to_string(field.z.size()) +
                                " samples for " + std::to_string(field.cols) + " x " +
                                std::to_string(field.rows));
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw InputError(inputMessage(path, "", "GDAL has no GTiff driver"));

  OGRSpatialReference srs;
  if (!crs.empty()) {
    if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE)
      throw InputError(
          inputMessage(path, "crs", "cannot interpret '" + crs + "': " + gdal::lastError("unknown CRS")));
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  }

  char** options = nullptr;
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "PREDICTOR", "3");  // floating-point predictor: DTMs compress well
  DatasetPtr ds(driver->Create(path.c_str(), field.cols, field.rows, 1, GDT_Float32, options));
  CSLDestroy(options);
  if (!ds)
    throw InputError(inputMessage(path, "", "cannot create: " + gdal::lastError("GTiff driver refused")));

  double gt[6] = {field.originX, field.cellX, 0.0, field.originY, 0.0, field.cellY};
  ds->SetGeoTransform(gt);
  if (!crs.empty()) ds->SetSpatialRef(&srs);
  GDALRasterBand* band = ds->GetRasterBand(1);
  for (float v : field.z)
    if (std::isnan(v)) {
      band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
      break;
    }
  // RasterIO takes a non-const buffer even for writing.
  std::vector<float> samples = field.z;
  if (band->RasterIO(GF_Write, 0, 0, field.cols, field.rows, samples.data(), field.cols, field.rows,
                     GDT_Float32, 0, 0, nullptr) != CE_None)
    throw InputError(inputMessage(path, "", "write failed: " + gdal::lastError("I/O error")));
  ds->FlushCache(true);
  if (CPLGetLastErrorType() >= CE_Failure)
    throw InputError(inputMessage(path, "", "write failed: " + gdal::lastError("I/O error")));
}

}  // namespace hv
