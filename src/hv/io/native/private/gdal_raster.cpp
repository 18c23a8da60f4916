#include <cpl_string.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>

#include "hv/io/native/private/gdal_init.h"
#include "hv/io/native/private/service_fetch.h"
#include "hv/io/native/raster.h"
#include "hv/io/native/remote.h"
#include "hv/io/native/terrain_raster.h"
#include "hv/util/input_file.h"
#include "hv/util/log.h"

namespace hv {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(GDALDataset::ToHandle(ds)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

DatasetPtr openRaster(const std::string& path) {
  gdal::requireOpenable(path, "raster", false);
  // GDAL's WCS driver keeps the service descriptions it fetched in a cache folder ($HOME/.gdal by
  // default): histoview's (docs/services.md, "Cache") instead.
  CPLStringList openOptions;
  if (STARTS_WITH_CI(path.c_str(), "WCS:")) {
    if (const std::string cache = cacheFolder(); !cache.empty())
      openOptions.SetNameValue("CACHE", (cache + "/gdal-wcs").c_str());
    // The WCS driver has a time-out of its own (30 s) and ignores GDAL_HTTP_TIMEOUT: given the same.
    if (const char* timeout = CPLGetConfigOption("GDAL_HTTP_TIMEOUT", nullptr))
      openOptions.SetNameValue("Timeout", timeout);
  }
  DatasetPtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, openOptions.List()));
  if (!ds) {
    // The WCS driver gives up on an error status (after its retries) without a message of its own.
    const char* fallback = isRemoteSource(path)
                               ? "the service answered with no raster and GDAL gave no reason (an HTTP "
                                 "error status, after the retries?)"
                               : "unknown format";
    throw InputError(inputMessage(path, "", "cannot open as a raster: " + gdal::lastError(fallback)));
  }
  if (ds->GetRasterCount() < 1) throw InputError(inputMessage(path, "", "has no raster band"));
  return ds;
}

// The decimation a raster of cols x rows is read at: 1 when it fits kMaxRasterCells, else the
// smallest integer step whose grid fits. 0 when no step would make a usable grid.
int decimationFor(std::uint64_t cols, std::uint64_t rows) {
  for (std::uint64_t step = 1; step <= 4096; ++step) {
    const std::uint64_t c = (cols + step - 1) / step, r = (rows + step - 1) / step;
    if (c < 2 || r < 2) return 0;
    if (c * r <= kMaxRasterCells) return int(step);
  }
  return 0;
}

// Band 1 of `ds` on its own grid, in its own units (no-data -> NaN, scale and offset applied).
// A raster over kMaxRasterCells is read at a coarser grid, with a warning in `diag` (when given):
// the size is checked before anything is allocated (a sparse GeoTIFF of 40000 x 40000 cells is
// 296 KB on disk and 6.4 GB as floats).
Heightfield readGrid(GDALDataset* ds, const std::string& path, Diagnostics* diag) {
  // Geotransform (GDAL data model): x = gt[0] + col * gt[1] + row * gt[2],
  //                                   y = gt[3] + col * gt[4] + row * gt[5].
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None)
    throw InputError(inputMessage(path, "geotransform", "missing: the elevations are not georeferenced"));
  if (gt[2] != 0.0 || gt[4] != 0.0)
    throw InputError(inputMessage(path, "geotransform", "rotated or sheared rasters are not supported"));
  if (gt[1] == 0.0 || gt[5] == 0.0) throw InputError(inputMessage(path, "geotransform", "zero pixel size"));

  const int sourceCols = ds->GetRasterXSize(), sourceRows = ds->GetRasterYSize();
  const std::string size = std::to_string(sourceCols) + " x " + std::to_string(sourceRows);
  if (sourceCols < 2 || sourceRows < 2)
    throw InputError(inputMessage(path, "size", size + " cells: expected at least 2 x 2 to make a terrain"));
  const int step = decimationFor(std::uint64_t(sourceCols), std::uint64_t(sourceRows));
  if (step == 0)
    throw InputError(inputMessage(path, "size",
                                  size + " cells: too large to read even decimated (the limit is " +
                                      std::to_string(kMaxRasterCells) + " cells, docs/formats.md, Limits)"));
  Heightfield field;
  field.cols = (sourceCols + step - 1) / step;
  field.rows = (sourceRows + step - 1) / step;
  field.originX = gt[0];
  field.originY = gt[3];
  // The decimated grid covers the same extent: its cells are the source's times the exact ratio.
  field.cellX = gt[1] * double(sourceCols) / field.cols;
  field.cellY = gt[5] * double(sourceRows) / field.rows;
  field.crs = gdal::crsDefinition(ds->GetSpatialRef());
  if (step > 1 && diag)
    diag->warn(inputMessage(path, "size",
                            size + " cells, over the limit of " + std::to_string(kMaxRasterCells) +
                                " (docs/formats.md, Limits): read at 1/" + std::to_string(step) + " resolution, " +
                                std::to_string(field.cols) + " x " + std::to_string(field.rows) + " cells"));

  GDALRasterBand* band = ds->GetRasterBand(1);
  field.z.resize(size_t(field.cols) * field.rows);
  // A smaller buffer than the window: GDAL decimates (nearest sample), from an overview when the
  // file has one.
  if (band->RasterIO(GF_Read, 0, 0, sourceCols, sourceRows, field.z.data(), field.cols, field.rows, GDT_Float32, 0, 0,
                     nullptr) != CE_None)
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
  if (std::all_of(field.z.begin(), field.z.end(), [](float v) { return std::isnan(v); }))
    throw InputError(inputMessage(path, "band 1", "every sample is no-data: no terrain to make"));
  return field;
}

