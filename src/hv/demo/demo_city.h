// The demo city: a deterministic synthetic scene with known ground truth.
//
// What is generated, in world coordinates of EPSG:2154 (Lambert-93, metres, z up) around
// (651000, 6862000):
// - a smooth terrain with a few metres of relief, sampled into a 2 m DTM (the renderer's input);
// - streets on a regular grid (asphalt carriageway with dashed centre lines, paved sidewalks raised by
//   a kerb), blocks of two rows of lots, one building per used lot with a concave footprint (L, U, T,
//   notched, stepped) and at least one courtyard (a footprint hole);
// - a ground-truth geometry richer than the LOD1 model: recessed windows and doors, balconies,
//   kerbs; roofs flat at the LOD1 height so that LOD1 is a fair approximation;
// - trees and parked cars that stand in today's city (for the lidar) but appear in no image;
// - photographs rendered by ray casting that ground truth (plus moving cars in some of them, masked
//   in a few), with varied intrinsics, a few with radial distortion and a few with an era colour
//   cast; held-out views rendered the same way without transients: the evaluation ground truth.
// The ground-truth colour of a surface point is `shade()`: procedural albedo (a function of the
// world position and the surface) under a fixed, view-independent lighting, so that blending
// several photographs can reproduce it.
//
// Everything is a pure function of DemoOptions (own PRNG, no std distributions), so two runs give
// byte-identical files.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <glm/glm.hpp>
#include <optional>
#include <string>
#include <vector>

#include "hv/camera/camera.h"
#include "hv/image/image.h"
#include "hv/scene/heightfield.h"
#include "hv/scene/mesh.h"
#include "hv/scene/native/lod1.h"
#include "hv/scene/native/raycast.h"
#include "hv/scene/point_cloud.h"

