#include "hv/app/pose_command.h"

#include "hv/io/cameras_json.h"
#include "hv/io/native/georef.h"
#include "hv/io/native/micmac_cameras.h"
#include "hv/io/native/scene_loader.h"
#include "hv/pose/geopose.h"
#include "hv/pose/pose.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"
#include "hv/util/input_file.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

namespace hv::app {

namespace fs = std::filesystem;

namespace {

struct PoseCommandOptions {
  std::string scene;
  std::string image;
  std::string gcp;
  std::string measures;
  std::string start;
  std::string refine = "focal";
  std::string size;
  std::string out;
  std::string geopose;
  double inlierPx = 0.0;
};

constexpr std::uint64_t kMaxGcpBytes = 64ull << 20;

}  // namespace

std::vector<pose::ControlPoint> readControlPoints(const std::string& gcpPath, const std::string& measuresPath,
                                                  const std::string& image, const std::string& imageFile) {
  if (measuresPath.empty())
    return pose::parseControlPoints(readTextFile(gcpPath, kMaxGcpBytes, "control points"), gcpPath);
  const auto ground = readMicmacGroundPoints(gcpPath);
  const auto measures = readMicmacImageMeasures(measuresPath);
  auto it = measures.find(image);
  if (it == measures.end() && !imageFile.empty()) it = measures.find(fs::path(imageFile).filename().string());
  if (it == measures.end()) {
    std::string names;
    for (const auto& [name, pts] : measures) names += (names.empty() ? "" : ", ") + name;
    throw InputError(measuresPath + ": no measures of the image '" + image + "' (it has: " + names + ")");
  }
  std::vector<pose::ControlPoint> points;
  for (const auto& [name, pixel] : it->second) {
    const auto g = ground.find(name);
    if (g == ground.end())
      throw InputError(measuresPath + ": point '" + name + "' is measured but " + gcpPath + " has no point of that name");
    pose::ControlPoint p;
    p.pixel = pixel;
    p.world = g->second;
    p.label = name;
    points.push_back(p);
  }
  return points;
}

namespace {

int runPose(const PoseCommandOptions& o) {
  Diagnostics diag;
  const Scene scene = loadScene(o.scene, diag);  // InputError: printed by setAction, exit code 2
  if (!o.geopose.empty() && scene.crs.empty())
    throw InputError("--geopose: " + o.scene +
                     " has no CRS (scene.json `crs`), so its cameras have no place on the Earth; declare the scene "
                     "CRS (e.g. \"crs\": \"EPSG:2154\") or leave out --geopose");
  std::string imageFile;
  for (const Photo& p : scene.photos)
    if (p.camera.id == o.image) imageFile = p.imagePath;
  const std::vector<pose::ControlPoint> points = readControlPoints(o.gcp, o.measures, o.image, imageFile);

  // The first camera: --start, else the scene's photograph with that id, else --size alone.
  Photo photo;
  bool found = false, startPose = false;
  if (!o.start.empty()) {
    CameraFileOptions cfo;
    cfo.requireImages = false;
    cfo.checkImageFiles = false;
    const std::vector<Photo> cams = readCameraFile(o.start, cfo, diag);
    for (const Photo& p : cams)
      if (p.camera.id == o.image || cams.size() == 1) photo = p, found = true;
    if (!found)
      throw InputError(o.start + ": no camera with the id '" + o.image + "' (and more than one camera in the file)");
    startPose = true;
  } else {
    for (const Photo& p : scene.photos)
      if (p.camera.id == o.image) photo = p, found = true, startPose = true;
  }
  if (!found) {
    if (o.size.empty())
      throw InputError("--image: no photograph '" + o.image + "' in " + o.scene +
                       ": give --start CAMERAS.json with its intrinsics, or --size WxH to solve its focal (6 points "
                       "or more, not all on one plane)");
    int w = 0, h = 0;
    char x = 0;
    if (std::sscanf(o.size.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w <= 0 || h <= 0)
      throw InputError("--size: expected WxH in pixels, got '" + o.size + "'");
    photo.camera.id = o.image;
    photo.camera.width = w;
    photo.camera.height = h;
    photo.camera.principal = {w / 2.0, h / 2.0};
    photo.camera.focal = glm::dvec2(0.0);
  }

  pose::PoseOptions options;
  options.refine = pose::parseRefine(o.refine);
  options.inlierPixels = o.inlierPx;
  if (!(photo.camera.focal.x > 0.0) && !options.refine.focal) options.refine.focal = true;
  const pose::PoseResult r = pose::solvePose(points, photo.camera, startPose, options);

  std::cout << "posed '" << o.image << "' from " << points.size() << " control points (" << r.inlierCount
            << " inliers)\n";
  for (const std::string& n : r.notes) std::cout << "note: " << n << "\n";
  std::cout << std::fixed << std::setprecision(2);
  for (size_t i = 0; i < points.size(); ++i)
    std::cout << "  " << std::left << std::setw(16) << points[i].label << std::right << std::setw(10)
              << r.residuals[i] << " px" << (r.inliers[i] ? "" : "   OUTLIER") << "\n";
  const Camera& c = r.camera;
  std::cout << std::setprecision(3) << "residuals: " << r.rmsPixels << " px RMS over the inliers\n"
            << "centre     (" << c.center.x << ", " << c.center.y << ", " << c.center.z << ")  +/- ("
            << r.centerSigma.x << ", " << r.centerSigma.y << ", " << r.centerSigma.z << ") (1 sigma)\n"
            << "rotation   +/- " << std::setprecision(4) << r.rotationSigmaDegrees << " deg\n"
            << std::setprecision(2) << "focal      " << c.focal.x << " px";
  if (r.focalSigma > 0.0) std::cout << " +/- " << r.focalSigma;
  std::cout << "\nprincipal  (" << c.principal.x << ", " << c.principal.y << ") px\n";
  if (c.distortion && options.refine.radial)
    std::cout << std::setprecision(5) << "radial     k1 " << c.distortion->c3 << ", k2 " << c.distortion->c5 << "\n";

  const fs::path out = fs::absolute(o.out);
  if (out.has_parent_path()) fs::create_directories(out.parent_path());
  Photo written = photo;
  written.camera = c;
  if (!written.imagePath.empty()) written.imagePath = fs::absolute(written.imagePath).lexically_normal().string();
  if (!written.maskPath.empty()) written.maskPath = fs::absolute(written.maskPath).lexically_normal().string();
  std::ofstream f(out, std::ios::binary | std::ios::trunc);
  f << cameraJson({written}, out.parent_path().string()) << "\n";
  f.close();
  if (!f) {
    std::cerr << "error: " << out.string() << ": cannot write\n";
    return kExitNotProduced;
  }
  std::cout << "wrote " << out.string() << "\n";
  if (!o.geopose.empty()) {
    const GeodeticFrame g = geodeticFrameAt(scene.crs, c.center, diag);
    pose::GeoPose gp;
    gp.latDeg = g.latDeg;
    gp.lonDeg = g.lonDeg;
    gp.heightM = g.heightM;
    gp.quaternion = pose::quaternionOf(pose::enuFromCameraObject(c.camFromWorld, g.enuFromWorld));
    if (g.heightIsZ)
      std::cout << "note: the scene CRS has no vertical axis: the GeoPose height is the camera's z, taken as a height "
                   "above the WGS 84 ellipsoid\n";
    const fs::path gpath = fs::absolute(o.geopose);
    if (gpath.has_parent_path()) fs::create_directories(gpath.parent_path());
    std::ofstream gf(gpath, std::ios::binary | std::ios::trunc);
    gf << pose::geoPoseJson(gp);
    gf.close();
    if (!gf) {
      std::cerr << "error: " << gpath.string() << ": cannot write\n";
      return kExitNotProduced;
    }
    std::cout << std::setprecision(9) << "geopose    lat " << gp.latDeg << ", lon " << gp.lonDeg << ", h "
              << std::setprecision(3) << gp.heightM << " m\nwrote " << gpath.string() << "\n";
  }
  return exitStatus(diag);
}

}  // namespace

void addPoseCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand(
      "pose",
      "a photograph's camera from control points (CSV u,v,x,y,z: pixels from the top-left corner, world in the "
      "scene CRS): RANSAC over minimal solutions, then Levenberg-Marquardt; prints each point's residual, flags "
      "outliers, the centre's uncertainty; writes a native cameras.json");
  cmd->footer(exitStatusHelp());
  auto o = std::make_shared<PoseCommandOptions>();
  cmd->add_option("scene", o->scene, "scene.json")->required()->check(CLI::ExistingFile);
  cmd->add_option("--image", o->image, "the photograph's id (in the scene, or in --start)")->required();
  cmd->add_option("--gcp", o->gcp, "control points, CSV with the header u,v,x,y,z (4 or more; 6 to solve the focal)")
      ->required();
  cmd->add_option("--measures", o->measures,
                  "MicMac's image measures (SetOfMesureAppuisFlottants XML); --gcp is then MicMac's ground points "
                  "(DicoAppuisFlottant XML), paired by point name");
  cmd->add_option("--start", o->start,
                  "a cameras.json holding the photograph's camera: the first guess, and the intrinsics not refined "
                  "(default: the scene's camera with that id)");
  cmd->add_option("--refine", o->refine,
                  "what is solved beyond the centre and rotation: focal, principal, radial (comma-separated) or none "
                  "(default focal)");
  cmd->add_option("--size", o->size, "WxH: the photograph's size when neither the scene nor --start has its camera");
  cmd->add_option("--inlier-px", o->inlierPx,
                  "a point is an inlier within this many pixels (default 0.5 % of the image diagonal, at least 2)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("-o,--out", o->out, "the cameras.json to write")->required();
  cmd->add_option("--geopose", o->geopose,
                  "also write the camera as an OGC GeoPose 1.0 Basic-Quaternion JSON (WGS 84 position, orientation "
                  "in the local East-North-Up frame; docs/pose.md); the scene must have a CRS");
  setAction(*cmd, exitCode, [o] { return runPose(*o); });
}

}  // namespace hv::app
