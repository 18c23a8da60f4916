// Writes every shader stage the renderer compiles, assembled as gpu::Program assembles it
// (hv/gpu/shader_assembly.h), into a folder: one file per stage, named after its program and
// defines, ending in .vert or .frag. tests/shader_validate.sh runs glslangValidator on them.
//
//   hv_shader_dump OUT_DIR
//
// The programs: every entry of render::programSources(), plus the forms the renderer links with
// counts of its own choosing: the naive binding at several image counts and the mat3 sprite form
// at several K (src/hv/render/renderer.cpp picks them from the context's limits).
#include "hv/gpu/shader_assembly.h"
#include "hv/render/renderer.h"

#include <exception>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using hv::render::ProgramSource;

std::string fileName(size_t index, const std::string& stage, const std::vector<std::string>& defines) {
  std::string name = (index < 10 ? "0" : "") + std::to_string(index) + "-" + stage;
  for (std::string d : defines) {
    for (char& c : d)
      if (c == '=') c = '-';
    name += "+" + d;
  }
  return name;
}

void write(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: hv_shader_dump OUT_DIR\n";
    return 2;
  }
  const fs::path dir = argv[1];
  try {
    fs::create_directories(dir);
    std::vector<ProgramSource> programs = hv::render::programSources();
    // Image counts and K that any ES 3.0 context, llvmpipe's and larger GPUs' cover: the smallest,
    // and counts past the 16 the shader once had a fixed ladder for.
    for (int n : {1, 2, 13, 24})
      programs.push_back({"fullscreen.vert", "ibr_shade.frag", {"HV_NAIVE", "HV_NAIVE_COUNT=" + std::to_string(n)}});
    for (int k : {1, 2, 7})
      programs.push_back({"points.vert", "points.frag", {"HV_MAT3_K=" + std::to_string(k)}});
    int stages = 0;
    for (size_t i = 0; i < programs.size(); ++i) {
      const ProgramSource& p = programs[i];
      for (const std::string& stage : {p.vertex, p.fragment}) {
        const std::string ext = stage.substr(stage.rfind('.'));
        const std::string stem = stage.substr(0, stage.rfind('.'));
        write(dir / (fileName(i, stem, p.defines) + ext), hv::gpu::preprocessShader(stage, p.defines));
        ++stages;
      }
    }
    std::cout << stages << " stages of " << programs.size() << " programs written to " << dir.string() << "\n";
  } catch (const std::exception& e) {
    std::cerr << "hv_shader_dump: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
