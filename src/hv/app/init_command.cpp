#include "hv/app/init_command.h"

#include "hv/io/native/cityjson.h"
#include "hv/io/native/footprints.h"
#include "hv/io/native/raster.h"
#include "hv/io/native/terrain_raster.h"
#include "hv/session/session.h"
#include "hv/util/diagnostics.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>

namespace hv::app {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// How deep init looks: FOLDER/images/2019/x.jpg is found, a whole disk is not walked.
constexpr int kMaxDepth = 3;
// A JSON file larger than this is not opened to see what it is (a cameras file of 100,000
// photographs is about 40 MB).
constexpr std::uintmax_t kMaxSniffBytes = std::uintmax_t(256) << 20;
// Footprint attributes tried for the building height, in this order (3D BAG, BD TOPO, OSM).
const std::vector<std::string> kHeightAttributes = {"height",    "hauteur", "HAUTEUR",        "measuredHeight",
                                                    "h_dak_max", "hoogte",  "building:height"};

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}
bool endsWith(const std::string& s, const std::string& end) {
  return s.size() >= end.size() && s.compare(s.size() - end.size(), end.size(), end) == 0;
}

std::optional<json> sniffJson(const fs::path& p) {
  std::error_code ec;
  if (fs::file_size(p, ec) > kMaxSniffBytes || ec) return std::nullopt;
  std::ifstream in(p, std::ios::binary);
  json j = json::parse(in, nullptr, false);
  if (j.is_discarded()) return std::nullopt;
  return j;
}

// A PLY's faces make it a mesh; without, a point cloud.
bool plyHasFaces(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::string line;
  for (int n = 0; n < 200 && std::getline(in, line); ++n) {
    if (line.rfind("end_header", 0) == 0) break;
    if (line.rfind("element face ", 0) == 0) return std::stoll("0" + line.substr(13)) > 0;
  }
  return false;
}

struct Found {
  std::vector<fs::path> nativeCameras, views, colmapDirs, micmacDirs, itownsCalibrations, itownsOrientations,
      itownsPatterns, rasters, vectors, cityjson, clouds, meshes, skipped;
  std::map<fs::path, int> imagesByDir;
  std::map<std::string, fs::path> imageByName;
};

void look(const fs::path& dir, int depth, Found& f) {
  std::error_code ec;
  std::vector<fs::directory_entry> entries;
  for (const auto& e : fs::directory_iterator(dir, ec)) entries.push_back(e);
  std::sort(entries.begin(), entries.end(), [](const auto& a, const auto& b) { return a.path() < b.path(); });
  bool hasColmapCameras = false, hasColmapImages = false, hasOrientation = false;
  for (const auto& e : entries) {
    const fs::path& p = e.path();
    const std::string name = p.filename().string(), low = lower(name);
    if (name.empty() || name[0] == '.') continue;
    if (e.is_directory(ec)) {
      if (depth < kMaxDepth) look(p, depth + 1, f);
      continue;
    }
    if (!e.is_regular_file(ec)) continue;
    if (low == "cameras.txt") hasColmapCameras = true;
    if (low == "images.txt") hasColmapImages = true;
    if (low.rfind("orientation-", 0) == 0 && endsWith(low, ".xml")) hasOrientation = true;
    if (endsWith(low, ".jpg") || endsWith(low, ".jpeg") || endsWith(low, ".png")) {
      ++f.imagesByDir[dir];
      f.imageByName.emplace(name, p);
    } else if (endsWith(low, ".city.json") || endsWith(low, ".cityjson")) {
      f.cityjson.push_back(p);
    } else if (endsWith(low, ".tif") || endsWith(low, ".tiff") || endsWith(low, ".asc") || endsWith(low, ".vrt")) {
      f.rasters.push_back(p);
    } else if (endsWith(low, ".gpkg") || endsWith(low, ".shp") || endsWith(low, ".geojson") || endsWith(low, ".fgb")) {
      // iTowns' panorama poses are a GeoJSON of points, not footprints.
      if (endsWith(low, ".geojson") && low.find("panoramic") != std::string::npos)
        f.itownsOrientations.push_back(p);
      else
        f.vectors.push_back(p);
    } else if (endsWith(low, ".las") || endsWith(low, ".laz")) {
      f.clouds.push_back(p);
    } else if (endsWith(low, ".ply")) {
      (plyHasFaces(p) ? f.meshes : f.clouds).push_back(p);
    } else if (endsWith(low, ".obj") || endsWith(low, ".gltf") || endsWith(low, ".glb")) {
      f.meshes.push_back(p);
    } else if (endsWith(low, ".json") && low != "scene.json") {
      const std::optional<json> j = sniffJson(p);
      if (!j) {
        f.skipped.push_back(p);
      } else if (j->is_object() && j->contains("cameras") && (*j)["cameras"].is_array()) {
        (low.rfind("views", 0) == 0 ? f.views : f.nativeCameras).push_back(p);
      } else if (j->is_object() && j->value("type", "") == "CityJSON") {
        f.cityjson.push_back(p);
      } else if (j->is_object() && j->value("type", "") == "FeatureCollection") {
        f.vectors.push_back(p);
      } else if (j->is_array() && !j->empty() && (*j)[0].is_object() && (*j)[0].contains("projection")) {
        f.itownsCalibrations.push_back(p);
      } else if (j->is_object() && j->contains("patterns")) {
        f.itownsPatterns.push_back(p);
      }
    }
  }
  if (hasColmapCameras && hasColmapImages) f.colmapDirs.push_back(dir);
  if (hasOrientation && lower(dir.filename().string()).rfind("ori-", 0) == 0) f.micmacDirs.push_back(dir);
}

