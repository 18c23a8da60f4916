#include <cpl_string.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

#include "hv/io/native/private/gdal_init.h"
#include "hv/io/native/raster.h"
#include "hv/util/log.h"

namespace hv {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(GDALDataset::ToHandle(ds)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

DatasetPtr openRaster(const std::string& path) {
  gdal::requireOpenable(path, "raster", false);
  DatasetPtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds)
    throw InputError(inputMessage(path, "", "cannot open as a raster: " + gdal::lastError("unknown format")));
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
    throw InputError(inputMessage(path, "size", size + " cells: too large to read even decimated (the limit is " +
                                                    std::to_string(kMaxRasterCells) +
                                                    " cells, docs/formats.md, Limits)"));
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
  if (band->RasterIO(GF_Read, 0, 0, sourceCols, sourceRows, field.z.data(), field.cols, field.rows, GDT_Float32, 0,
                     0, nullptr) != CE_None)
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
    diag.warn(inputMessage(path, "band 1 unit", std::string("'") + unit +
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
  const DatasetPtr ds = openRaster(path);
  GeoreferencedHeightfield out;
  Heightfield f = readGrid(ds.get(), path, &diag);
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
  if (!heightUnit.empty()) band->SetUnitType(heightUnit.c_str());
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
