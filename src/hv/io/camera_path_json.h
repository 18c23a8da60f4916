// Reading camera paths (PATH.json, docs/formats.md): the cameras.json schema plus an optional time
// `t` per camera. The interpolation itself is hv/camera/camera_path.h (no file formats there).
#pragma once

#include "hv/camera/camera_path.h"
#include "hv/util/diagnostics.h"

#include <string>

namespace hv {

// Reads PATH.json. Cameras are read by hv::parseCameraJson (images neither required nor checked);
// a key that cannot be read makes the whole path an InputError (a path silently missing a key
// would fly elsewhere), as do a bad `t` and the CameraPath checks. Warnings go to `diag`.
CameraPath readCameraPath(const std::string& path, Diagnostics& diag);
CameraPath parseCameraPath(const std::string& text, const std::string& pathForErrors, Diagnostics& diag);
// Writes key cameras as PATH.json (what readCameraPath reads back; e.g. a path recorded in the
// viewer): the cameras.json schema with each key's `t`.
std::string cameraPathJson(const std::vector<PathKey>& keys);

}  // namespace hv
