// The orthophoto through GDAL (hv/io/native/orthophoto_reader.h).
#include <cpl_string.h>
#include <gdal_priv.h>
#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "hv/io/native/georef.h"
#include "hv/io/native/orthophoto_reader.h"
#include "hv/io/native/private/gdal_init.h"
#include "hv/io/native/private/service_fetch.h"
#include "hv/io/native/remote.h"
#include "hv/util/log.h"

namespace hv {

namespace {

struct DatasetCloser {
  void operator()(GDALDataset* ds) const { GDALClose(GDALDataset::ToHandle(ds)); }
};
using DatasetPtr = std::unique_ptr<GDALDataset, DatasetCloser>;

std::string wktOf(const OGRSpatialReference& srs) {
  char* wkt = nullptr;
  const char* const options[] = {"FORMAT=WKT2_2019", nullptr};
  srs.exportToWkt(&wkt, options);
  std::string s = wkt ? wkt : "";
  CPLFree(wkt);
  return s;
}

OGRSpatialReference srsFrom(const std::string& definition, const std::string& path, const std::string& field) {
  OGRSpatialReference srs;
  if (srs.SetFromUserInput(definition.c_str(), OGRSpatialReference::SET_FROM_USER_INPUT_LIMITATIONS_get()) !=
      OGRERR_NONE)
    throw InputError(inputMessage(path, field, "GDAL cannot read the CRS '" + definition + "'"));
  if (srs.IsCompound()) srs.StripVertical();
  if (srs.GetAxesCount() == 3) srs.DemoteTo2D(nullptr);
  srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

// The raster's finest pixel as it lands in the target CRS (its units), at the raster's centre;
// the geotransform's own pixel when there is no transformation.
double nativePixel(GDALDataset* ds, const double gt[6], const OGRSpatialReference* from,
                   const OGRSpatialReference* to) {
  const double own = std::min(std::hypot(gt[1], gt[4]), std::hypot(gt[2], gt[5]));
  if (!from || !to || from->IsSame(to)) return own;
  std::unique_ptr<OGRCoordinateTransformation> t(OGRCreateCoordinateTransformation(from, to));
  if (!t) return 0.0;
  const double cx = 0.5 * ds->GetRasterXSize(), cy = 0.5 * ds->GetRasterYSize();
  double x[3], y[3];
  for (int k = 0; k < 3; ++k) {
    const double px = cx + (k == 1 ? 1.0 : 0.0), py = cy + (k == 2 ? 1.0 : 0.0);
    x[k] = gt[0] + px * gt[1] + py * gt[2];
    y[k] = gt[3] + px * gt[4] + py * gt[5];
  }
  if (!t->Transform(3, x, y)) return 0.0;
  return std::min(std::hypot(x[1] - x[0], y[1] - y[0]), std::hypot(x[2] - x[0], y[2] - y[0]));
}

}  // namespace

Orthophoto readOrthophoto(const OrthophotoRequest& r, Diagnostics& diag) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  const std::string& path = r.path;
  const std::string& field = r.field;
  if (!(r.maxX > r.minX) || !(r.maxY > r.minY))
    throw InputError(inputMessage(path, field, "no terrain extent to read it over (expected a terrain)"));
  gdal::requireOpenable(path, field, false);
  // GDAL's WMS and WMTS drivers keep their tiles in histoview's cache folder (gdal::ensureRegistered).
  const gdal::ServiceProgress progress("the orthophoto", path);
  DatasetPtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
  if (!ds)
    throw InputError(inputMessage(path, field, "cannot open as a raster: " + gdal::lastError("unknown format")));
  const int bands = ds->GetRasterCount();
  if (bands < 1) throw InputError(inputMessage(path, field, "has no raster band (expected RGB, RGBA or grey)"));
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None)
    throw InputError(inputMessage(path, field, "has no geotransform (expected a georeferenced raster)"));