// Metres per unit of a band's unit type (GDAL's GetUnitType: free text, "m", "ft", ...); 0 for
// none or one not recognised.
double unitToMetre(std::string unit) {
  std::transform(unit.begin(), unit.end(), unit.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  unit.erase(0, unit.find_first_not_of(" \t"));
  unit.erase(unit.find_last_not_of(" \t") + 1);
  for (const char* m : {"m", "metre", "metres", "meter", "meters"})
    if (unit == m) return 1.0;
  for (const char* ft : {"ft", "foot", "feet", "international foot", "international feet"})
    if (unit == ft) return 0.3048;
  for (const char* us : {"us-ft", "ftus", "us survey foot", "us survey feet", "foot_us", "us_survey_foot"})
    if (unit == us) return 1200.0 / 3937.0;
  for (const char* cm : {"cm", "centimetre", "centimetres", "centimeter", "centimeters"})
    if (unit == cm) return 0.01;
  return 0.0;
}

// The unit band 1 declares, in metres; 0 when it declares none (or one not recognised: warned).
double bandUnitToMetre(GDALDataset* ds, const std::string& path, Diagnostics& diag) {
  const char* unit = ds->GetRasterBand(1)->GetUnitType();
  if (!unit || !*unit) return 0.0;
  const double toMetre = unitToMetre(unit);
  if (toMetre == 0.0)
    diag.warn(inputMessage(path, "band 1 unit",
                           std::string("'") + unit +
                               "' not recognised (expected m, ft or US survey foot): heights "
                               "taken in the CRS's height unit"));
  return toMetre;
}

// Heights of `f` (on the raster's own grid, x and y still in its CRS) into the scene's metres:
// through PROJ sample by sample when both CRSs have a vertical axis (a geoid or datum change
// differs from place to place), else a unit conversion only.
void heightsToScene(Heightfield& f, double bandToMetre, const GeoTransform& t, const std::string& path,
                    Diagnostics& diag) {
  const double sourceUnit = t.source().heightToMetre();
  if (t.transformsHeights() && !t.sameCrs()) {
    const double toCrsUnit = bandToMetre > 0.0 ? bandToMetre / sourceUnit : 1.0;
    size_t failed = 0;
    for (int j = 0; j < f.rows; ++j)
      for (int i = 0; i < f.cols; ++i) {
        float& v = f.z[size_t(j) * f.cols + i];
        if (std::isnan(v)) continue;
        const glm::dvec2 p = f.samplePosition(i, j);
        try {
          v = float(t.point({p.x, p.y, double(v) * toCrsUnit}).z);
        } catch (const InputError&) {
          v = std::numeric_limits<float>::quiet_NaN();
          ++failed;
        }
      }
    if (failed)
      diag.warn(inputMessage(path, "heights",
                             std::to_string(failed) + " samples PROJ cannot transform into the scene CRS (no-data)"));
    return;
  }
  const double toMetre = bandToMetre > 0.0 ? bandToMetre : sourceUnit;
  if (toMetre != 1.0)
    for (float& v : f.z) v = float(double(v) * toMetre);  // NaN stays NaN
  if (!t.sameCrs())
    diag.warn(inputMessage(
        path, "heights",
        "taken as they are, only converted to metres: " + t.source().summary() + " and the scene's " +
            t.scene().summary() +
            " do not both have a vertical axis; declare compound CRSs (e.g. EPSG:2154+5720) to transform heights "
            "between vertical datums"));
}

// A GDAL spatial reference for the horizontal part of `definition`, x = easting or longitude
// (GDAL's raster convention).
OGRSpatialReference horizontalSrs(const std::string& definition, const std::string& path) {
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(definition.c_str(), OGRSpatialReference::SET_FROM_USER_INPUT_LIMITATIONS_get()) !=
      OGRERR_NONE)
    throw InputError(inputMessage(path, "CRS", "GDAL cannot read '" + definition + "': " + gdal::lastError("unknown")));
  if (srs.IsCompound()) srs.StripVertical();
  if (srs.GetAxesCount() == 3) srs.DemoteTo2D(nullptr);
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

// An in-memory dataset holding `f` (no-data as NaN), for GDAL's warper.
DatasetPtr memoryDataset(const Heightfield& f, const OGRSpatialReference& srs, const std::string& path) {
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("MEM");
  if (!driver) throw InputError(inputMessage(path, "", "GDAL has no MEM driver"));
  DatasetPtr ds(driver->Create("", f.cols, f.rows, 1, GDT_Float32, nullptr));
  if (!ds) throw InputError(inputMessage(path, "", "cannot make an in-memory copy: " + gdal::lastError("MEM")));
  double gt[6] = {f.originX, f.cellX, 0.0, f.originY, 0.0, f.cellY};
  ds->SetGeoTransform(gt);
  ds->SetSpatialRef(&srs);
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
  std::vector<float> samples = f.z;  // RasterIO takes a non-const buffer even for writing
  if (band->RasterIO(GF_Write, 0, 0, f.cols, f.rows, samples.data(), f.cols, f.rows, GDT_Float32, 0, 0, nullptr) !=
      CE_None)
    throw InputError(inputMessage(path, "", "cannot make an in-memory copy: " + gdal::lastError("I/O error")));
  return ds;
}

// The cell size of the warped grid, in the scene CRS's units: the finer of the source's two cell
// sides as they land in the scene at the raster's centre, so that no source sample is skipped (a
// geographic raster's cells are far from square in metres). 0 when PROJ cannot say: GDAL's own
// suggestion then.
double warpedCellSize(const Heightfield& f, const GeoTransform& t) {
  try {
    const glm::dvec2 c = f.samplePosition(f.cols / 2, f.rows / 2);
    const glm::dvec3 o = t.point({c.x, c.y, 0.0});
    const double dx = glm::length(glm::dvec2(t.point({c.x + f.cellX, c.y, 0.0}) - o));
    const double dy = glm::length(glm::dvec2(t.point({c.x, c.y + f.cellY, 0.0}) - o));
    return std::min(dx, dy) / t.scene().horizontalToMetre;
  } catch (const InputError&) {
    return 0.0;
  }
}

// `f` resampled into `to` by GDAL's warper: the exact transformation at every cell (-et 0: no
// approximation), no-data (NaN) honoured, square cells of `cell` (0: GDAL's suggestion). Bilinear
// *interpolation*: a DTM samples a surface, and where the target is coarser than the source
// along an axis GDAL would otherwise widen its kernel into a filter whose discrete weights are
// off-centre (a bias of up to a tenth of a cell times the slope); XSCALE = YSCALE = 1 keep the
// four-sample kernel.
Heightfield warpGrid(const Heightfield& f, const OGRSpatialReference& from, const OGRSpatialReference& to, double cell,
                     const std::string& path, Diagnostics& diag) {
  const DatasetPtr source = memoryDataset(f, from, path);
  char* wkt = nullptr;
  const char* const wktOptions[] = {"FORMAT=WKT2_2019", nullptr};
  to.exportToWkt(&wkt, wktOptions);
  const std::string target = wkt ? wkt : "";
  CPLFree(wkt);
  CPLStringList args;
  for (const char* a : {"-of", "MEM", "-r", "bilinear", "-et", "0", "-srcnodata", "nan", "-dstnodata", "nan", "-ot",
                        "Float32", "-wo", "XSCALE=1", "-wo", "YSCALE=1", "-t_srs"})
    args.AddString(a);
  args.AddString(target.c_str());
  if (cell > 0.0) {
    const std::string size = CPLSPrintf("%.17g", cell);
    for (const char* a : {"-tr", size.c_str(), size.c_str()}) args.AddString(a);
  }
  GDALWarpAppOptions* options = GDALWarpAppOptionsNew(args.List(), nullptr);
  if (!options) throw InputError(inputMessage(path, "", "GDAL refuses the warp options: " + gdal::lastError("?")));
  GDALDatasetH input = GDALDataset::ToHandle(source.get());
  int usageError = 0;
  DatasetPtr warped(GDALDataset::FromHandle(GDALWarp("", nullptr, 1, &input, options, &usageError)));
  GDALWarpAppOptionsFree(options);
  if (!warped)
    throw InputError(inputMessage(path, "", "cannot warp into the scene CRS: " + gdal::lastError("GDALWarp failed")));
  return readGrid(warped.get(), path, &diag);
}

}  // namespace

