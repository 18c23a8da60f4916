// The programs the GL passes link, each a type whose uniforms are resolved once at link time
// (gpu/program.h): a name the linked program lacks throws, naming the program and the uniform,
// unless it is declared optional below (with the variant that leaves it out). The sources are
// named too, not indices into a list; programSources() (render/renderer.h), the list the shader
// test walks, is made of them.
#pragma once

#include "hv/gpu/gl.h"
#include "hv/render/renderer.h"

#include <string>
#include <vector>

namespace hv::render::gl {

struct ProgramSources {
  ProgramSource depth;       // photographs' depth maps
  ProgramSource viewDepth;   // the view's depth and building ids
  ProgramSource shade;       // the blend
  ProgramSource tileDepth;   // tile depth ranges for culling
  ProgramSource naive;       // the naive baseline, with a count any ES 3.0 context has units for
  ProgramSource pointDepth;  // point sprites into depth maps and the view
  ProgramSource pointColor;  // textured sprites, 2022 form (N')
  ProgramSource pointMat3;   // the 2016 form (the renderer picks K)
  ProgramSource debugDepth;  // DebugView::DepthMap
  ProgramSource lines;       // DebugSettings::frusta
  ProgramSource vehicles;    // the traffic's models and contact shadows
  ProgramSource vehicleDepth;  // the view's linear depth as the rasteriser's, for the traffic
  ProgramSource pickDepth;     // one texel of the view's depth, packed for a read-back (picking)
};
const ProgramSources& programs();

// Links `src`, with `extraDefines` after its own. Throws with the info log.
gpu::Program linkProgram(const ProgramSource& src, const std::vector<std::string>& extraDefines = {});

// depth.vert + depth.frag: a photograph's depth map, or the view's depth and building ids.
struct DepthProgram {
  gpu::Program program;
  GLint clipFromRender = -1, near = -1, far = -1, date = -1, pushBack = -1, center = -1;
  DepthProgram() = default;
  explicit DepthProgram(const ProgramSource& src);
};

// fullscreen.vert + ibr_shade.frag: the blend, with the photographs in texture arrays or, the
// naive binding (HV_NAIVE_COUNT = n), on n sampler pairs.
struct ShadeProgram {
  gpu::Program program;
  GLint images = -1, depthMaps = -1;           // the array binding
  std::vector<GLint> naiveImages, naiveDepths;  // the naive binding, per image
  GLint params = -1, viewDepth = -1, idealLookup = -1, useLookup = -1, tileLists = -1, viewBuilding = -1,
        validity = -1, validityWidth = -1, pointColor = -1, points = -1, meshPushBack = -1, culling = -1,
        tileSize = -1, tilesX = -1, viewRectMin = -1, viewRectInvSize = -1, viewDepthSize = -1, viewNear = -1,
        viewFar = -1, sphereRadius = -1, viewCenter = -1, viewDirFromPix = -1, imageCount = -1, method = -1,
        region = -1, blendK = -1, occlusion = -1, debugImage = -1, background = -1, mode = -1;
  // shaders/untextured.glsl: where no photograph contributes.
  GLint shading = -1, sky = -1, up = -1, sunDir = -1, albedo = -1, skyLight = -1, groundLight = -1, sunLight = -1,
        horizon = -1, zenith = -1;
  // The orthophoto on untextured terrain (ibr_shade.frag).
  GLint orthophotoOn = -1, orthophoto = -1, orthoU = -1, orthoV = -1;
  // Picture quality (the array binding only; -1 in the naive one): weights, feathering, mipmaps,
  // the transient filter.
  GLint weighting = -1, resolutionWeight = -1, penaltyEpsilon = -1, viewFocal = -1, feather = -1, maskFeather = -1,
        mipmaps = -1, sliceWidth = -1, consensus = -1, geometryK = -1;
  ShadeProgram() = default;
  // naiveCount > 0: the naive binding with that many images. `config`: the defines of a
  // per-configuration program (gl/shade_config.h), whose options' uniforms may be compiled out.
  explicit ShadeProgram(const ProgramSource& src, int naiveCount = 0, const std::vector<std::string>& config = {});
};

// fullscreen.vert + tile_depth.frag: each tile's depth range.
struct TileDepthProgram {
  gpu::Program program;
  GLint viewDepth = -1, depthSize = -1, tileSize = -1;
  TileDepthProgram() = default;
  explicit TileDepthProgram(const ProgramSource& src);
};

// points.vert + points.frag: sprites' depths (HV_DEPTH_ONLY), or their colours (2022 form, or the
// 2016 mat3 form with HV_MAT3_K images).
struct PointProgram {
  gpu::Program program;
  // Both variants.
  GLint M = -1, MinvT = -1, Minv = -1, C = -1, targetSize = -1, near = -1, far = -1, maxPointSize = -1,
        depthOffset = -1, classify = -1, dropTransient = -1, keptClasses = -1, radius = -1;
  // The colour variants.
  GLint images = -1, depthMaps = -1, params = -1, viewDepth = -1, pointParams = -1, imageCount = -1, method = -1,
        region = -1, blendK = -1, occlusion = -1, epsilonTest = -1, epsilon = -1, eyeDome = -1, edlStrength = -1,
        edlRadius = -1, depthTolerance = -1, viewBuilding = -1, validity = -1, validityWidth = -1;
  PointProgram() = default;
  explicit PointProgram(const ProgramSource& src, const std::vector<std::string>& extraDefines = {});
};

// fullscreen.vert + debug_depth.frag: DebugView::DepthMap.
struct DebugDepthProgram {
  gpu::Program program;
  GLint depthMaps = -1, slice = -1, rectMin = -1, rectSize = -1;
  DebugDepthProgram() = default;
  explicit DebugDepthProgram(const ProgramSource& src);
};

// lines.vert + lines.frag: the frusta overlay.
struct LinesProgram {
  gpu::Program program;
  GLint clipFromRender = -1, near = -1, far = -1, color = -1;
  LinesProgram() = default;
  explicit LinesProgram(const ProgramSource& src);
};

// vehicles.vert + vehicles.frag: the traffic, each class's model instanced and lit by sun and sky,
// and a contact shadow under each vehicle.
struct VehicleProgram {
  gpu::Program program;
  GLint clipFromRender = -1, sunDir = -1, skyLight = -1, groundLight = -1, sunLight = -1, shadow = -1,
        shadowOpacity = -1, shadowLift = -1;
  VehicleProgram() = default;
  explicit VehicleProgram(const ProgramSource& src);
};

// fullscreen.vert + vehicle_depth.frag: the view's linear depth rewritten as the rasteriser's
// depth of the same projection, so that the vehicles are drawn without gl_FragDepth.
struct VehicleDepthProgram {
  gpu::Program program;
  GLint viewDepth = -1, near = -1, far = -1;
  VehicleDepthProgram() = default;
  explicit VehicleDepthProgram(const ProgramSource& src);
};

// fullscreen.vert + pick_depth.frag: one texel of the view's linear depth packed into RGBA8
// (GlBackend::readViewDepth).
struct PickDepthProgram {
  gpu::Program program;
  GLint viewDepth = -1, texel = -1;
  PickDepthProgram() = default;
  explicit PickDepthProgram(const ProgramSource& src);
};

}  // namespace hv::render::gl
