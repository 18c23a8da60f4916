// The typed programs (render/gl/programs.h, gpu/program.h): every one links on the context with
// all its declared uniforms resolved, and a name the linked program lacks fails at link time,
// naming the program and the uniform.
#include "hv/render/gl/programs.h"

#include "hv/gpu/program.h"
#include "hv/render/testing/gl_test_support.h"

#include <gtest/gtest.h>

namespace hv::render::gl {
namespace {

TEST(ProgramsGlTest, EveryTypedProgramResolvesItsUniforms) {
  testing::glContext();
  const ProgramSources& p = programs();
  EXPECT_NO_THROW(DepthProgram{p.depth});
  EXPECT_NO_THROW(DepthProgram{p.viewDepth});
  EXPECT_NO_THROW(ShadeProgram{p.shade});
  // The naive binding with 5 images (16 units: 6 for the pass, 2 per image).
  ShadeProgram naive(p.shade, 5);
  EXPECT_EQ(naive.naiveImages.size(), 5u);
  EXPECT_EQ(naive.naiveDepths.size(), 5u);
  EXPECT_EQ(naive.images, -1);   // no arrays in the naive variant
  EXPECT_EQ(naive.tileLists, -1);  // nor tile lists
  EXPECT_NO_THROW(TileDepthProgram{p.tileDepth});
  const PointProgram depthOnly(p.pointDepth);
  EXPECT_GE(depthOnly.radius, 0);
  EXPECT_EQ(depthOnly.images, -1);  // HV_DEPTH_ONLY: no colour uniforms resolved
  const PointProgram colour(p.pointColor);
  EXPECT_GE(colour.images, 0);
  EXPECT_NO_THROW(PointProgram{p.pointMat3});
  EXPECT_NO_THROW(DebugDepthProgram{p.debugDepth});
  EXPECT_NO_THROW(LinesProgram{p.lines});
  EXPECT_NO_THROW(VehicleProgram{p.vehicles});
}

TEST(ProgramsGlTest, MissingUniformThrowsNamingProgramAndUniform) {
  testing::glContext();
  const gpu::Program program = linkProgram(programs().lines);
  const gpu::UniformResolver u(program, "lines.vert + lines.frag");
  EXPECT_GE(u.required("u_color"), 0);
  EXPECT_EQ(u.optional("u_colour"), -1);
  try {
    u.required("u_colour");
    FAIL() << "a misspelt uniform resolved";
  } catch (const gpu::MissingUniform& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("lines.vert + lines.frag"), std::string::npos) << what;
    EXPECT_NE(what.find("'u_colour'"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace hv::render::gl