Heightfield readHeightfield(const std::string& path) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  const DatasetPtr ds = openRaster(path);
  return readGrid(ds.get(), path, nullptr);
}

GeoreferencedHeightfield readHeightfield(const std::string& path, const SourceGeoref& georef, Diagnostics& diag) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  const gdal::ServiceProgress progress("terrain", path);  // a line per service request
  const DatasetPtr ds = openRaster(path);
  GeoreferencedHeightfield out;
  Heightfield f = readGrid(ds.get(), path, &diag);
  gdal::trimTileCache();  // a WMTS's tiles in GDAL's cache, under histoview's cap
  const double bandToMetre = bandUnitToMetre(ds.get(), path, diag);
  out.sourceCrs = sourceCrsOf(georef, f.crs);
  if (out.sourceCrs.empty()) {  // no scene CRS: a local frame, the raster as it is
    out.sourceCrs = georef.crs.empty() ? f.crs : georef.crs;
    out.field = std::move(f);
    return out;
  }
  const GeoTransform t = sourceTransform(georef, out.sourceCrs, path, diag);
  if (t.source().geocentric || t.scene().geocentric)
    throw InputError(inputMessage(path, "CRS",
                                  "a terrain raster and the scene need a CRS with a vertical z (projected or "
                                  "compound), not a geocentric one: " +
                                      (t.source().geocentric ? t.source() : t.scene()).summary()));
  if (!t.isIdentity() || (bandToMetre > 0.0 && bandToMetre != 1.0)) {
    heightsToScene(f, bandToMetre, t, path, diag);
    if (!t.sameHorizontalCrs()) {
      const int cols = f.cols, rows = f.rows;
      f = warpGrid(f, horizontalSrs(out.sourceCrs, path), horizontalSrs(georef.sceneCrs, path), warpedCellSize(f, t),
                   path, diag);
      log::debug("terrain: " + path + ": warped " + std::to_string(cols) + "x" + std::to_string(rows) + " -> " +
                 std::to_string(f.cols) + "x" + std::to_string(f.rows) + " cells of " + std::to_string(f.cellX) +
                 " scene units");
    }
    // Both grids are now in the scene CRS's own unit (feet for EPSG:2994): the scene frame is metres.
    const double k = t.scene().horizontalToMetre;
    f.originX *= k, f.originY *= k, f.cellX *= k, f.cellY *= k;
  }
  f.crs = georef.sceneCrs;
  out.field = std::move(f);
  return out;
}

