#include "hv/render/gl/programs.h"

#include "hv/gpu/program.h"
#include "hv/render/gl/layer_peel_programs.h"

#include <algorithm>

namespace hv::render {

namespace gl {

namespace {

// "vertex + fragment [defines]", as messages name a program.
std::string programName(const ProgramSource& src, const std::vector<std::string>& extraDefines) {
  std::string name = src.vertex + " + " + src.fragment;
  std::vector<std::string> defines = src.defines;
  defines.insert(defines.end(), extraDefines.begin(), extraDefines.end());
  if (!defines.empty()) {
    name += " [";
    for (size_t i = 0; i < defines.size(); ++i) name += (i ? " " : "") + defines[i];
    name += "]";
  }
  return name;
}

bool hasDefine(const ProgramSource& src, const std::vector<std::string>& extra, const std::string& prefix) {
  auto match = [&](const std::string& d) { return d.rfind(prefix, 0) == 0; };
  return std::any_of(src.defines.begin(), src.defines.end(), match) || std::any_of(extra.begin(), extra.end(), match);
}

}  // namespace

const ProgramSources& programs() {
  static const ProgramSources p = {
      {"depth.vert", "depth.frag", {}},
      {"depth.vert", "depth.frag", {"HV_WRITE_BUILDING"}},
      {"fullscreen.vert", "ibr_shade.frag", {}},
      {"fullscreen.vert", "tile_depth.frag", {}},
      // The renderer links the naive baseline with its own count; this one has 16 units: 6 for the
      // pass, 2 per image.
      {"fullscreen.vert", "ibr_shade.frag", {"HV_NAIVE", "HV_NAIVE_COUNT=5"}},
      {"points.vert", "points.frag", {"HV_DEPTH_ONLY"}},
      {"points.vert", "points.frag", {}},
      {"points.vert", "points.frag", {"HV_MAT3_K=4"}},
      {"fullscreen.vert", "debug_depth.frag", {}},
      {"lines.vert", "lines.frag", {}},
      {"vehicles.vert", "vehicles.frag", {}},
      {"fullscreen.vert", "vehicle_depth.frag", {}},
      {"fullscreen.vert", "pick_depth.frag", {}},
  };
  return p;
}

gpu::Program linkProgram(const ProgramSource& src, const std::vector<std::string>& extraDefines) {
  std::vector<std::string> defines = src.defines;
  defines.insert(defines.end(), extraDefines.begin(), extraDefines.end());
  return gpu::Program(src.vertex, src.fragment, defines);
}

DepthProgram::DepthProgram(const ProgramSource& src) : program(linkProgram(src)) {
  const gpu::UniformResolver u(program, programName(src, {}));
  clipFromRender = u.required("u_clipFromRender");
  near = u.required("u_near");
  far = u.required("u_far");
  date = u.required("u_date");
  pushBack = u.required("u_pushBack");
  center = u.required("u_center");
}

ShadeProgram::ShadeProgram(const ProgramSource& src, int naiveCount, const std::vector<std::string>& config) {
  std::vector<std::string> extra = config;
  if (naiveCount > 0) extra = {"HV_NAIVE", "HV_NAIVE_COUNT=" + std::to_string(naiveCount)};
  program = linkProgram(src, extra);
  const gpu::UniformResolver u(program, programName(src, extra));
  const bool naive = naiveCount > 0 || hasDefine(src, extra, "HV_NAIVE");
  if (naive) {
    for (int k = 0; k < naiveCount; ++k) {
      naiveImages.push_back(u.required(("u_image" + std::to_string(k)).c_str()));
      naiveDepths.push_back(u.required(("u_depth" + std::to_string(k)).c_str()));
    }
  } else {
    images = u.required("u_images");
    depthMaps = u.required("u_depthMaps");
  }
  params = u.required("u_params");
  viewDepth = u.required("u_viewDepth");
  idealLookup = u.required("u_idealLookup");
  useLookup = u.required("u_useLookup");
  // The naive baseline walks every image: its variant has no tile lists.
  auto tiles = [&](const char* name) { return naive ? u.optional(name) : u.required(name); };
  tileLists = tiles("u_tileLists");
  viewBuilding = u.required("u_viewBuilding");
  validity = u.required("u_validity");
  validityWidth = u.required("u_validityWidth");
  pointColor = u.required("u_pointColor");
  points = u.required("u_points");
  meshPushBack = u.required("u_meshPushBack");
  culling = tiles("u_culling");
  tileSize = tiles("u_tileSize");
  tilesX = tiles("u_tilesX");
  viewRectMin = u.required("u_viewRectMin");
  viewRectInvSize = u.required("u_viewRectInvSize");
  viewDepthSize = u.required("u_viewDepthSize");
  viewNear = u.required("u_viewNear");
  viewFar = u.required("u_viewFar");
  sphereRadius = u.required("u_sphereRadius");
  viewCenter = u.required("u_viewCenter");
  viewDirFromPix = u.required("u_viewDirFromPix");
  imageCount = u.required("u_imageCount");
  // The geometry weights' per-configuration program has no distance weighting (region, K) and no
  // nearest method.
  auto blendUniform = [&](const char* name) { return config.empty() ? u.required(name) : u.optional(name); };
  method = blendUniform("u_method");
  region = blendUniform("u_region");
  blendK = blendUniform("u_blendK");
  occlusion = u.required("u_occlusion");
  debugImage = u.required("u_debugImage");
  background = u.required("u_background");
  mode = u.required("u_mode");
  // A per-configuration program leaves out the uniforms of the options that are off.
  auto quality = [&](const char* name) { return naive || !config.empty() ? u.optional(name) : u.required(name); };
  weighting = quality("u_weighting");
  resolutionWeight = quality("u_resolutionWeight");
  penaltyEpsilon = quality("u_penaltyEpsilon");
  geometryK = quality("u_geometryK");
  viewFocal = quality("u_viewFocal");
  feather = quality("u_feather");
  maskFeather = quality("u_maskFeather");
  consensus = quality("u_consensus");
  mipmaps = quality("u_mipmaps");
  sliceWidth = quality("u_sliceWidth");
  shading = u.required("u_shading");
  sky = u.required("u_sky");
  up = u.required("u_up");
  sunDir = u.required("u_sunDir");
  albedo = u.required("u_albedo");
  skyLight = u.required("u_skyLight");
  groundLight = u.required("u_groundLight");
  sunLight = u.required("u_sunLight");
  horizon = u.required("u_horizon");
  zenith = u.required("u_zenith");
  orthophotoOn = tiles("u_orthophotoOn");  // the array binding only (the shader's HV_NAIVE)
  orthophoto = tiles("u_orthophoto");
  orthoU = tiles("u_orthoU");
  orthoV = tiles("u_orthoV");
}

TileDepthProgram::TileDepthProgram(const ProgramSource& src) : program(linkProgram(src)) {
  const gpu::UniformResolver u(program, programName(src, {}));
  viewDepth = u.required("u_viewDepth");
  depthSize = u.required("u_depthSize");
  tileSize = u.required("u_tileSize");
}

PointProgram::PointProgram(const ProgramSource& src, const std::vector<std::string>& extraDefines)
    : program(linkProgram(src, extraDefines)) {
  const gpu::UniformResolver u(program, programName(src, extraDefines));
  M = u.required("u_M");
  MinvT = u.required("u_MinvT");
  Minv = u.required("u_Minv");
  C = u.required("u_C");
  targetSize = u.required("u_targetSize");
  near = u.required("u_near");
  far = u.required("u_far");
  maxPointSize = u.required("u_maxPointSize");
  depthOffset = u.required("u_depthOffset");
  classify = u.required("u_classify");
  dropTransient = u.required("u_dropTransient");
  keptClasses = u.required("u_keptClasses");
  radius = u.required("u_radius");
  if (hasDefine(src, extraDefines, "HV_DEPTH_ONLY")) return;
  images = u.required("u_images");
  depthMaps = u.required("u_depthMaps");
  params = u.required("u_params");
  viewDepth = u.required("u_viewDepth");
  pointParams = u.required("u_pointParams");
  imageCount = u.required("u_imageCount");
  method = u.required("u_method");
  region = u.required("u_region");
  blendK = u.required("u_blendK");
  occlusion = u.required("u_occlusion");
  epsilonTest = u.required("u_epsilonTest");
  epsilon = u.required("u_epsilon");
  eyeDome = u.required("u_eyeDome");
  edlStrength = u.required("u_edlStrength");
  edlRadius = u.required("u_edlRadius");
  depthTolerance = u.required("u_depthTolerance");
  viewBuilding = u.required("u_viewBuilding");
  validity = u.required("u_validity");
  validityWidth = u.required("u_validityWidth");
}

DebugDepthProgram::DebugDepthProgram(const ProgramSource& src) : program(linkProgram(src)) {
  const gpu::UniformResolver u(program, programName(src, {}));
  depthMaps = u.required("u_depthMaps");
  slice = u.required("u_slice");
  rectMin = u.required("u_rectMin");
  rectSize = u.required("u_rectSize");
}

LinesProgram::LinesProgram(const ProgramSource& src) : program(linkProgram(src)) {
  const gpu::UniformResolver u(program, programName(src, {}));
  clipFromRender = u.required("u_clipFromRender");
  near = u.required("u_near");
  far = u.required("u_far");
  color = u.required("u_color");
}

VehicleProgram::VehicleProgram(const ProgramSource& src) : program(linkProgram(src)) {
  const gpu::UniformResolver u(program, programName(src, {}));
  clipFromRender = u.required("u_clipFromRender");
  sunDir = u.required("u_sunDir");
  skyLight = u.required("u_skyLight");
  groundLight = u.required("u_groundLight");
  sunLight = u.required("u_sunLight");
  shadow = u.required("u_shadow");
  shadowOpacity = u.required("u_shadowOpacity");
  shadowLift = u.required("u_shadowLift");
}

VehicleDepthProgram::VehicleDepthProgram(const ProgramSource& src) : program(linkProgram(src)) {
  const gpu::UniformResolver u(program, programName(src, {}));
  viewDepth = u.required("u_viewDepth");
  near = u.required("u_near");
  far = u.required("u_far");
}

PickDepthProgram::PickDepthProgram(const ProgramSource& src) : program(linkProgram(src)) {
  const gpu::UniformResolver u(program, programName(src, {}));
  viewDepth = u.required("u_viewDepth");
  texel = u.required("u_texel");
}

}  // namespace gl

const std::vector<ProgramSource>& programSources() {
  static const std::vector<ProgramSource> list = [] {
    const gl::ProgramSources& p = gl::programs();
    const gl::LayerPeelSources& peel = gl::layerPeelPrograms();
    return std::vector<ProgramSource>{p.depth,      p.viewDepth,  p.shade,      p.tileDepth, p.naive,    p.pointDepth,
                                      p.pointColor, p.pointMat3,  p.debugDepth, p.lines,     p.vehicles, p.vehicleDepth,
                                      p.pickDepth,  peel.terrain, peel.item,    peel.test};
  }();
  return list;
}

}  // namespace hv::render