namespace hv::demo {

// Tuning constants of the city and of its photographs (metres, degrees where named so).
struct CitySettings {
  glm::dvec2 originXY{651000.0, 6862000.0};  // EPSG:2154, a spot in Paris's western suburbs
  double baseElevation = 38.0;               // terrain mean, metres
  // Layout: blocks of 2 rows x `lotsPerRow` lots, separated by streets.
  int lotsPerRow = 3;
  double lotWidth = 18.0, lotDepth = 17.0;  // nominal lot size; split positions vary per block
  double sidewalkWidth = 3.0, roadWidth = 8.0, kerbHeight = 0.15;
  double margin = 24.0;          // grass around the street grid
  double groundCell = 1.0;       // ground-truth terrain tessellation
  double dtmCell = 2.0;          // DTM grid spacing
  double reliefAmplitude = 1.8;  // metres, terrain undulations
  // Buildings.
  double minHeight = 8.0, maxHeight = 25.0;
  double buildingGap = 0.8;  // half the passage between neighbouring buildings
  double floorHeight = 3.1;
  double windowWidth = 1.2, windowHeight = 1.5, sillHeight = 0.9, bayWidth = 3.2;
  double doorWidth = 1.2, doorHeight = 2.4;
  double recessDepth = 0.3;  // windows and doors, into the wall
  double balconyDepth = 1.0, balconyThickness = 0.15, balconyParapet = 0.95;
  double balconyProbability = 0.45;  // per building with street façades
  // Transients.
  double treeSpacing = 11.0;
  int parkedCarsPerStreet = 3;
  // Lighting baked into the ground truth: Lambert under a fixed sun plus a sky ambient term.
  double sunAzimuthDeg = 135.0, sunElevationDeg = 42.0;  // azimuth counter-clockwise from +x (east)
  double ambient = 0.42, diffuse = 0.62;
  glm::dvec3 skyColor{0.70, 0.80, 0.90};  // background of photos and views (coverage 0)
  // Cameras.
  double streetEyeMin = 1.6, streetEyeMax = 2.0;  // above the ground under the camera
  double elevatedMin = 15.0, elevatedMax = 40.0;
  double walkStep = 6.0;             // spacing of successive street-level shots
  double minBuildingFraction = 0.3;  // of a coarse ray grid, for a camera to be accepted
  double maxSkyFraction = 0.6;
  // A camera is rejected when more than maxCloseFraction of that grid hits closer than this (metres):
  // a wall filling the frame shows too little of the city.
  double streetCloseDistance = 4.0, elevatedCloseDistance = 12.0, maxCloseFraction = 0.15;
  // Distortion: displacement at the image corner, pixels (p_d - p).
  double distortionCornerMin = 6.0, distortionCornerMax = 15.0;
  double maskDilation = 2.0;  // pixels (Chebyshev), around car pixels
  // Large cities (DemoOptions::blocks > 0, docs/demo-city.md): blocks on a fixed lattice around
  // the centre block, so that the centre is the same whatever the size.
  double largeDtmCell = 4.0;     // DTM grid spacing (the small city keeps dtmCell)
  double lotFill = 0.9;          // share of the lots that are built
  double courtyardShare = 0.08;  // share of the built lots with a courtyard
  int truthRadius = 3;           // blocks around the centre block with the full ground truth (7 x 7 blocks)
  int surveyRadius = 1;          // blocks around the centre block whose streets the cameras and the lidar use
};

// The simulated mobile-mapping scan: a vehicle drives every survey street (World::surveyStreets) in its
// right-hand lane; a scanner on its roof turns in the vertical plane across the street and
// casts `raysPerProfile` rays per turn, one turn every `profileSpacing` metres of travel.
struct LidarSettings {
  double profileSpacing = 0.75;  // metres of travel between two turns of the scanner
  int raysPerProfile = 240;      // rays per full turn (1.5 degrees apart)
  double scannerHeight = 2.4;    // above the ground under the vehicle
  double laneOffset = 2.0;       // right of the street's centre line
  double minRange = 0.5, maxRange = 60.0;
};

// The demo's traffic (docs/traffic.md): SUMO (sumo.dlr.de) run on the city's street grid, written
// as a plain network (nodes and edges), built by netconvert, random trips (randomTrips.py, a fixed
// seed) and `sumo --fcd-output` for the trajectories.
struct TrafficOptions {
  bool enabled = true;
  double seconds = 60.0;    // simulated time; trips start during the first two thirds of it
  double period = 1.0;      // a trip starts every `period` seconds (randomTrips.py -p)
  double stepLength = 0.5;  // SUMO's step: the FCD's sampling, seconds
  std::uint32_t seed = 42;
  double timeoutSeconds = 60.0;  // each SUMO tool is stopped after this long (wall clock)
};

struct DemoOptions {
  std::uint32_t seed = 1;
  int buildings = 40;  // the small city (blocks == 0)
  // > 0: a large city of about this many blocks (6 lots each, CitySettings::lotFill of them built)
  // instead of `buildings`: full ground truth, cameras and lidar only around the centre, the DTM as
  // a Cloud-Optimized GeoTIFF and the footprints as a GeoPackage (docs/demo-city.md).
  int blocks = 0;
  int photos = 36;
  int views = 8;
  int samplesPerAxis = 2;  // supersampling: samplesPerAxis^2 rays per pixel
  CitySettings city;
  LidarSettings lidar;
  TrafficOptions traffic;
};

// Material ids: the ground-truth mesh's Mesh::triangleTags.
enum class Material : std::uint32_t {
  Grass = 0,
  Asphalt,
  Paving,
  Kerb,
  Plaster,
  Brick,
  Stone,
  Glass,
  Reveal,
  Door,
  Balcony,
  RoofGravel,
  RoofTiles,
  TreeTrunk,
  TreeCrown,
  CarBody,
  CarGlass,
  CarWheel,
  Count
};
const char* materialName(Material m);
// ASPRS LAS 1.4 class for a material (2 ground, 5 high vegetation, 6 building, 1 unclassified for
// vehicles, which have no class of their own in the base table), for the later lidar simulation.
std::uint8_t asprsClass(Material m);

// One textured surface: a material with the local frame its pattern is drawn in. `origin`, `u`
// (along), `w` (up the pattern) are world; `size` the extent in (u, w) where it matters (windows,
// doors); `tint` per building or car.
struct Surface {
  Material material = Material::Grass;
  int building = -1;
  glm::dvec3 origin{0.0}, u{1.0, 0.0, 0.0}, w{0.0, 0.0, 1.0};
  glm::dvec2 size{0.0};
  glm::dvec3 tint{1.0};
  std::uint32_t variant = 0;  // pattern variant (dash phase, brick bond, ...)
};

// A triangle mesh whose triangles each point to a Surface; Mesh::triangleTags hold the material.
struct Layer {
  Mesh mesh;
  std::vector<std::uint32_t> surfaceOf;  // per triangle, index into `surfaces`
  std::vector<Surface> surfaces;
  void append(const Layer& other);
};

struct Street {
  bool alongX = true;           // centre line parallel to x (else to y)
  double centre = 0.0;          // y (alongX) or x of the centre line, world
  double from = 0.0, to = 0.0;  // extent along the line, world
};

struct Building {
  std::string id;
  std::vector<std::vector<glm::dvec2>> rings;  // world, outer CCW then holes CW
  double height = 0.0;                         // LOD1 attribute
  double baseZ = 0.0;  // LOD1 base: the DTM's minimum under the footprint (as the renderer computes it)
  double topZ = 0.0;   // roof, = baseZ + height, also the ground-truth roof
  double groundFloorZ = 0.0;
  int floors = 0;
  bool courtyard = false;
};

struct World {
  DemoOptions options;
  glm::dvec3 origin{0.0};             // world point the procedural patterns are computed relative to
  Layer truth;                        // terrain, kerbs, buildings with openings and balconies: photos and views
  Layer trees;                        // today's city only: in no photo and no view
  Layer parkedCars;                   // today's city only: in no photo and no view
  std::vector<Footprint> footprints;  // the LOD1 inputs given to the renderer (buildings.geojson)
  std::vector<Building> buildings;
  std::vector<Street> streets;
  // The streets the cameras walk and the lidar vehicle drives: all of them in the small city,
  // those around the centre (CitySettings::surveyRadius) in a large one.
  std::vector<Street> surveyStreets;
  Heightfield dtm;                         // the renderer's terrain (dtm.tif)
  Aabb cityBounds;                         // the street grid (cameras stay inside)
  glm::dvec3 sunDirection{0.0, 0.0, 1.0};  // towards the sun, unit
  std::array<double, 3> phase{};           // terrain undulation phases (seeded)
  double streetWidth = 0.0, roadWidth = 0.0, kerbHeight = 0.0;

