#include "hv/gpu/gl.h"

#include "hv/gpu/shader_assembly.h"
#include "hv/gpu/shader_sources.h"

#include <sstream>
#include <stdexcept>

namespace hv::gpu {

namespace {
GLint getInt(GLenum e) {
  GLint v = 0;
  glGetIntegerv(e, &v);
  return v;
}
std::string getString(GLenum e) {
  const auto* s = reinterpret_cast<const char*>(glGetString(e));
  return s ? s : "";
}
const char* errorName(GLenum e) {
  switch (e) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    default: return "unknown GL error";
  }
}
}  // namespace

GlLimits queryLimits() {
  GlLimits l;
  l.maxTextureSize = getInt(GL_MAX_TEXTURE_SIZE);
  l.maxArrayTextureLayers = getInt(GL_MAX_ARRAY_TEXTURE_LAYERS);
  l.maxTextureImageUnits = getInt(GL_MAX_TEXTURE_IMAGE_UNITS);
  l.maxUniformBlockSize = getInt(GL_MAX_UNIFORM_BLOCK_SIZE);
  l.maxVaryingComponents = getInt(GL_MAX_VARYING_COMPONENTS);
  l.maxFragmentUniformVectors = getInt(GL_MAX_FRAGMENT_UNIFORM_VECTORS);
  l.maxRenderbufferSize = getInt(GL_MAX_RENDERBUFFER_SIZE);
  const int extensions = getInt(GL_NUM_EXTENSIONS);
  for (int i = 0; i < extensions; ++i) {
    const GLubyte* name = glGetStringi(GL_EXTENSIONS, GLuint(i));
    if (name && std::string(reinterpret_cast<const char*>(name)) == "GL_EXT_texture_filter_anisotropic") {
      GLfloat v = 0.0f;
      glGetFloatv(kGlMaxTextureMaxAnisotropy, &v);
      l.maxAnisotropy = v;
    }
  }
  l.vendor = getString(GL_VENDOR);
  l.renderer = getString(GL_RENDERER);
  l.version = getString(GL_VERSION);
  l.glslVersion = getString(GL_SHADING_LANGUAGE_VERSION);
  return l;
}

std::string glDescription() { return getString(GL_VENDOR) + " | " + getString(GL_RENDERER) + " | " + getString(GL_VERSION); }

void checkGlError(const char* where) {
  const GLenum e = glGetError();
  if (e == GL_NO_ERROR) return;
  clearGlErrors();
  throw std::runtime_error(std::string("GL error ") + errorName(e) + " at " + where);
}

int clearGlErrors() {
  int n = 0;
  while (glGetError() != GL_NO_ERROR && n < 64) ++n;
  return n;
}

void deleteTexture(GLuint id) { glDeleteTextures(1, &id); }
void deleteBuffer(GLuint id) { glDeleteBuffers(1, &id); }
void deleteFramebuffer(GLuint id) { glDeleteFramebuffers(1, &id); }
void deleteVertexArray(GLuint id) { glDeleteVertexArrays(1, &id); }
void deleteProgram(GLuint id) { glDeleteProgram(id); }

Texture makeTexture() {
  GLuint id = 0;
  glGenTextures(1, &id);
  return Texture(id);
}
Buffer makeBuffer() {
  GLuint id = 0;
  glGenBuffers(1, &id);
  return Buffer(id);
}
Framebuffer makeFramebuffer() {
  GLuint id = 0;
  glGenFramebuffers(1, &id);
  return Framebuffer(id);
}
VertexArray makeVertexArray() {
  GLuint id = 0;
  glGenVertexArrays(1, &id);
  return VertexArray(id);
}

namespace {
const std::string* embedded(const std::string& file) {
  const std::string* src = findShaderSource(file);
  if (!src) throw std::runtime_error("shader not embedded: " + file);
  return src;
}
}  // namespace

namespace {
GLuint compile(GLenum type, const std::string& file, const std::string& source) {
  GLuint s = glCreateShader(type);
  const char* p = source.c_str();
  glShaderSource(s, 1, &p, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetShaderiv(s, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(std::max(len, 1)), '\0');
    glGetShaderInfoLog(s, len, nullptr, log.data());
    glDeleteShader(s);
    throw std::runtime_error("shader " + file + " does not compile:\n" + log);
  }
  return s;
}
}  // namespace

Program::Program(const std::string& vertexFile, const std::string& fragmentFile,
                 const std::vector<std::string>& defines)
    : Program(ShaderText{vertexFile, *embedded(vertexFile)}, ShaderText{fragmentFile, *embedded(fragmentFile)},
              defines) {}

Program::Program(const ShaderText& vertex, const ShaderText& fragment, const std::vector<std::string>& defines) {
  const std::string& vertexFile = vertex.name;
  const std::string& fragmentFile = fragment.name;
  const GLuint vs = compile(GL_VERTEX_SHADER, vertexFile, preprocessShader(vertex, defines));
  GLuint fs = 0;
  try {
    fs = compile(GL_FRAGMENT_SHADER, fragmentFile, preprocessShader(fragment, defines));
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  const GLuint prog = glCreateProgram();
  glAttachShader(prog, vs);
  glAttachShader(prog, fs);
  glLinkProgram(prog);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = 0;
  glGetProgramiv(prog, GL_LINK_STATUS, &ok);
  if (!ok) {
    GLint len = 0;
    glGetProgramiv(prog, GL_INFO_LOG_LENGTH, &len);
    std::string log(size_t(std::max(len, 1)), '\0');
    glGetProgramInfoLog(prog, len, nullptr, log.data());
    glDeleteProgram(prog);
    throw std::runtime_error("program " + vertexFile + " + " + fragmentFile + " does not link:\n" + log);
  }
  name_ = GlName<deleteProgram>(prog);
}

GLint Program::uniform(const char* name) const {
  auto it = uniforms_.find(name);
  if (it != uniforms_.end()) return it->second;
  const GLint loc = glGetUniformLocation(name_.id(), name);
  uniforms_[name] = loc;
  return loc;
}

void checkFramebuffer(const char* what) {
  const GLenum s = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (s != GL_FRAMEBUFFER_COMPLETE) {
    std::ostringstream m;
    m << "framebuffer for " << what << " incomplete (status 0x" << std::hex << s << ")";
    throw std::runtime_error(m.str());
  }
}

}  // namespace hv::gpu
