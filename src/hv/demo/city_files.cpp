#include "hv/demo/city_files.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <mutex>
#include <stdexcept>
#include <vector>

namespace hv::demo::detail {

namespace {

void registerGdal() {
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

std::string lastError() {
  const char* m = CPLGetLastErrorMsg();
  return m && *m ? m : "unknown GDAL error";
}

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::runtime_error(path + ": " + what + " (" + lastError() + ")");
}

OGRSpatialReference spatialReference(const std::string& path, const std::string& crs) {
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE) fail(path, "cannot interpret the CRS '" + crs + "'");
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

struct DatasetCloser {
  void operator()(GDALDataset* d) const { GDALClose(GDALDataset::ToHandle(d)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

}  // namespace

void writeCog(const std::string& path, const Heightfield& field, const std::string& crs) {
  if (field.cols <= 0 || field.rows <= 0 || field.z.size() != size_t(field.cols) * field.rows)
    throw std::invalid_argument(path + ": heightfield has " + std::to_string(field.z.size()) + " samples for " +
                                std::to_string(field.cols) + " x " + std::to_string(field.rows));
  registerGdal();
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
  if (!mem || !cog) fail(path, "GDAL has no MEM or COG driver");
  DatasetPtr ds(mem->Create("", field.cols, field.rows, 1, GDT_Float32, nullptr));
  if (!ds) fail(path, "cannot create the raster in memory");
  double gt[6] = {field.originX, field.cellX, 0.0, field.originY, 0.0, field.cellY};
  ds->SetGeoTransform(gt);
  const OGRSpatialReference srs = spatialReference(path, crs);
  ds->SetSpatialRef(&srs);
  std::vector<float> samples = field.z;  // RasterIO takes a non-const buffer even for writing
  if (ds->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, field.cols, field.rows, samples.data(), field.cols, field.rows,
                                     GDT_Float32, 0, 0, nullptr) != CE_None)
    fail(path, "cannot fill the raster");
  std::vector<int> levels;
  for (int f = 2; std::max(field.cols, field.rows) / f >= 16; f *= 2) levels.push_back(f);
  if (!levels.empty() &&
      ds->BuildOverviews("AVERAGE", int(levels.size()), levels.data(), 0, nullptr, nullptr, nullptr) != CE_None)
    fail(path, "cannot build the overviews");
  char** options = nullptr;
  options = CSLSetNameValue(options, "BLOCKSIZE", "256");
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "PREDICTOR", "YES");  // floating-point predictor for Float32
  options = CSLSetNameValue(options, "OVERVIEWS", "FORCE_USE_EXISTING");
  DatasetPtr out(cog->CreateCopy(path.c_str(), ds.get(), FALSE, options, nullptr, nullptr));
  CSLDestroy(options);
  if (!out) fail(path, "cannot write the Cloud-Optimized GeoTIFF");
  out.reset();
  if (CPLGetLastErrorType() >= CE_Failure) fail(path, "write failed");
}

struct GeoPackageWriter::Impl {
  DatasetPtr ds;
  OGRLayer* layer = nullptr;
  int idField = -1, heightField = -1;
  std::size_t inTransaction = 0;
};

namespace {
constexpr std::size_t kFeaturesPerTransaction = 20000;
// GeoPackage writes the time of writing into gpkg_contents; a fixed one keeps the file reproducible.
constexpr const char* kFixedDate = "2000-01-01T00:00:00.000Z";
}  // namespace

GeoPackageWriter::GeoPackageWriter(const std::string& path, const std::string& crs)
    : impl_(std::make_unique<Impl>()), path_(path) {
  registerGdal();
  CPLSetThreadLocalConfigOption("OGR_CURRENT_DATE", kFixedDate);
  GDALDriver* gpkg = GetGDALDriverManager()->GetDriverByName("GPKG");
  if (!gpkg) fail(path, "GDAL has no GPKG driver");
  VSIUnlink(path.c_str());  // GPKG would open an existing file and add to it
  impl_->ds.reset(gpkg->Create(path.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
  if (!impl_->ds) fail(path, "cannot create the GeoPackage");
  OGRSpatialReference srs = spatialReference(path, crs);  // CreateLayer takes a non-const one
  char** options = nullptr;
  options = CSLSetNameValue(options, "SPATIAL_INDEX", "YES");
  options = CSLSetNameValue(options, "GEOMETRY_NAME", "geom");
  impl_->layer = impl_->ds->CreateLayer("buildings", &srs, wkbPolygon, options);
  CSLDestroy(options);
  if (!impl_->layer) fail(path, "cannot create the layer 'buildings'");
  OGRFieldDefn id("id", OFTString), height("height", OFTReal);
  if (impl_->layer->CreateField(&id) != OGRERR_NONE || impl_->layer->CreateField(&height) != OGRERR_NONE)
    fail(path, "cannot create the fields 'id' and 'height'");
  impl_->idField = impl_->layer->GetLayerDefn()->GetFieldIndex("id");
  impl_->heightField = impl_->layer->GetLayerDefn()->GetFieldIndex("height");
}

GeoPackageWriter::~GeoPackageWriter() { CPLSetThreadLocalConfigOption("OGR_CURRENT_DATE", nullptr); }

void GeoPackageWriter::add(const Footprint& fp) {
  if (!impl_->ds) throw std::logic_error(path_ + ": GeoPackage already closed");
  if (impl_->inTransaction == 0 && impl_->ds->StartTransaction() != OGRERR_NONE)
    fail(path_, "cannot start a transaction");
  OGRFeature feature(impl_->layer->GetLayerDefn());
  feature.SetField(impl_->idField, fp.id.c_str());
  feature.SetField(impl_->heightField, fp.height.value_or(0.0));
  OGRPolygon polygon;
  for (const auto& ring : fp.rings) {
    OGRLinearRing r;
    for (glm::dvec2 p : ring) r.addPoint(p.x, p.y);
    if (!ring.empty()) r.addPoint(ring.front().x, ring.front().y);
    polygon.addRing(&r);
  }
  feature.SetGeometry(&polygon);
  if (impl_->layer->CreateFeature(&feature) != OGRERR_NONE) fail(path_, "cannot write footprint " + fp.id);
  ++count_;
  if (++impl_->inTransaction == kFeaturesPerTransaction) {
    if (impl_->ds->CommitTransaction() != OGRERR_NONE) fail(path_, "cannot commit");
    impl_->inTransaction = 0;
  }
}

void GeoPackageWriter::close() {
  if (!impl_->ds) return;
  if (impl_->inTransaction > 0 && impl_->ds->CommitTransaction() != OGRERR_NONE) fail(path_, "cannot commit");
  impl_->inTransaction = 0;
  CPLErrorReset();
  impl_->ds.reset();  // writes the spatial index
  if (CPLGetLastErrorType() >= CE_Failure) fail(path_, "cannot close");
}

}  // namespace hv::demo::detail