void writeGeoTiff(const std::string& path, const Heightfield& field, const std::string& crs,
                  const std::string& heightUnit) {
  if (field.cols <= 0 || field.rows <= 0 || field.z.size() != size_t(field.cols) * field.rows)
    throw std::invalid_argument("writeGeoTiff: heightfield has " + std::to_string(field.z.size()) + " samples for " +
                                std::to_string(field.cols) + " x " + std::to_string(field.rows));
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw InputError(inputMessage(path, "", "GDAL has no GTiff driver"));

  OGRSpatialReference srs;
  if (!crs.empty()) {
    if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE)
      throw InputError(inputMessage(path, "crs", "cannot interpret '" + crs + "': " + gdal::lastError("unknown CRS")));
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  }

  char** options = nullptr;
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "PREDICTOR", "3");  // floating-point predictor: DTMs compress well
  DatasetPtr ds(driver->Create(path.c_str(), field.cols, field.rows, 1, GDT_Float32, options));
  CSLDestroy(options);
  if (!ds) throw InputError(inputMessage(path, "", "cannot create: " + gdal::lastError("GTiff driver refused")));

  double gt[6] = {field.originX, field.cellX, 0.0, field.originY, 0.0, field.cellY};
  ds->SetGeoTransform(gt);
  if (!crs.empty()) ds->SetSpatialRef(&srs);
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (!heightUnit.empty()) band->SetUnitType(heightUnit.c_str());
  for (float v : field.z)
    if (std::isnan(v)) {
      band->SetNoDataValue(std::numeric_limits<double>::quiet_NaN());
      break;
    }
  // RasterIO takes a non-const buffer even for writing.
  std::vector<float> samples = field.z;
  if (band->RasterIO(GF_Write, 0, 0, field.cols, field.rows, samples.data(), field.cols, field.rows, GDT_Float32, 0, 0,
                     nullptr) != CE_None)
    throw InputError(inputMessage(path, "", "write failed: " + gdal::lastError("I/O error")));
  ds->FlushCache(true);
  if (CPLGetLastErrorType() >= CE_Failure)
    throw InputError(inputMessage(path, "", "write failed: " + gdal::lastError("I/O error")));
}

