// `histoview pose SCENE --image ID --gcp points.csv -o camera.json`: a photograph's camera from
// control points (hv/pose/pose.h, docs/pose.md).
#pragma once

#include "hv/pose/control_points.h"

#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace hv::app {

void addPoseCommand(CLI::App& app, int& exitCode);

// The control points of photograph `image` (its id or its image file's name): from a CSV
// (pose/control_points.h), or from MicMac's ground points (`gcpPath`, a DicoAppuisFlottant XML)
// paired by name with their image measures (`measuresPath`, SetOfMesureAppuisFlottants). Throws
// InputError naming the file: no measures for that image, a measured point without a ground point.
std::vector<pose::ControlPoint> readControlPoints(const std::string& gcpPath, const std::string& measuresPath,
                                                  const std::string& image, const std::string& imageFile = "");

}  // namespace hv::app