// Prefers a file whose name says what it is ("dtm", "cameras"), else the first.
fs::path preferred(const std::vector<fs::path>& files, const std::vector<std::string>& words) {
  for (const std::string& w : words)
    for (const fs::path& p : files)
      if (lower(p.filename().string()).find(w) != std::string::npos) return p;
  return files.front();
}

}  // namespace

InitResult initScene(const std::string& folder, const std::string& sceneDir) {
  InitResult r;
  r.scene = json::object();
  Found f;
  look(fs::path(folder), 0, f);
  const fs::path base = fs::absolute(sceneDir).lexically_normal();
  // Relative to the scene's folder when the data is under it, else absolute.
  auto rel = [&](const fs::path& p) {
    const fs::path a = fs::absolute(p).lexically_normal();
    const std::string r = a.lexically_relative(base).generic_string();
    return r.empty() || r.rfind("..", 0) == 0 ? a.generic_string() : r;
  };
  auto say = [&](const std::string& what, const std::string& text) {
    std::string w = what;
    w.resize(std::max<size_t>(w.size(), 10), ' ');
    r.report.push_back(w + " " + text);
  };
  auto others = [&](const std::vector<fs::path>& all, const fs::path& chosen, const std::string& what) {
    for (const fs::path& p : all)
      if (p != chosen) say("", "also " + rel(p) + " (" + what + "; not used: edit scene.json to choose it)");
  };
  std::optional<std::string> crs;
  std::string crsFrom;
  Diagnostics quiet;  // what the readers say while init probes is not the user's concern yet

  // The images: the folder with most of them is where the cameras' images are.
  fs::path imageDir;
  int images = 0, imageDirs = 0, most = 0;
  for (const auto& [dir, n] : f.imagesByDir) {
    images += n;
    ++imageDirs;
    if (n > most) {
      most = n;
      imageDir = dir;
    }
  }
  if (images)
    say("images", std::to_string(images) + " (JPEG, PNG) in " + std::to_string(imageDirs) + " folder(s), most in " +
                      (rel(imageDir).empty() ? "." : rel(imageDir)));

  // Cameras: the native format first (it is what `histoview cameras convert` writes), then
  // COLMAP, MicMac, iTowns.
  if (!f.nativeCameras.empty()) {
    const fs::path p = preferred(f.nativeCameras, {"cameras"});
    r.scene["cameras"] = {{"path", rel(p)}};
    const std::optional<json> j = sniffJson(p);
    say("cameras",
        rel(p) + " (histoview's own format, " + std::to_string(j ? (*j)["cameras"].size() : 0) + " cameras)");
    others(f.nativeCameras, p, "a cameras file");
  } else if (!f.colmapDirs.empty()) {
    const fs::path p = f.colmapDirs.front();
    r.scene["cameras"] = {{"format", "colmap"}, {"path", rel(p)}, {"images", imageDir.empty() ? "." : rel(imageDir)}};
    say("cameras", rel(p) + " (a COLMAP text model), images guessed in " + (imageDir.empty() ? "." : rel(imageDir)) +
                       "; COLMAP's frame is arbitrary: set \"up\" if the views open upside down");
  } else if (!f.micmacDirs.empty()) {
    const fs::path p = f.micmacDirs.front();
    // The images: where the first orientation's image is.
    fs::path dir = imageDir;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(p, ec)) {
      const std::string n = e.path().filename().string();
      if (n.rfind("Orientation-", 0) == 0 && endsWith(n, ".xml")) {
        const auto it = f.imageByName.find(n.substr(12, n.size() - 16));
        if (it != f.imageByName.end()) dir = it->second.parent_path();
        break;
      }
    }
    r.scene["cameras"] = {{"format", "micmac"}, {"orientations", rel(p)}, {"images", dir.empty() ? "." : rel(dir)}};
    say("cameras",
        rel(p) + " (MicMac orientations, centres in ECEF, EPSG:4978), images in " + (dir.empty() ? "." : rel(dir)));
  } else if (!f.itownsCalibrations.empty() && !f.itownsOrientations.empty()) {
    r.scene["cameras"] = {
        {"format", "itowns"},
        {"orientations", rel(f.itownsOrientations.front())},
        {"calibration", rel(f.itownsCalibrations.front())},
        {"images", f.itownsPatterns.empty() ? "images/{panoId}-{cameraId}.jpg" : rel(f.itownsPatterns.front())}};
    say("cameras", rel(f.itownsOrientations.front()) + " + " + rel(f.itownsCalibrations.front()) + " (iTowns)" +
                       (f.itownsPatterns.empty() ? "; the image pattern is a guess: check cameras.images" : ""));
  } else {
    say("cameras",
        "none found (cameras.json, a COLMAP cameras.txt + images.txt, a MicMac Ori-*/ folder or iTowns "
        "calibration + panoramics GeoJSON): the scene shows the geometry untextured");
  }
  for (const fs::path& p : f.views)
    say("views", rel(p) + " (view cameras: histoview render SCENE --views " + rel(p) + ")");

  // Terrain: a raster GDAL reads, not among the photographs.
  std::vector<fs::path> dtms;
  for (const fs::path& p : f.rasters) {
    try {
      const RasterSize size = rasterSize(p.string());
      (void)size;
      dtms.push_back(p);
    } catch (const InputError& e) {
      say("", "skipped " + rel(p) + ": " + e.what());
    }
  }
  if (!dtms.empty()) {
    const fs::path p = preferred(dtms, {"dtm", "dem", "mnt", "terrain", "ahn", "elev"});
    r.scene["terrain"] = {{"path", rel(p)}};
    const RasterSize size = rasterSize(p.string());
    const std::string text = rel(p) + " (" + std::to_string(size.cols) + " x " + std::to_string(size.rows) + " cells";
    if (std::uint64_t(size.cols) * std::uint64_t(size.rows) <= kMaxRasterCells) {
      try {
        const GeoreferencedHeightfield h = readHeightfield(p.string(), SourceGeoref{}, quiet);
        if (!h.sourceCrs.empty() && !crs) {
          crs = h.sourceCrs;
          crsFrom = rel(p);
        }
      } catch (const InputError&) {
      }
    }
    say("terrain", text + ")");
    others(dtms, p, "a raster");
  }

  // Buildings: CityJSON first (3D as it is), else footprints with a height attribute.
  if (!f.cityjson.empty()) {
    const fs::path p = f.cityjson.front();
    try {
      const CityJsonBuildings city = readCityJson(p.string(), quiet);
      r.scene["buildings"] = {{"path", rel(p)}};
      say("buildings", rel(p) + " (CityJSON, " + std::to_string(city.ids.size()) + " buildings" +
                           (city.crs.empty() ? "" : ", " + city.crs) + ")");
      if (!city.crs.empty() && !crs) {
        crs = city.crs;
        crsFrom = rel(p);
      }
    } catch (const InputError& e) {
      say("", "skipped " + rel(p) + ": " + e.what());
    }
  }
  if (!r.scene.contains("buildings")) {
    for (const fs::path& p : f.vectors) {
      for (const std::string& attribute : kHeightAttributes) {
        FootprintFields fields;
        fields.height = attribute;
        Diagnostics d;
        try {
          const GeoreferencedFootprints read = readFootprints(p.string(), fields, SourceGeoref{}, d);
          if (read.footprints.empty()) continue;
          r.scene["buildings"] = {{"path", rel(p)}, {"height", attribute}};
          say("buildings", rel(p) + " (" + std::to_string(read.footprints.size()) + " footprints, height from the '" +
                               attribute + "' attribute" +
                               (read.sourceCrs.empty() ? "" : ", " + read.sourceCrs.substr(0, 40)) +
                               "; base: the terrain under each)");
          if (!read.sourceCrs.empty() && !crs) {
            crs = read.sourceCrs;
            crsFrom = rel(p);
          }
        } catch (const InputError&) {
        }
        break;  // a source that opened: its attributes are what they are
      }
      if (r.scene.contains("buildings")) break;
      say("", "skipped " + rel(p) + ": no polygon with a height attribute (tried " + kHeightAttributes.front() + ", " +
                  kHeightAttributes[1] + ", ...; set buildings.height to the right one)");
    }
  }

  if (!f.meshes.empty()) {
    const fs::path p = preferred(f.meshes, {"mesh"});
    r.scene["mesh"] = {{"path", rel(p)}};
    say("mesh", rel(p));
    others(f.meshes, p, "a mesh");
  }
  if (!f.clouds.empty()) {
    std::vector<fs::path> las;  // LAS over PLY: it declares its CRS and classes
    for (const fs::path& p : f.clouds)
      if (endsWith(lower(p.string()), ".las")) las.push_back(p);
    const fs::path p = las.empty() ? f.clouds.front() : las.front();
    r.scene["points"] = {{"path", rel(p)}};
    say("points", rel(p));
    others(f.clouds, p, "a point cloud");
  }

  if (crs) {
    r.scene["crs"] = *crs;
    say("crs", (crs->size() > 60 ? crs->substr(0, 57) + "..." : *crs) + " (guessed: the CRS " + crsFrom +
                   " declares; every source is brought into it)");
  } else if (!r.scene.contains("cameras") || r.scene["cameras"].value("format", "") != "micmac") {
    say("crs", "none declared by the sources: they are taken as they are (add \"crs\" if they differ)");
  }
  if (r.scene.contains("cameras") && !r.scene.contains("terrain") && !r.scene.contains("buildings") &&
      !r.scene.contains("mesh") && !r.scene.contains("points"))
    say("hint",
        "no geometry found: set \"terrain\": {\"height\": H} for a ground plane at elevation H, and add "
        "building footprints if you have them");
  for (const fs::path& p : f.skipped) say("", "skipped " + rel(p) + ": not JSON this version reads");
  return r;
}