void writeTiledGeoTiff(const std::string& path, int cols, int rows, double originX, double originY, double cell,
                       const std::string& crs, const std::function<float(int, int)>& height, bool sparse) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw InputError(inputMessage(path, "", "GDAL has no GTiff driver"));
  constexpr int kBlock = 512;
  CPLStringList options;
  options.SetNameValue("TILED", "YES");
  options.SetNameValue("BLOCKXSIZE", "512");
  options.SetNameValue("BLOCKYSIZE", "512");
  options.SetNameValue("COMPRESS", "DEFLATE");
  options.SetNameValue("PREDICTOR", "3");
  options.SetNameValue("BIGTIFF", "IF_SAFER");
  if (sparse) options.SetNameValue("SPARSE_OK", "TRUE");
  DatasetPtr ds(driver->Create(path.c_str(), cols, rows, 1, GDT_Float32, options.List()));
  if (!ds) throw InputError(inputMessage(path, "", "cannot create: " + gdal::lastError("GTiff driver refused")));
  double gt[6] = {originX, cell, 0.0, originY, 0.0, -cell};
  ds->SetGeoTransform(gt);
  if (!crs.empty()) {
    OGRSpatialReference srs;
    if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE)
      throw InputError(inputMessage(path, "crs", "cannot interpret '" + crs + "'"));
    ds->SetSpatialRef(&srs);
  }
  constexpr float kNoData = -9999.0f;
  GDALRasterBand* band = ds->GetRasterBand(1);
  band->SetNoDataValue(kNoData);
  std::vector<float> block(size_t(kBlock) * kBlock);
  for (int by = 0; by < rows; by += kBlock)
    for (int bx = 0; bx < cols; bx += kBlock) {
      const int w = std::min(kBlock, cols - bx), h = std::min(kBlock, rows - by);
      bool any = false;
      for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
          const float v = height(bx + i, by + j);
          any = any || !std::isnan(v);
          block[size_t(j) * w + i] = std::isnan(v) ? kNoData : v;
        }
      if (sparse && !any) continue;
      if (band->RasterIO(GF_Write, bx, by, w, h, block.data(), w, h, GDT_Float32, 0, 0, nullptr) != CE_None)
        throw InputError(inputMessage(path, "", "write failed: " + gdal::lastError("I/O error")));
    }
  ds->FlushCache(true);
  if (CPLGetLastErrorType() >= CE_Failure)
    throw InputError(inputMessage(path, "", "write failed: " + gdal::lastError("I/O error")));
}

void addOverviews(const std::string& path, const std::vector<int>& factors, const std::string& resampling) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  gdal::requireOpenable(path, "raster", false);
  DatasetPtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE));
  if (!ds) throw InputError(inputMessage(path, "", "cannot open for update: " + gdal::lastError("unknown format")));
  std::vector<int> list = factors;
  if (ds->BuildOverviews(resampling.c_str(), int(list.size()), list.data(), 0, nullptr, nullptr, nullptr) != CE_None)
    throw InputError(inputMessage(path, "overviews", "cannot build: " + gdal::lastError("GDAL refused")));
}

// ---------------------------------------------------------------------------------------------
// TerrainRaster (hv/io/native/terrain_raster.h)

RasterSize rasterSize(const std::string& path) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  const gdal::ServiceProgress progress("terrain", path);
  const DatasetPtr ds = openRaster(path);
  return {ds->GetRasterXSize(), ds->GetRasterYSize(), ds->GetRasterBand(1)->GetOverviewCount()};
}

struct TerrainRaster::Impl {
  DatasetPtr ds;
  GDALRasterBand* band = nullptr;
  std::string path, sourceCrs;
  TerrainGrid grid;
  double gt[6] = {0, 1, 0, 0, 0, -1};  // the source's geotransform (PROJ takes source coordinates)
  // Raw values -> heights: no-data, scale and offset (as readGrid).
  int hasNoData = 0;
  double noData = 0.0;
  double scale = 1.0, offset = 0.0;
  bool rescale = false;
  // Heights -> scene metres: a factor, or PROJ sample by sample (then toCrsUnit first).
  double toMetre = 1.0, toCrsUnit = 1.0;
  std::optional<GeoTransform> heights;
  // The grids a level may be read from, finest first (ratio 1: band 1 itself).
  struct Source {
    GDALRasterBand* band = nullptr;  // null: the pyramid in memory
    int cols = 0, rows = 0;
    double rx = 1.0, ry = 1.0;
    std::vector<float> z;
  };
  std::vector<Source> sources;
  int gdalOverviews = 0, pyramidLevels = 0;
  mutable std::mutex mutex;  // GDAL datasets are not thread-safe
  mutable TerrainRasterStats stats;

