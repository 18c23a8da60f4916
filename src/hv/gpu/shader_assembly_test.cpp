// Shader assembly without a GL context (hv/gpu/shader_assembly.h): the generated naive binding,
// include and define resolution, and the per-image test chain shared by the mesh and point passes.
#include "hv/gpu/shader_assembly.h"

#include "hv/gpu/shader_sources.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

namespace hv::gpu {
namespace {

int occurrences(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

TEST(ShaderAssembly, NaiveBindingForOneImage) {
  const std::string g = naiveBindingGlsl(1);
  EXPECT_EQ(occurrences(g, "uniform highp sampler2D u_image0;\n"), 1);
  EXPECT_EQ(occurrences(g, "uniform highp sampler2D u_depth0;\n"), 1);
  EXPECT_EQ(occurrences(g, "uniform "), 2);
  EXPECT_EQ(occurrences(g, "void hv_naiveBlend(vec3 P, vec3 normal, vec2 existed, inout HvBlend b) {\n"), 1);
  EXPECT_EQ(occurrences(g, "  hv_naiveStep(0, u_image0, u_depth0, P, normal, existed, b);\n"), 1);
  EXPECT_EQ(occurrences(g, "hv_naiveStep("), 1);
  EXPECT_EQ(g.find("u_image1"), std::string::npos);
}

TEST(ShaderAssembly, NaiveBindingForThirteenImagesInOrder) {
  const std::string g = naiveBindingGlsl(13);
  EXPECT_EQ(occurrences(g, "uniform highp sampler2D u_image"), 13);
  EXPECT_EQ(occurrences(g, "uniform highp sampler2D u_depth"), 13);
  EXPECT_EQ(occurrences(g, "hv_naiveStep("), 13);
  // Step i uses pair i, in increasing i (the renderer binds the i-th selected image to pair i).
  size_t last = 0;
  for (int i = 0; i < 13; ++i) {
    const std::string si = std::to_string(i);
    EXPECT_EQ(occurrences(g, "uniform highp sampler2D u_image" + si + ";\n"), 1) << i;
    EXPECT_EQ(occurrences(g, "uniform highp sampler2D u_depth" + si + ";\n"), 1) << i;
    const size_t at =
        g.find("  hv_naiveStep(" + si + ", u_image" + si + ", u_depth" + si + ", P, normal, existed, b);\n");
    ASSERT_NE(at, std::string::npos) << i;
    EXPECT_GT(at, last) << i;
    last = at;
  }
  EXPECT_EQ(g.find("u_image13"), std::string::npos);
  EXPECT_THROW(naiveBindingGlsl(0), std::invalid_argument);
}

TEST(ShaderAssembly, DefinesFollowTheVersionLineAndIncludesAreResolved) {
  const ShaderText probe{"probe.frag", "#version 300 es\n#include \"colormap.glsl\"\nvoid main() {}\n"};
  const std::string s = preprocessShader(probe, {"HV_A", "HV_B=3"});
  EXPECT_EQ(s.rfind("#version 300 es\n#define HV_A\n#define HV_B 3\n", 0), 0u) << s;
  EXPECT_NE(s.find(*findShaderSource("colormap.glsl")), std::string::npos);
  EXPECT_EQ(s.find("#include"), std::string::npos);
  EXPECT_THROW(preprocessShader(ShaderText{"probe.frag", "#version 300 es\n#include \"absent.glsl\"\n"}, {}),
               std::runtime_error);
}

TEST(ShaderAssembly, NaiveShadingProgramTakesItsCountFromTheDefine) {
  const std::string naive = preprocessShader("ibr_shade.frag", {"HV_NAIVE", "HV_NAIVE_COUNT=13"});
  EXPECT_NE(naive.find(naiveBindingGlsl(13)), std::string::npos);
  EXPECT_EQ(naive.find("#include"), std::string::npos);
  // The array binding: the generated include yields nothing (it sits under #ifdef HV_NAIVE).
  const std::string arrays = preprocessShader("ibr_shade.frag", {});
  EXPECT_EQ(arrays.find("u_image0"), std::string::npos);
  EXPECT_EQ(arrays.find("#include"), std::string::npos);
}

TEST(ShaderAssembly, MalformedNaiveCountIsNamed) {
  for (const std::vector<std::string>& defines :
       {std::vector<std::string>{"HV_NAIVE"}, {"HV_NAIVE", "HV_NAIVE_COUNT=0"}, {"HV_NAIVE", "HV_NAIVE_COUNT=x3"},
        {"HV_NAIVE", "HV_NAIVE_COUNT="}, {"HV_NAIVE", "HV_NAIVE_COUNT=4 "}}) {
    try {
      preprocessShader("ibr_shade.frag", defines);
      ADD_FAILURE() << "accepted " << defines.back();
    } catch (const std::runtime_error& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("ibr_shade.frag"), std::string::npos) << m;
      EXPECT_NE(m.find("HV_NAIVE_COUNT"), std::string::npos) << m;
    }
  }
  try {
    preprocessShader(ShaderText{"probe.frag", "#version 300 es\n#include \"generated:nothing\"\n"}, {});
    ADD_FAILURE() << "accepted an unknown generated include";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("generated:nothing"), std::string::npos) << e.what();
  }
}

// The mesh and the point passes run one per-image test chain: its functions are defined once, in
// shaders/image_test.glsl, and both passes' colour programs are assembled with it.
TEST(ShaderAssembly, MeshAndPointPassesShareThePerImageTestChain) {
  const std::string chain = *findShaderSource("image_test.glsl");
  for (const char* f : {"bool hv_inImage(", "bool hv_project(", "bool hv_existedAt(", "float hv_shadowBias(",
                        "bool hv_shadowed(", "void hv_accumulate(", "vec2 hv_surfaceExisted("}) {
    EXPECT_EQ(occurrences(chain, f), 1) << f;
    for (const std::string& name : shaderNames())
      if (name != "image_test.glsl") EXPECT_EQ(occurrences(*findShaderSource(name), f), 0) << f << " in " << name;
    EXPECT_EQ(occurrences(preprocessShader("ibr_shade.frag", {}), f), 1) << f;
    EXPECT_EQ(occurrences(preprocessShader("points.frag", {}), f), 1) << f;
  }
  // Both passes call the date test (a photograph does not texture what did not exist at its date).
  for (const char* pass : {"ibr_shade.frag", "points.frag"})
    EXPECT_GE(occurrences(*findShaderSource(pass), "hv_existedAt(im, existed)"), 1) << pass;
}

}  // namespace
}  // namespace hv::gpu