  // CRSs: orthophoto.crs, else the raster's, else the scene's; none at all without a scene CRS.
  std::unique_ptr<OGRSpatialReference> from, to;
  double toMetre = 1.0;
  if (!r.sceneCrs.empty()) {
    to = std::make_unique<OGRSpatialReference>(srsFrom(r.sceneCrs, path, "crs"));
    toMetre = describeCrs(r.sceneCrs).horizontalToMetre;
    if (!(toMetre > 0.0))
      throw InputError(inputMessage(path, field, "the scene CRS is not projected (expected metres or feet)"));
    if (!r.crs.empty()) {
      from = std::make_unique<OGRSpatialReference>(srsFrom(r.crs, path, "orthophoto.crs"));
    } else if (const OGRSpatialReference* own = ds->GetSpatialRef()) {
      from = std::make_unique<OGRSpatialReference>(*own);
      from->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    }
  }
  const bool warp = from && to && !from->IsSame(to.get());

  // The size: the rectangle at the resolution asked, else the raster's own, within the cap.
  const double w = (r.maxX - r.minX), h = (r.maxY - r.minY);
  double pixel = r.resolution > 0.0 ? r.resolution : nativePixel(ds.get(), gt, from.get(), to.get()) * toMetre;
  if (!(pixel > 0.0) || !std::isfinite(pixel)) pixel = std::max(w, h) / kMaxOrthophotoSide;
  pixel = std::max(pixel, std::max(w, h) / kMaxOrthophotoSide);
  // Whole pixels; an extent a whole number of the raster's pixels (its own grid) stays that number
  // despite rounding (1e-6 of a pixel).
  const int cols = std::clamp(int(std::ceil(w / pixel - 1e-6)), 1, kMaxOrthophotoSide);
  const int rows = std::clamp(int(std::ceil(h / pixel - 1e-6)), 1, kMaxOrthophotoSide);

  CPLStringList args;
  for (const char* a : {"-of", "MEM", "-r", "bilinear", "-ot", "Byte", "-dstalpha"}) args.AddString(a);
  const double k = 1.0 / toMetre;  // the scene frame (metres) into the scene CRS's units
  args.AddString("-te");
  for (double v : {r.minX * k, r.minY * k, r.maxX * k, r.maxY * k}) args.AddString(CPLSPrintf("%.17g", v));
  args.AddString("-ts");
  args.AddString(CPLSPrintf("%d", cols));
  args.AddString(CPLSPrintf("%d", rows));
  if (warp) {
    args.AddString("-s_srs");
    args.AddString(wktOf(*from).c_str());
    args.AddString("-t_srs");
    args.AddString(wktOf(*to).c_str());
  }
  // A palette becomes RGBA before the warp (bilinear over indices would mix unrelated colours).
  DatasetPtr expanded;
  GDALDatasetH input = GDALDataset::ToHandle(ds.get());
  if (bands == 1 && ds->GetRasterBand(1)->GetColorTable()) {
    const char* const expand[] = {"-of", "MEM", "-expand", "rgba", nullptr};
    GDALTranslateOptions* t = GDALTranslateOptionsNew(const_cast<char**>(expand), nullptr);
    expanded.reset(GDALDataset::FromHandle(GDALTranslate("", input, t, nullptr)));
    GDALTranslateOptionsFree(t);
    if (!expanded)
      throw InputError(inputMessage(path, field, "cannot expand its palette: " + gdal::lastError("GDALTranslate")));
    input = GDALDataset::ToHandle(expanded.get());
  }
  if (ds->GetRasterBand(1)->GetRasterDataType() != GDT_Byte)
    diag.warn(inputMessage(path, field,
                           std::string("samples of type ") +
                               GDALGetDataTypeName(ds->GetRasterBand(1)->GetRasterDataType()) +
                               ", not bytes: clipped to [0, 255]"));
  GDALWarpAppOptions* options = GDALWarpAppOptionsNew(args.List(), nullptr);
  if (!options) throw InputError(inputMessage(path, field, "GDAL refuses the warp options: " + gdal::lastError("?")));
  int usageError = 0;
  DatasetPtr out(GDALDataset::FromHandle(GDALWarp("", nullptr, 1, &input, options, &usageError)));
  GDALWarpAppOptionsFree(options);
  if (!out)
    throw InputError(inputMessage(path, field, "cannot read it over the terrain: " + gdal::lastError("GDALWarp failed")));