  void clean(std::vector<float>& v) const {
    const float noDataF = float(noData);
    for (float& x : v) {
      if (hasNoData && (x == noDataF || (std::isnan(noData) && std::isnan(x))))
        x = std::numeric_limits<float>::quiet_NaN();
      else if (rescale)
        x = float(double(x) * scale + offset);
    }
  }
  // Samples [x0, x0 + w) x [y0, y0 + h) of a source, cleaned.
  std::vector<float> window(const Source& s, int x0, int y0, int w, int h) const {
    std::vector<float> out(size_t(w) * size_t(h));
    if (!s.band) {
      for (int j = 0; j < h; ++j) std::copy_n(&s.z[size_t(y0 + j) * s.cols + x0], w, &out[size_t(j) * w]);
      stats.pyramidSamples += out.size();
      return out;
    }
    if (s.band->RasterIO(GF_Read, x0, y0, w, h, out.data(), w, h, GDT_Float32, 0, 0, nullptr) != CE_None)
      throw InputError(inputMessage(path, "band 1", "read failed: " + gdal::lastError("I/O error")));
    (s.band == band ? stats.fullResolutionSamples : stats.overviewSamples) += out.size();
    clean(out);
    return out;
  }
  void buildPyramid(Diagnostics& diag);
};

TerrainRaster::TerrainRaster() : impl_(std::make_unique<Impl>()) {}
TerrainRaster::~TerrainRaster() = default;
const TerrainGrid& TerrainRaster::grid() const { return impl_->grid; }
const std::string& TerrainRaster::path() const { return impl_->path; }
const std::string& TerrainRaster::sourceCrs() const { return impl_->sourceCrs; }
int TerrainRaster::gdalOverviews() const { return impl_->gdalOverviews; }
int TerrainRaster::pyramidLevels() const { return impl_->pyramidLevels; }
TerrainRasterStats TerrainRaster::stats() const {
  const std::lock_guard<std::mutex> lock(impl_->mutex);
  return impl_->stats;
}

// The pyramid of averages, from the coarsest grid the file has: its blocks of f x f (f the
// smallest power of two that brings it within kTerrainPyramidCells) averaged strip by strip, then
// halved until one tile's worth is left.
void TerrainRaster::Impl::buildPyramid(Diagnostics& diag) {
  const auto t0 = std::chrono::steady_clock::now();
  const Source from = sources.back();
  int f = 2;
  auto fits = [&](int k) {
    return std::uint64_t((from.cols + k - 1) / k) * std::uint64_t((from.rows + k - 1) / k) <= kTerrainPyramidCells;
  };
  while (!fits(f)) f *= 2;
  Source base;
  base.cols = (from.cols + f - 1) / f;
  base.rows = (from.rows + f - 1) / f;
  base.rx = from.rx * f;
  base.ry = from.ry * f;
  base.z.assign(size_t(base.cols) * base.rows, std::numeric_limits<float>::quiet_NaN());
  std::vector<double> sum(static_cast<size_t>(base.cols));
  std::vector<std::uint32_t> count(static_cast<size_t>(base.cols));
  int blockCols = 0, blockRows = 0;
  from.band->GetBlockSize(&blockCols, &blockRows);
  for (int r = 0; r < base.rows; ++r) {
    const int y0 = r * f, h = std::min(f, from.rows - y0);
    // Once a row of blocks is done, GDAL's block cache lets it go: the pass holds one row of
    // blocks, not the raster (GDAL's cache may otherwise grow to 5% of the memory).
    if (r > 0 && blockRows > 0 && y0 / blockRows != (y0 - f) / blockRows) from.band->FlushCache(false);
    std::vector<float> strip(size_t(from.cols) * h);
    if (from.band->RasterIO(GF_Read, 0, y0, from.cols, h, strip.data(), from.cols, h, GDT_Float32, 0, 0, nullptr) !=
        CE_None)
      throw InputError(inputMessage(path, "band 1", "read failed: " + gdal::lastError("I/O error")));
    stats.pyramidBuildSamples += strip.size();
    clean(strip);
    std::fill(sum.begin(), sum.end(), 0.0);
    std::fill(count.begin(), count.end(), 0u);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < from.cols; ++i) {
        const float v = strip[size_t(j) * from.cols + i];
        if (std::isnan(v)) continue;
        sum[size_t(i / f)] += v;
        ++count[size_t(i / f)];
      }
    for (int c = 0; c < base.cols; ++c)
      if (count[c]) base.z[size_t(r) * base.cols + c] = float(sum[c] / count[c]);
  }
  sources.push_back(std::move(base));
  pyramidLevels = 1;
  while (std::max(sources.back().cols, sources.back().rows) > 64) {
    const Source& prev = sources.back();
    Source next;
    next.z = averageBlocks(prev.z, prev.cols, prev.rows, 2, next.cols, next.rows);
    next.rx = prev.rx * 2, next.ry = prev.ry * 2;
    sources.push_back(std::move(next));
    ++pyramidLevels;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const Source& finest = sources[sources.size() - size_t(pyramidLevels)];
  diag.warn(inputMessage(path, "overviews",
                         std::string(gdalOverviews ? "none coarse enough" : "none") + " for a raster of " +
                             std::to_string(grid.cols) + " x " + std::to_string(grid.rows) +
                             " cells: a pyramid of averages was built in memory (" + std::to_string(pyramidLevels) +
                             " levels, the finest " + std::to_string(finest.cols) + " x " +
                             std::to_string(finest.rows) + ", " + CPLSPrintf("%.1f", seconds) +
                             " s; nothing written to disk); `gdaladdo -r average` on the file makes this unnecessary"));
}

