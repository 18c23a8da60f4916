// Fuzz target: MicMac XML (hv::parseMicmacOrientation, hv::parseMicmacCalibration, ground control
// points and their image measures).
#include "fuzz_util.h"
#include "hv/io/native/micmac_cameras.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace {

// What the fuzzed orientation's FileInterne reads: a valid calibration with radial distortion,
// or the fuzzed text itself (so a calibration mutation is reached through either entry point).
const char* kCalibration =
    "<ExportAPERO><CalibrationInternConique><KnownConv>eConvApero_DistM2C</KnownConv><PP>320 240</PP>"
    "<F>1000</F><SzIm>640 480</SzIm><CalibDistortion><ModRad><CDist>320 240</CDist><CoeffDist>1e-7</CoeffDist>"
    "</ModRad></CalibDistortion></CalibrationInternConique></ExportAPERO>";

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hv::fuzz::expectOnlyInputErrors("micmac_xml orientation", [&] {
    const auto o = hv::parseMicmacOrientation(text, "Orientation-fuzz.jpg.xml",
                                              [](const std::string&) { return std::string(kCalibration); });
    (void)o.camera.project(o.camera.center + o.camera.rayDirection(o.camera.principal));
  });
  hv::fuzz::expectOnlyInputErrors("micmac_xml orientation+calibration", [&] {
    (void)hv::parseMicmacOrientation(text, "Orientation-fuzz.jpg.xml", [&](const std::string&) { return text; });
  });
  hv::fuzz::expectOnlyInputErrors("micmac_xml calibration", [&] {
    hv::Camera camera;
    hv::parseMicmacCalibration(text, "AutoCal-fuzz.xml", camera);
  });
  const std::string path = hv::fuzz::writeScratch("micmac.xml", data, size);
  hv::fuzz::expectOnlyInputErrors("micmac_xml ground points", [&] { (void)hv::readMicmacGroundPoints(path); });
  hv::fuzz::expectOnlyInputErrors("micmac_xml measures", [&] { (void)hv::readMicmacImageMeasures(path); });
  return 0;
}
