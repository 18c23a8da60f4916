// iTowns oriented images: a panorama orientation GeoJSON (one Point feature per panorama: id,
// roll/pitch/heading in degrees), a calibration JSON (the rig: one entry per camera, pose in the
// panorama frame, projection, radial distortion) and an image URL pattern with {panoId} and
// {cameraId} (or a JSON file of one pattern per panorama). Each panorama is a rig of pinhole
// cameras sharing its pose. Conventions follow iTowns' OrientedImageLayer,
// CameraCalibrationParser and OrientationUtils (quaternionFromRollPitchHeading), as written out in
// ../shared/data/README.md (paris-stereopolis):
//   p_world = Q p_pano + position,  Q = Ry(-roll) Rx(-pitch) Rz(-heading)   (pano: x right, y forward, z up)
//   p_cam   = R_cal (p_pano - t_cal)                                          (camera: x right, y down, z forward)
//   so C = position + Q t_cal and camFromWorld = R_cal Q^T;
//   focal = (proj[0], proj[4]), principal = (proj[2], proj[5]) (y-down pixels, corner origin);
//   distortion: centre pps, c3 c5 c7 = poly357, r2max = limit^2.
// No meridian-convergence rotation: iTowns applies one only when the view CRS differs from the
// GeoJSON's, and histoview's world frame is the GeoJSON's CRS.
#pragma once

#include "hv/scene/scene.h"
#include "hv/util/diagnostics.h"

#include <string>
#include <vector>

namespace hv {

struct ITownsSource {
  std::string orientations;  // GeoJSON path
  std::string calibration;   // calibration JSON path
  std::string images;        // pattern with {panoId} and {cameraId}, or a .json file of per-pano patterns
  std::string baseDir;       // what relative image paths are relative to (iTowns: the page; here the
                             // scene.json directory); empty: the orientation file's directory
};

// One Photo per (panorama, camera). A panorama or calibration entry with a bad field is skipped
// with an error naming the file, the entry and the field; the rest loads. Throws InputError when a
// file cannot be read at all. `checkImageFiles`: the images must exist.
std::vector<Photo> readITownsCameras(const ITownsSource& source, Diagnostics& diag, bool checkImageFiles = true);

}  // namespace hv