  // The colour bands (grey: one) and the alpha band the warp added (or kept).
  std::vector<int> colour;
  int alpha = 0;
  for (int b = 1; b <= out->GetRasterCount(); ++b) {
    if (out->GetRasterBand(b)->GetColorInterpretation() == GCI_AlphaBand)
      alpha = b;
    else if (colour.size() < 3)
      colour.push_back(b);
  }
  if (colour.empty()) throw InputError(inputMessage(path, field, "has only an alpha band (expected RGB or grey)"));
  if (colour.size() == 2) colour.resize(1);  // grey and something: grey
  Orthophoto o;
  o.path = path;
  o.width = cols;
  o.height = rows;
  o.minX = r.minX, o.minY = r.minY, o.maxX = r.maxX, o.maxY = r.maxY;
  o.rgba.assign(std::size_t(cols) * rows * 4, 255);
  std::vector<std::uint8_t> band(std::size_t(cols) * rows);
  for (int c = 0; c < 4; ++c) {
    const int b = c < 3 ? colour[std::min<std::size_t>(std::size_t(c), colour.size() - 1)] : alpha;
    if (b == 0) continue;
    if (out->GetRasterBand(b)->RasterIO(GF_Read, 0, 0, cols, rows, band.data(), cols, rows, GDT_Byte, 0, 0, nullptr) !=
        CE_None)
      throw InputError(inputMessage(path, field, "cannot read band " + std::to_string(b) + ": " +
                                                     gdal::lastError("I/O error")));
    for (std::size_t i = 0; i < band.size(); ++i) o.rgba[i * 4 + std::size_t(c)] = band[i];
  }
  log::debug("orthophoto: " + path + ": " + std::to_string(cols) + "x" + std::to_string(rows) + ", " +
             std::to_string(w / cols) + " m per pixel" + (warp ? ", warped into the scene CRS" : ""));
  gdal::trimTileCache();
  return o;
}

void writeOrthophotoCog(const std::string& path, const Orthophoto& o, const std::string& crs) {
  gdal::ensureRegistered();
  const gdal::QuietErrors quiet;
  if (o.empty()) throw InputError(inputMessage(path, "", "no image to write"));
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
  if (!mem || !cog) throw InputError(inputMessage(path, "", "GDAL has no MEM or COG driver"));
  const int channels = int(o.rgba.size() / (std::size_t(o.width) * o.height));
  DatasetPtr ds(mem->Create("", o.width, o.height, channels, GDT_Byte, nullptr));
  if (!ds) throw InputError(inputMessage(path, "", "cannot make an in-memory image: " + gdal::lastError("MEM")));
  const double gt[6] = {o.minX, o.metresPerPixelX(), 0.0, o.maxY, 0.0, -o.metresPerPixelY()};
  ds->SetGeoTransform(const_cast<double*>(gt));
  if (!crs.empty()) {
    OGRSpatialReference srs = srsFrom(crs, path, "crs");
    ds->SetSpatialRef(&srs);
  }
  std::vector<std::uint8_t> band(std::size_t(o.width) * o.height);
  for (int c = 0; c < channels; ++c) {
    for (std::size_t i = 0; i < band.size(); ++i) band[i] = o.rgba[i * std::size_t(channels) + std::size_t(c)];
    GDALRasterBand* b = ds->GetRasterBand(c + 1);
    b->SetColorInterpretation(c == 3 ? GCI_AlphaBand : GDALColorInterp(GCI_RedBand + c));
    if (b->RasterIO(GF_Write, 0, 0, o.width, o.height, band.data(), o.width, o.height, GDT_Byte, 0, 0, nullptr) !=
        CE_None)
      throw InputError(inputMessage(path, "", "cannot fill the in-memory image: " + gdal::lastError("I/O error")));
  }
  const char* const options[] = {"COMPRESS=DEFLATE", "BLOCKSIZE=256", nullptr};
  DatasetPtr written(cog->CreateCopy(path.c_str(), ds.get(), FALSE, const_cast<char**>(options), nullptr, nullptr));
  if (!written) throw InputError(inputMessage(path, "", "cannot write: " + gdal::lastError("COG driver")));
}

}  // namespace hv