  // The continuous terrain the ground truth is built on (the DTM samples it).
  double terrainZ(double x, double y) const;
  // Ground surface height (terrain plus the kerb on sidewalks).
  double groundZ(double x, double y) const;
  bool onRoad(double x, double y) const;
  bool onSidewalk(double x, double y) const;  // paved, raised by the kerb (crossings' corners included)
  bool insideBuilding(double x, double y) const;
};

// The city's world model. For a large city (options.blocks > 0) only the blocks within
// CitySettings::truthRadius of the centre get ground-truth geometry, buildings, trees and cars; the
// DTM covers the whole city.
World buildWorld(const DemoOptions& options);

// The lattice of a large city: block (i, j), i in [i0, i0 + nbx), j in [j0, j0 + nby), is centred
// on originXY + (i * pitchX, j * pitchY); streets run between blocks and around the city.
struct BlockGrid {
  int nbx = 0, nby = 0, i0 = 0, j0 = 0;
  double blockW = 0.0, blockD = 0.0, streetWidth = 0.0, pitchX = 0.0, pitchY = 0.0;
  glm::dvec2 origin{0.0};
  glm::dvec2 blockCorner(int i, int j) const;  // south-west corner of block (i, j)
  double streetX(int i) const;                 // centre line of the street west of block column i
  double streetY(int j) const;                 // centre line of the street south of block row j
  glm::dvec2 lo() const;                       // the whole street grid, south-west corner
  glm::dvec2 hi() const;                       // north-east corner
};
// About `blocks` blocks, nbx x nby, the city roughly square in metres.
BlockGrid blockGrid(const CitySettings& city, int blocks);

// Every LOD1 footprint of a large city, block row by block row, south to north (row j0 + r is
// done when rowDone(r + 1, nby) is called). The ground-truth buildings of buildWorld are these
// same footprints (same ids, rings and heights). Ids: "b<i>_<j>_<lot>", stable across city sizes.
void forEachFootprint(const DemoOptions& options, const std::function<void(const Footprint&)>& visit,
                      const std::function<void(int done, int rows)>& rowDone = {});

// Ground-truth colour (linear in [0,1], the value written to 8-bit images after clamping and
// rounding) of a surface point: procedural albedo under the fixed lighting. `hit` must come from
// a ray cast against `layer.mesh`.
glm::dvec3 shade(const World& world, const Layer& layer, const RayHit& hit);
// Same for a hit on World::truth.
glm::dvec3 shade(const World& world, const RayHit& hit);

// Era colour casts applied to a whole photograph after rendering.
enum class EraCast { None, Sepia, Faded, Cyanotype };
glm::dvec3 applyCast(EraCast cast, glm::dvec3 rgb);

struct Shot {
  Camera camera;
  std::string date;  // ISO 8601, photographs only
  bool elevated = false;
  bool masked = false;  // writes a mask over its cars
  EraCast cast = EraCast::None;
  Layer cars;  // moving cars seen by this photograph only
};

struct ShotPlan {
  std::vector<Shot> photos;
  std::vector<Shot> views;  // held out: no cars, no cast, no distortion
};

// Chooses every camera (and the cars of each photograph). `caster` is built on world.truth.mesh.
ShotPlan planShots(const World& world, const RayCaster& caster);

// The ray for a sample at distorted pixel position pxDistorted: through the ideal pixel
// camera.undistort(pxDistorted) (the CPU warp, independent of any shader). nullopt where the
// distortion cannot be inverted. Returns a unit world direction.
std::optional<glm::dvec3> sampleRay(const Camera& camera, glm::dvec2 pxDistorted);

struct Rendered {
  Image8 color;     // RGB
  Image8 coverage;  // 255 where every sample of the pixel hit a surface, else 0
  Image8 mask;      // 0 on car pixels dilated by CitySettings::maskDilation, 255 elsewhere
};

// Ray casts a shot (world.truth plus the shot's cars): samplesPerAxis^2 samples per pixel on a
// regular sub-grid, averaged; rows shared among all cores. The era cast is applied last.
Rendered renderShot(const World& world, const RayCaster& truthCaster, const Shot& shot, int samplesPerAxis);

// Scans today's city (World::truth plus the trees and parked cars) with the mobile-mapping
// scanner of options.lidar: every hit becomes a point with its ASPRS class (asprsClass of the hit
// material: ground 2, building 6, trees 5, cars 1), its ground-truth colour (shade(), 8-bit values
// scaled to 16 bits), an intensity (the colour's luma times the cosine of incidence), and the hit
// triangle's normal turned towards the scanner. Points come street by street, turn by turn, ray by
// ray (deterministic; turns are shared among all cores). CRS "EPSG:2154".
PointCloud simulateLidar(const World& world);

// What simulateTraffic did: the FCD written (its path, the offset from SUMO's coordinates to the
// scene frame for scene.json's "traffic"), or why not.
struct TrafficResult {
  bool ok = false;
  std::string fcdPath;     // outDir/fcd.xml
  glm::dvec2 offset{0.0};  // scene frame = SUMO's x, y + offset
  std::string message;     // what was done, or why it failed (a missing tool named)
  double wallSeconds = 0.0;
};

// Writes outDir/traffic/ (streets.nod.xml, streets.edg.xml, streets.net.xml, trips.xml, logs) and
// outDir/fcd.xml: every street of World::streets two-way with one lane each way, nodes at their
// crossings, coordinates relative to CitySettings::originXY. Never throws for a missing or
// failing tool: the result says which and why.
TrafficResult simulateTraffic(const World& world, const TrafficOptions& options, const std::string& outDir);

struct DemoSummary {
  std::string scenePath, viewsPath, truthDir;
  int photos = 0, views = 0, buildings = 0;  // buildings: LOD1 footprints written
  std::size_t points = 0;                    // of the simulated lidar scan
  TrafficResult traffic;                     // the SUMO run (options.traffic)
};

// Writes the demo scene into outDir (created): scene.json, dtm.tif, buildings.geojson,
// points.las and points.ply (the lidar scan), cameras.json, images/, masks/, views.json, truth/
// (see docs/demo-city.md). A large city writes dtm.tif as a Cloud-Optimized GeoTIFF (tiled, with
// overviews) and buildings.gpkg (GeoPackage with its spatial index) instead of buildings.geojson.
DemoSummary generate(const DemoOptions& options, const std::string& outDir,
                     std::function<void(const std::string&)> progress = {});

}  // namespace hv::demo
