// The native camera file (cameras.json; also the format of VIEWS.json, where `image` may be
// absent). Schema in docs/formats.md; conventions in hv/camera/camera.h.
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <string>
#include <vector>

namespace hv {

struct CameraFileOptions {
  bool requireImages = true;     // cameras.json: yes; VIEWS.json: no
  bool checkImageFiles = true;   // the image (and mask) file must exist
};

// Reads every camera it can; a camera with a bad field is skipped with an error naming the file,
// the camera id and the field (Diagnostics::errors); the others load. Relative image paths are
// resolved against the file's directory. Throws InputError when the file cannot be read or is
// not JSON with a "cameras" array.
std::vector<Photo> readCameraFile(const std::string& path, const CameraFileOptions& options, Diagnostics& diag);
std::vector<Photo> parseCameraJson(const std::string& text, const std::string& pathForErrors,
                                   const std::string& baseDir, const CameraFileOptions& options,
                                   Diagnostics& diag);

// Writes cameras in the same schema (full double precision).
std::string cameraJson(const std::vector<Photo>& photos, const std::string& baseDir);

}  // namespace hv
