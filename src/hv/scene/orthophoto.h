// An orthophoto draped on the terrain where no photograph reaches (de Castro & Brédif 2022's
// terrain texture; scene.json "orthophoto", docs/formats.md): one RGBA image, north up, over a
// rectangle of the scene frame's x, y, read at load (hv/io/native/orthophoto_reader.h). The
// renderer samples it as the base colour of untextured terrain (shaders/untextured.glsl); the CPU
// twin of that lookup is sampleOrthophoto.
#pragma once

#include <glm/glm.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace hv {

struct Orthophoto {
  std::string path;  // as scene.json names it (a file or a connection string)
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;  // width * height * 4, straight alpha, row 0 the northern edge
  // The rectangle the image covers, scene frame: column 0's left edge is minX, row 0's top edge maxY.
  double minX = 0.0, minY = 0.0, maxX = 0.0, maxY = 0.0;

  bool empty() const { return width <= 0 || height <= 0; }
  double metresPerPixelX() const { return width > 0 ? (maxX - minX) / width : 0.0; }
  double metresPerPixelY() const { return height > 0 ? (maxY - minY) / height : 0.0; }
  std::size_t bytes() const { return rgba.size(); }
};

// Texture coordinates of a point of the scene frame: u across from minX (0) to maxX (1), v down
// from maxY (0) to minY (1), the image's rows in upload order (row 0 at v = 0). Outside [0, 1]:
// off the orthophoto.
glm::dvec2 orthophotoTexCoord(const Orthophoto& o, double x, double y);

// The affine map from the render frame (scene frame minus `origin`) to texture coordinates, as the
// shader takes it: u = dot(uRow, (x, y, 1)), v = dot(vRow, (x, y, 1)).
struct OrthophotoAffine {
  glm::dvec3 uRow{0.0}, vRow{0.0};
};
OrthophotoAffine orthophotoAffine(const Orthophoto& o, const glm::dvec3& origin);

// The colour a bilinear (GL_LINEAR, clamp to edge) lookup at texture coordinates uv returns,
// straight RGBA in [0, 1]: the CPU reference of the shader's textureLod(u_orthophoto, uv, 0.0).
glm::dvec4 sampleOrthophoto(const Orthophoto& o, glm::dvec2 uv);

}  // namespace hv