std::shared_ptr<TerrainRaster> TerrainRaster::open(const std::string& path, const SourceGeoref& georef,
                                                   Diagnostics& diag, std::string& whyNot) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  const gdal::ServiceProgress progress("terrain", path);
  std::shared_ptr<TerrainRaster> raster(new TerrainRaster());
  Impl& m = *raster->impl_;
  m.path = path;
  m.ds = openRaster(path);
  m.band = m.ds->GetRasterBand(1);
  // The checks of readGrid.
  if (m.ds->GetGeoTransform(m.gt) != CE_None)
    throw InputError(inputMessage(path, "geotransform", "missing: the elevations are not georeferenced"));
  if (m.gt[2] != 0.0 || m.gt[4] != 0.0)
    throw InputError(inputMessage(path, "geotransform", "rotated or sheared rasters are not supported"));
  if (m.gt[1] == 0.0 || m.gt[5] == 0.0) throw InputError(inputMessage(path, "geotransform", "zero pixel size"));
  const int cols = m.ds->GetRasterXSize(), rows = m.ds->GetRasterYSize();
  if (cols < 2 || rows < 2)
    throw InputError(inputMessage(
        path, "size",
        std::to_string(cols) + " x " + std::to_string(rows) + " cells: expected at least 2 x 2 to make a terrain"));
  m.noData = m.band->GetNoDataValue(&m.hasNoData);
  int hasScale = 0, hasOffset = 0;
  const double scale = m.band->GetScale(&hasScale), offset = m.band->GetOffset(&hasOffset);
  m.scale = hasScale ? scale : 1.0;
  m.offset = hasOffset ? offset : 0.0;
  m.rescale = m.scale != 1.0 || m.offset != 0.0;

  // Into the scene frame, as readHeightfield(path, georef, diag).
  const std::string declared = gdal::crsDefinition(m.ds->GetSpatialRef());
  double horizontalToMetre = 1.0;
  m.sourceCrs = sourceCrsOf(georef, declared);
  if (m.sourceCrs.empty()) {
    m.sourceCrs = georef.crs.empty() ? declared : georef.crs;
  } else {
    GeoTransform t = sourceTransform(georef, m.sourceCrs, path, diag);
    if (t.source().geocentric || t.scene().geocentric)
      throw InputError(inputMessage(path, "CRS",
                                    "a terrain raster and the scene need a CRS with a vertical z (projected or "
                                    "compound), not a geocentric one: " +
                                        (t.source().geocentric ? t.source() : t.scene()).summary()));
    const double bandToMetre = bandUnitToMetre(m.ds.get(), path, diag);
    if (!t.isIdentity() || (bandToMetre > 0.0 && bandToMetre != 1.0)) {
      if (!t.sameHorizontalCrs()) {
        whyNot = "its horizontal CRS (" + t.source().summary() + ") is not the scene's (" + t.scene().summary() +
                 "): it would have to be warped whole";
        return nullptr;
      }
      const double sourceUnit = t.source().heightToMetre();
      if (t.transformsHeights() && !t.sameCrs()) {
        m.toCrsUnit = bandToMetre > 0.0 ? bandToMetre / sourceUnit : 1.0;
        m.heights.emplace(std::move(t));
      } else {
        m.toMetre = bandToMetre > 0.0 ? bandToMetre : sourceUnit;
        if (!t.sameCrs())
          diag.warn(inputMessage(
              path, "heights",
              "taken as they are, only converted to metres: " + t.source().summary() + " and the scene's " +
                  t.scene().summary() +
                  " do not both have a vertical axis; declare compound CRSs (e.g. EPSG:2154+5720) to transform "
                  "heights between vertical datums"));
        horizontalToMetre = t.scene().horizontalToMetre;
      }
      if (m.heights) horizontalToMetre = m.heights->scene().horizontalToMetre;
    }
  }
  m.grid = {cols,
            rows,
            m.gt[0] * horizontalToMetre,
            m.gt[3] * horizontalToMetre,
            m.gt[1] * horizontalToMetre,
            m.gt[5] * horizontalToMetre};

  // The grids to read from: band 1, its overviews (coarser and coarser), the pyramid if needed.
  m.sources.push_back({m.band, cols, rows, 1.0, 1.0, {}});
  std::vector<Impl::Source> overviews;
  for (int i = 0; i < m.band->GetOverviewCount(); ++i) {
    GDALRasterBand* o = m.band->GetOverview(i);
    if (!o || o->GetXSize() < 1 || o->GetYSize() < 1 || o->GetXSize() >= cols) continue;
    overviews.push_back(
        {o, o->GetXSize(), o->GetYSize(), double(cols) / o->GetXSize(), double(rows) / o->GetYSize(), {}});
  }
  std::sort(overviews.begin(), overviews.end(), [](const auto& a, const auto& b) { return a.rx < b.rx; });
  m.gdalOverviews = int(overviews.size());
  for (auto& o : overviews) m.sources.push_back(std::move(o));
  const Impl::Source& coarsest = m.sources.back();
  if (std::uint64_t(cols) * std::uint64_t(rows) > kTerrainTilesAboveCells &&
      std::uint64_t(coarsest.cols) * std::uint64_t(coarsest.rows) > kTerrainPyramidCells)
    m.buildPyramid(diag);
  else if (m.gdalOverviews)
    log::info("terrain: " + path + ": read through its " + std::to_string(m.gdalOverviews) + " overview(s)");
  return raster;
}

