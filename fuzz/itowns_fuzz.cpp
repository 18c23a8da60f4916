// Fuzz target: iTowns oriented images (hv::readITownsCameras): the panoramas' GeoJSON orientations
// and the rig calibration. The input is the calibration, a line "%%", then the orientations;
// without the separator each file is fuzzed against a valid counterpart.
#include "fuzz_util.h"
#include "hv/io/native/itowns_cameras.h"

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

const char* kCalibration = R"([{"id": 300, "rotation": [1,0,0, 0,1,0, 0,0,1], "position": [0,0,0],
  "projection": [1000,0,512, 0,1000,512, 0,0,1], "size": [1024, 1024],
  "distortion": {"pps": [512, 512], "poly357": [1e-8, 0, 0], "limit": 700}}])";
const char* kOrientations = R"({"type": "FeatureCollection", "features": [{"type": "Feature",
  "geometry": {"type": "Point", "coordinates": [651000, 6862000, 40]},
  "properties": {"id": 7, "roll": 1, "pitch": 2, "heading": 90, "date": "2008-07-01"}}]})";

void read(const std::string& calibration, const std::string& orientations) {
  const std::string calib = hv::fuzz::writeScratch("calibration.json", calibration);
  const std::string poses = hv::fuzz::writeScratch("orientations.geojson", orientations);
  hv::fuzz::expectOnlyInputErrors("itowns", [&] {
    hv::Diagnostics diag;
    const auto photos = hv::readITownsCameras({poses, calib, "img/{panoId}-{cameraId}.jpg"}, diag, false);
    for (const hv::Photo& p : photos) {
      const hv::Camera& c = p.camera;
      if (c.width <= 0 || c.height <= 0 || c.width > 65536 || c.height > 65536) {
        std::fprintf(stderr, "itowns: BUG: camera '%s' read with %dx%d pixels\n", c.id.c_str(), c.width, c.height);
        std::abort();
      }
      (void)c.project(c.center + c.rayDirection(c.principal));
    }
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const size_t split = text.find("\n%%\n");
  if (split != std::string::npos) {
    read(text.substr(0, split + 1), text.substr(split + 4));
  } else {
    read(text, kOrientations);
    read(kCalibration, text);
  }
  return 0;
}