void addInitCommand(CLI::App& app, int& exitCode) {
  auto* cmd = app.add_subcommand("init",
                                 "write FOLDER/scene.json from the cameras, images, DTM, footprints or "
                                 "CityJSON, mesh and point cloud found in FOLDER, saying what was guessed");
  auto folder = std::make_shared<std::string>();
  auto output = std::make_shared<std::string>();
  auto force = std::make_shared<bool>(false);
  cmd->add_option("folder", *folder, "the folder of your data")->required()->check(CLI::ExistingDirectory);
  cmd->add_option("-o,--output", *output, "where to write the scene (default FOLDER/scene.json)");
  cmd->add_flag("--force", *force, "overwrite an existing scene.json");
  setAction(*cmd, exitCode, [folder, output, force] {
    const fs::path out = output->empty() ? fs::path(*folder) / "scene.json" : fs::path(*output);
    if (fs::exists(out) && !*force) {
      std::cerr << "error: " << out.string() << " exists; --force overwrites it\n";
      return 1;
    }
    const fs::path dir = out.has_parent_path() ? out.parent_path() : fs::path(".");
    const InitResult r = initScene(*folder, dir.string());
    for (const std::string& line : r.report) std::cout << line << "\n";
    fs::create_directories(dir);
    std::ofstream file(out);
    file << r.scene.dump(1) << "\n";
    if (!file) {
      std::cerr << "error: cannot write " << out.string() << "\n";
      return 1;
    }
    std::cout << "wrote " << out.string() << "; next: histoview info " << out.string() << ", then histoview view "
              << out.string() << "\n";
    return 0;
  });
}

}  // namespace hv::app