std::vector<float> TerrainRaster::levelSamples(int step, int kx0, int ky0, int nx, int ny) const {
  const Impl& m = *impl_;
  const std::lock_guard<std::mutex> lock(m.mutex);
  const gdal::QuietErrors quiet;
  // The coarsest grid no coarser than the step; a coarser one when that window would be too large
  // (never in practice: the pyramid is within kTerrainPyramidCells).
  size_t pick = 0;
  for (size_t i = 0; i < m.sources.size(); ++i)
    if (m.sources[i].rx <= step * (1.0 + 1e-9)) pick = i;
  OverviewAxis ax, ay;
  OverviewSpan sx, sy;
  for (;; ++pick) {
    const Impl::Source& s = m.sources[pick];
    ax = {m.grid.cols, s.cols, s.rx};
    ay = {m.grid.rows, s.rows, s.ry};
    sx = overviewSpan(ax, step, kx0, nx);
    sy = overviewSpan(ay, step, ky0, ny);
    const std::uint64_t cells = std::uint64_t(sx.hi - sx.lo + 1) * std::uint64_t(sy.hi - sy.lo + 1);
    if (cells <= kTerrainPyramidCells) break;
    if (pick + 1 == m.sources.size())
      throw InputError(inputMessage(m.path, "band 1",
                                    "a window of " + std::to_string(cells) + " samples is over the limit of " +
                                        std::to_string(kTerrainPyramidCells)));
  }
  const Impl::Source& s = m.sources[pick];
  const int w = sx.hi - sx.lo + 1, h = sy.hi - sy.lo + 1;
  m.stats.largestWindow = std::max(m.stats.largestWindow, std::uint64_t(w) * std::uint64_t(h));
  ++m.stats.reads;
  const std::vector<float> window = m.window(s, sx.lo, sy.lo, w, h);
  std::vector<float> out = resampleOverview(window, ax, ay, sx, sy, step, kx0, ky0, nx, ny);
  if (m.heights) {
    for (int b = 0; b < ny; ++b)
      for (int a = 0; a < nx; ++a) {
        float& v = out[size_t(b) * nx + a];
        if (std::isnan(v)) continue;
        const double i = double(std::min<std::int64_t>(std::int64_t(kx0 + a) * step, m.grid.cols - 1));
        const double j = double(std::min<std::int64_t>(std::int64_t(ky0 + b) * step, m.grid.rows - 1));
        const double x = m.gt[0] + (i + 0.5) * m.gt[1], y = m.gt[3] + (j + 0.5) * m.gt[5];
        try {
          v = float(m.heights->point({x, y, double(v) * m.toCrsUnit}).z);
        } catch (const InputError&) {
          v = std::numeric_limits<float>::quiet_NaN();
        }
      }
  } else if (m.toMetre != 1.0) {
    for (float& v : out) v = float(double(v) * m.toMetre);
  }
  return out;
}

}  // namespace hv
