#include "hv/render/gl/programs.h"

namespace hv::render {

namespace gl {

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
  };
  return p;
}

gpu::Program linkProgram(const ProgramSource& src, const std::vector<std::string>& extraDefines) {
  std::vector<std::string> defines = src.defines;
  defines.insert(defines.end(), extraDefines.begin(), extraDefines.end());
  return gpu::Program(src.vertex, src.fragment, defines);
}

}  // namespace gl

const std::vector<ProgramSource>& programSources() {
  static const std::vector<ProgramSource> list = [] {
    const gl::ProgramSources& p = gl::programs();
    return std::vector<ProgramSource>{p.depth,      p.viewDepth,  p.shade,     p.tileDepth,  p.naive,
                                      p.pointDepth, p.pointColor, p.pointMat3, p.debugDepth, p.lines};
  }();
  return list;
}

}  // namespace hv::render
