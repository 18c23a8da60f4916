#include "hv/app/points_tiles_command.h"

#include "hv/io/native/georef.h"
#include "hv/io/native/las_reader.h"
#include "hv/io/native/ply_points.h"
#include "hv/io/tiles3d.h"
#include "hv/session/outputs.h"
#include "hv/session/session.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

namespace hv::app {

namespace fs = std::filesystem;

int runPointsTiles(const PointsTilesOptions& o) {
  std::string ext = fs::path(o.input).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  PointCloud cloud;
  if (ext == ".las" || ext == ".laz")
    cloud = readLas(o.input);
  else if (ext == ".ply")
    cloud = readPlyPoints(o.input);
  else
    throw InputError(inputMessage(o.input, "", "expected a .las or .ply point cloud"));
  const std::string crs = o.crs.empty() ? cloud.crs : o.crs;
  if (crs.empty())
    throw InputError(inputMessage(o.input, "crs",
                                  "none declared: 3D Tiles are earth-centred, so the cloud's CRS is needed (--crs)"));
  if (cloud.empty()) throw InputError(inputMessage(o.input, "", "no points to write"));
  Diagnostics diag;
  // Into EPSG:4978, normals turned by the local Jacobian at the cloud's centre.
  const GeoTransform toEcef(crs, "EPSG:4978", diag);
  const glm::dmat3 turn = glm::inverse(glm::transpose(toEcef.jacobian(cloud.bounds().center())));
  toEcef.points(cloud.positions);
  for (glm::vec3& n : cloud.normals) {
    const glm::dvec3 m = turn * glm::dvec3(n);
    if (glm::length(m) > 0.0) n = glm::vec3(glm::normalize(m));
  }
  // East-north-up at the centre: the tiles' boxes then lie flat on the ground.
  const glm::dvec3 c = cloud.bounds().center();
  const glm::dvec3 up = ecefUp(c);
  const glm::dvec3 east = glm::normalize(glm::cross(glm::dvec3(0, 0, 1), up));
  const glm::dvec3 north = glm::cross(up, east);
  const glm::dmat4 enu(glm::dvec4(east, 0), glm::dvec4(north, 0), glm::dvec4(up, 0), glm::dvec4(c, 1));
  const glm::dmat4 local = glm::inverse(enu);
  for (glm::dvec3& p : cloud.positions) p = glm::dvec3(local * glm::dvec4(p, 1.0));
  const glm::dmat3 toLocal(local);
  for (glm::vec3& n : cloud.normals) n = glm::vec3(glm::normalize(toLocal * glm::dvec3(n)));

  PointTilesOptions options;
  options.pointsPerTile = o.pointsPerTile;
  const PointTilesWritten written = writePointTiles(cloud, enu, options);
  fs::create_directories(o.out);
  std::uint64_t bytes = 0;
  for (const PointTilesFile& f : written.files) {
    std::ofstream out(fs::path(o.out) / f.name, std::ios::binary | std::ios::trunc);
    out.write(f.bytes.data(), std::streamsize(f.bytes.size()));
    if (!out) throw std::runtime_error((fs::path(o.out) / f.name).string() + ": cannot be written");
    bytes += f.bytes.size();
  }
  for (const std::string& w : diag.warnings) std::cerr << "warning: " << w << "\n";
  PointFields kept = cloud.fields();
  kept.intensity = false;  // pnts has no field for it (classes go into the batch table)
  std::cout << "wrote " << (fs::path(o.out) / "tileset.json").string() << ": " << cloud.size() << " points ("
            << kept.describe() << ") in " << written.tiles << " tiles, " << written.depth + 1 << " levels, " << bytes
            << " bytes\n";
  return kExitOk;
}

void addPointsTilesCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<PointsTilesOptions>();
  auto* cmd = app.add_subcommand("points-tiles",
                                 "write a point cloud (LAS, PLY) as a 3D Tiles tileset of pnts tiles, for "
                                 "\"points\": {\"tileset\": ...} (docs/formats.md)");
  cmd->add_option("input", o->input, "the point cloud (.las or .ply)")->required();
  cmd->add_option("out", o->out, "the folder to write tileset.json and the tiles into")->required();
  cmd->add_option("--crs", o->crs, "the cloud's CRS when its file declares none (or to override it)");
  cmd->add_option("--points-per-tile", o->pointsPerTile, "the most points a tile keeps (default 20000)")
      ->check(CLI::Range(std::size_t(1), std::size_t(1) << 26));
  setAction(*cmd, exitCode, [o] { return runPointsTiles(*o); });
}

}  // namespace hv::app
