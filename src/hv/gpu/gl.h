// The thin GL layer: RAII handles, limits, shader programs. The only headers that include the
// GLES 3 API are under hv/gpu and hv/render; everything is GLES 3.0 / GLSL ES 3.00 (the WebGL2
// subset).
#pragma once

#include "hv/gpu/shader_assembly.h"

#include <GLES3/gl3.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace hv::gpu {

// What the context can do; queried once at start and used to size everything.
// EXT_texture_filter_anisotropic's enums (not in the core GLES 3.0 header).
inline constexpr GLenum kGlTextureMaxAnisotropy = 0x84FE;
inline constexpr GLenum kGlMaxTextureMaxAnisotropy = 0x84FF;

struct GlLimits {
  int maxTextureSize = 0;
  int maxArrayTextureLayers = 0;
  int maxTextureImageUnits = 0;
  int maxUniformBlockSize = 0;
  int maxVaryingComponents = 0;
  int maxFragmentUniformVectors = 0;
  int maxRenderbufferSize = 0;
  // GL_MAX_TEXTURE_MAX_ANISOTROPY_EXT where EXT_texture_filter_anisotropic is present, else 0.
  float maxAnisotropy = 0.0f;
  std::string vendor, renderer, version, glslVersion;
};
GlLimits queryLimits();
std::string glDescription();

// Throws std::runtime_error naming `where` and the GL error, if any is pending.
void checkGlError(const char* where);
// Drains pending errors; returns how many there were.
int clearGlErrors();

// Move-only owner of one GL name.
template <void (*Delete)(GLuint)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint id) : id_(id) {}
  ~GlName() { reset(); }
  GlName(GlName&& o) noexcept : id_(std::exchange(o.id_, 0)) {}
  GlName& operator=(GlName&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = std::exchange(o.id_, 0);
    }
    return *this;
  }
  GlName(const GlName&) = delete;
  GlName& operator=(const GlName&) = delete;
  GLuint id() const { return id_; }
  explicit operator bool() const { return id_ != 0; }
  void reset() {
    if (id_) Delete(id_);
    id_ = 0;
  }

 private:
  GLuint id_ = 0;
};

void deleteTexture(GLuint id);
void deleteBuffer(GLuint id);
void deleteFramebuffer(GLuint id);
void deleteVertexArray(GLuint id);
void deleteProgram(GLuint id);
using Texture = GlName<deleteTexture>;
using Buffer = GlName<deleteBuffer>;
using Framebuffer = GlName<deleteFramebuffer>;
using VertexArray = GlName<deleteVertexArray>;

Texture makeTexture();
Buffer makeBuffer();
Framebuffer makeFramebuffer();
VertexArray makeVertexArray();

// A linked program from two shaders, each assembled by preprocessShader (hv/gpu/shader_assembly.h:
// includes resolved, `defines` inserted after the #version line). Throws with the info log.
class Program {
 public:
  Program() = default;
  Program(const std::string& vertexFile, const std::string& fragmentFile,
          const std::vector<std::string>& defines = {});
  Program(const ShaderText& vertex, const ShaderText& fragment, const std::vector<std::string>& defines = {});
  GLuint id() const { return name_.id(); }
  void use() const { glUseProgram(name_.id()); }
  GLint uniform(const char* name) const;  // -1 when absent (optimised out)

 private:
  GlName<deleteProgram> name_;
  mutable std::map<std::string, GLint> uniforms_;
};

// Checks that the bound framebuffer is complete; throws naming `what` otherwise.
void checkFramebuffer(const char* what);

}  // namespace hv::gpu
