// Fuzz target: scene.json (hv::loadScene). The input is written to scene.json in a private scratch
// directory that also holds small valid sources (dtm.asc, buildings.geojson, cameras.json,
// img.png), so that relative paths in the seeds reach the terrain, footprint and camera loaders;
// any other path points nowhere and must give an error, not a crash.
#include "fuzz_util.h"
#include "gdal_drivers.h"
#include "hv/io/native/scene_loader.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace {

const char* kDtm =
    "ncols 4\nnrows 4\nxllcorner -20\nyllcorner -20\ncellsize 10\nNODATA_value -9999\n"
    "1 1 2 2\n1 1 2 2\n1 -9999 2 2\n1 1 2 3\n";

const char* kBuildings = R"({"type":"FeatureCollection","features":[
{"type":"Feature","id":1,"properties":{"height":12},"geometry":{"type":"Polygon","coordinates":[[[0,0],[10,0],[10,10],[0,10],[0,0]]]}},
{"type":"Feature","id":2,"properties":{"height":"7.5","base":3},"geometry":{"type":"Polygon","coordinates":[[[-15,-15],[-5,-15],[-5,-5],[-15,-5],[-15,-15]],[[-12,-12],[-12,-8],[-8,-8],[-8,-12],[-12,-12]]]}}
]})";

const char* kCameras = R"({"cameras":[
{"id":"a","width":64,"height":48,"center":[0,-30,5],"rotation":[1,0,0,0,0,-1,0,1,0],"focal":[50,50],"principal":[32,24],"image":"img.png"},
{"id":"b","width":64,"height":48,"center":[5,-30,5],"rotation":[1,0,0,0,0,-1,0,1,0],"focal":[50,50],"principal":[32,24],"image":"img.png","mask":"missing.png"}
]})";

// Only the existence of img.png is checked at load time.
const char* kImage = "\x89PNG\r\n\x1a\n";

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  hv::fuzz::keepOnlyGdalDrivers({"GeoJSON", "GeoJSONSeq", "ESRIJSON", "TopoJSON", "AAIGrid", "GTiff"});
  hv::fuzz::writeScratch("dtm.asc", kDtm);
  hv::fuzz::writeScratch("buildings.geojson", kBuildings);
  hv::fuzz::writeScratch("cameras.json", kCameras);
  hv::fuzz::writeScratch("img.png", kImage);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string path = hv::fuzz::writeScratch("scene.json", data, size);
  hv::fuzz::expectOnlyInputErrors("scene_json", [&] {
    hv::Diagnostics diag;
    const hv::Scene scene = hv::loadScene(path, diag);
    // What `histoview info` does with a loaded scene.
    (void)scene.bounds();
    (void)scene.cameraSpacing();
  });
  return 0;
}
