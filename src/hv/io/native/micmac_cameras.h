// MicMac orientations: `Ori-Name/Orientation-<image>.xml` (ExportAPERO/OrientationConique) with the
// intrinsic calibration it names (`FileInterne`, an `AutoCal*.xml` CalibrationInternConique) or
// carries inline (`Interne`).
//
// Conventions (MicMac's `eConvApero_DistM2C`, checked against the files' own Verif/Appuis points
// and the ground control points of ../shared/data/paris-historical-micmac, see docs/conventions.md):
// - `Centre` is the camera centre in the orientation's frame (ECEF EPSG:4978 for a georeferenced
//   block): C = Centre.
// - `ParamRotation/CodageMatr` L1..L3 (rows) maps camera directions to world directions: with the
//   MicMac camera frame x right, y down, z forward, x_cam = Lᵀ (X − C). So camFromWorld = Lᵀ.
//   (Reading L as world → camera puts the Verif points hundreds of pixels off, and behind the
//   camera for two images of three.)
// - Ideal pixel: PP + F (x/z, y/z), one focal for both axes, y down.
// - Distortion M2C ("monde to camera") goes from the ideal pixel to the image pixel:
//   p_d = p + (p − CDist) (k1 r² + k2 r⁴ + k3 r⁶), r = |p − CDist|, CoeffDist = k1 k2 k3 in
//   pixel units: histoview's radial polynomial with c3 = k1, c5 = k2, c7 = k3.
// - Pixels: MicMac puts the centre of the top-left pixel at (0, 0) (a pixel's integer index is its
//   centre), histoview at (0.5, 0.5): every MicMac image position gets +0.5 on both axes (PP,
//   CDist, Verif/Appuis Im, GCP measures). The data cannot show half a pixel (Verif is MicMac's own
//   projection; the GCPs' residuals are tens of pixels): this follows MicMac's image access.
// Not read (each is an error naming the file and the element): other KnownConv values, angular
// rotation codings, a non-identity OrIntImaM2C (scanned-film interior orientation), projections
// other than eProjStenope, distortion models other than ModRad (ModPhgrStd is accepted when its
// decentric and affine terms are zero), more than three radial coefficients, and non-zero
// distortion under eConvApero_DistC2M.
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace hv {

// A Verif/Appuis entry: a terrain point and where MicMac projects it (histoview pixels).
struct MicmacCheckPoint {
  int num = 0;
  glm::dvec3 world{0.0};
  glm::dvec2 pixel{0.0};
};

struct MicmacOrientation {
  Camera camera;          // in the orientation's own frame; id = the image name's stem
  std::string imageName;  // NameFileImage, else from the file name Orientation-<image>.xml
  std::string calibrationPath;  // the FileInterne resolved, empty when inline
  std::vector<MicmacCheckPoint> checks;
  double checkTolerance = 0.0;  // Verif/Tol (pixels), 0 when absent
};

// Reads an AutoCal / CalibrationInternConique document (text) into the intrinsics of `camera`
// (width, height, focal, principal, distortion). Throws InputError naming `pathForErrors` and the
// element.
void parseMicmacCalibration(const std::string& xml, const std::string& pathForErrors, Camera& camera);

// Parses an orientation document (text). `readFile` returns the text of the FileInterne it is
// given (resolved by the caller) and may throw InputError. Throws InputError naming
// `pathForErrors` (or the calibration file) and the element.
using MicmacFileReader = std::function<std::string(const std::string& fileInterne)>;
MicmacOrientation parseMicmacOrientation(const std::string& xml, const std::string& pathForErrors,
                                         const MicmacFileReader& readFile);

// Reads one Orientation-*.xml; FileInterne is looked up relative to the MicMac project directory
// (the parent of the Ori- folder, as MicMac writes it when RelativeNameFI is true), then beside the
// orientation file.
MicmacOrientation readMicmacOrientation(const std::string& path);

// Every Orientation-*.xml of `oriDir` (sorted by name), its image in `imageDir`. A file that
// cannot be read (bad XML, missing element, wrong sizes) or whose image is missing is reported and
// skipped; the rest load. Cameras are in the orientation's frame (see hv/io/georef.h).
std::vector<Photo> readMicmacCameras(const std::string& oriDir, const std::string& imageDir, Diagnostics& diag,
                                     bool checkImageFiles = true);

// Ground control points: a DicoAppuisFlottant file (OneAppuisDAF: Pt, NamePt) → name → point.
std::map<std::string, glm::dvec3> readMicmacGroundPoints(const std::string& path);
// Their image measures: a SetOfMesureAppuisFlottants file → image name → point name → pixel
// (histoview convention, +0.5 from MicMac's).
std::map<std::string, std::map<std::string, glm::dvec2>> readMicmacImageMeasures(const std::string& path);

}  // namespace hv
