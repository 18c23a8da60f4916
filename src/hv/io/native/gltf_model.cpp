#include "hv/io/native/gltf_model.h"

#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"

// tinygltf without its file system (buffers must be in the file: nothing is read beside it) and
// without image decoding (textures are not used).
#define TINYGLTF_IMPLEMENTATION
#define TINYGLTF_NO_FS
#define TINYGLTF_NO_STB_IMAGE
#define TINYGLTF_NO_STB_IMAGE_WRITE
#define TINYGLTF_NO_EXTERNAL_IMAGE
// tinygltf's writers use std::ofstream even without its file system, and do not include it.
#include <fstream>
// (a block of its own: include sorting must keep it after <fstream>)
#include <tiny_gltf.h>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <cstring>

namespace hv {

namespace {

bool ignoreImage(tinygltf::Image*, const int, std::string*, std::string*, int, int, const unsigned char*, int, void*) {
  return true;
}

glm::dmat4 localMatrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) return glm::make_mat4(node.matrix.data());  // column-major, as glm's
  glm::dmat4 m(1.0);
  if (node.translation.size() == 3)
    m = glm::translate(m, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    m *= glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
  if (node.scale.size() == 3) m = glm::scale(m, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

class Reader {
 public:
  Reader(const tinygltf::Model& model, const std::string& source) : m_(model), source_(source) {}

  VehicleModel read() {
    const int sceneIndex = m_.defaultScene >= 0 ? m_.defaultScene : 0;
    if (!m_.scenes.empty()) {
      if (sceneIndex >= int(m_.scenes.size())) fail("scene " + std::to_string(sceneIndex) + ": no such scene");
      for (const int n : m_.scenes[std::size_t(sceneIndex)].nodes) node(n, glm::dmat4(1.0), 0);
    } else {
      // No scene: every mesh as it is.
      for (std::size_t k = 0; k < m_.meshes.size(); ++k) mesh(int(k), glm::dmat4(1.0));
    }
    if (out_.vertices.empty())
      fail("expected triangles (a mesh primitive of mode TRIANGLES with POSITION), found none");
    if (!fitToUnitBox(out_)) fail("expected a model with a length, a width and a height, got a flat or empty one");
    out_.source = source_;
    return std::move(out_);
  }

 private:
  [[noreturn]] void fail(const std::string& what) const { throw InputError(source_ + ": " + what); }

  void node(int index, const glm::dmat4& parent, int depth) {
    if (index < 0 || index >= int(m_.nodes.size())) fail("node " + std::to_string(index) + ": no such node");
    if (depth > 64) fail("nodes: expected a tree, got a hierarchy deeper than 64 (a cycle?)");
    const tinygltf::Node& n = m_.nodes[std::size_t(index)];
    const glm::dmat4 world = parent * localMatrix(n);
    if (n.mesh >= 0) mesh(n.mesh, world);
    for (const int c : n.children) node(c, world, depth + 1);
  }

  // The floats of an accessor of `components` floats per element.
  std::vector<float> floats(int index, int type, const std::string& what) const {
    const tinygltf::Accessor& a = accessor(index, what);
    if (a.type != type || a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      fail(what + ": expected an accessor of " + std::to_string(tinygltf::GetNumComponentsInType(std::uint32_t(type))) +
           " floats per element");
    const int comps = tinygltf::GetNumComponentsInType(std::uint32_t(type));
    std::vector<float> out(a.count * std::size_t(comps));
    const auto [bytes, stride] = view(a, std::size_t(comps) * 4, what);
    for (std::size_t i = 0; i < a.count; ++i)
      std::memcpy(&out[i * std::size_t(comps)], bytes + i * stride, std::size_t(comps) * 4);
    for (const float f : out)
      if (!std::isfinite(f)) fail(what + ": expected finite numbers");
    return out;
  }

  std::vector<std::uint32_t> indices(int index, std::size_t vertexCount) const {
    const tinygltf::Accessor& a = accessor(index, "indices");
    std::size_t size = 0;
    switch (a.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        size = 1;
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        size = 2;
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        size = 4;
        break;
      default:
        fail("indices: expected unsigned bytes, shorts or ints");
    }
    if (a.type != TINYGLTF_TYPE_SCALAR) fail("indices: expected scalars");
    const auto [bytes, stride] = view(a, size, "indices");
    std::vector<std::uint32_t> out(a.count);
    for (std::size_t i = 0; i < a.count; ++i) {
      const std::uint8_t* p = bytes + i * stride;
      std::uint32_t v = 0;
      if (size == 1)
        v = p[0];
      else if (size == 2) {
        std::uint16_t s;
        std::memcpy(&s, p, 2);
        v = s;
      } else
        std::memcpy(&v, p, 4);
      if (v >= vertexCount)
        fail("indices: index " + std::to_string(v) + " past the " + std::to_string(vertexCount) + " vertices");
      out[i] = v;
    }
    return out;
  }

  const tinygltf::Accessor& accessor(int index, const std::string& what) const {
    if (index < 0 || index >= int(m_.accessors.size()))
      fail(what + ": accessor " + std::to_string(index) + ": no such accessor");
    const tinygltf::Accessor& a = m_.accessors[std::size_t(index)];
    if (a.sparse.isSparse) fail(what + ": sparse accessors are not read");
    if (a.bufferView < 0) fail(what + ": expected an accessor with a bufferView");
    return a;
  }

  // The accessor's first byte and stride, checked to lie in its buffer.
  std::pair<const std::uint8_t*, std::size_t> view(const tinygltf::Accessor& a, std::size_t elementBytes,
                                                   const std::string& what) const {
    if (a.bufferView >= int(m_.bufferViews.size()))
      fail(what + ": bufferView " + std::to_string(a.bufferView) + ": no such view");
    const tinygltf::BufferView& v = m_.bufferViews[std::size_t(a.bufferView)];
    if (v.buffer < 0 || v.buffer >= int(m_.buffers.size()))
      fail(what + ": buffer " + std::to_string(v.buffer) + ": no such buffer");
    const std::vector<unsigned char>& data = m_.buffers[std::size_t(v.buffer)].data;
    const std::size_t stride = v.byteStride ? v.byteStride : elementBytes;
    if (stride < elementBytes) fail(what + ": expected a byteStride of at least " + std::to_string(elementBytes));
    if (a.count > kMaxGltfTriangles * 3)
      fail(what + ": more than " + std::to_string(kMaxGltfTriangles * 3) + " elements");
    const std::size_t begin = v.byteOffset + a.byteOffset;
    const std::size_t span = a.count == 0 ? 0 : (a.count - 1) * stride + elementBytes;
    if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset || a.byteOffset > v.byteLength ||
        span > v.byteLength - a.byteOffset)
      fail(what + ": expected the accessor inside its bufferView and buffer (" + std::to_string(data.size()) +
           " bytes)");
    return {data.data() + begin, stride};
  }

  glm::vec3 materialColour(int material, float* paint) const {
    *paint = 0.0f;
    if (material < 0) return glm::vec3(0.8f);
    if (material >= int(m_.materials.size())) fail("material " + std::to_string(material) + ": no such material");
    const tinygltf::Material& mat = m_.materials[std::size_t(material)];
    if (mat.name == "paint" || mat.name == "body") *paint = 1.0f;
    const std::vector<double>& f = mat.pbrMetallicRoughness.baseColorFactor;
    glm::vec3 c(0.8f);
    if (f.size() >= 3) c = glm::vec3(float(f[0]), float(f[1]), float(f[2]));
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(c[k])) fail("material '" + mat.name + "': expected a finite baseColorFactor");
    return glm::clamp(c, 0.0f, 1.0f);
  }

  void mesh(int index, const glm::dmat4& world) {
    if (index < 0 || index >= int(m_.meshes.size())) fail("mesh " + std::to_string(index) + ": no such mesh");
    const glm::dmat3 normalMatrix = glm::transpose(glm::inverse(glm::dmat3(world)));
    for (const tinygltf::Primitive& prim : m_.meshes[std::size_t(index)].primitives) {
      if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) continue;  // points, lines
      const auto pos = prim.attributes.find("POSITION");
      if (pos == prim.attributes.end()) fail("mesh " + std::to_string(index) + ": expected a POSITION attribute");
      const std::vector<float> p = floats(pos->second, TINYGLTF_TYPE_VEC3, "POSITION");
      const std::size_t count = p.size() / 3;
      std::vector<float> n;
      if (const auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
        n = floats(it->second, TINYGLTF_TYPE_VEC3, "NORMAL");
        if (n.size() != p.size()) fail("NORMAL: expected as many normals as positions");
      }
      std::vector<std::uint32_t> idx;
      if (prim.indices >= 0)
        idx = indices(prim.indices, count);
      else
        for (std::uint32_t i = 0; i < count; ++i) idx.push_back(i);
      if (out_.vertices.size() / 3 + idx.size() / 3 > kMaxGltfTriangles)
        fail("expected at most " + std::to_string(kMaxGltfTriangles) + " triangles");
      float paint = 0.0f;
      const glm::vec3 colour = materialColour(prim.material, &paint);
      for (std::size_t t = 0; t + 2 < idx.size(); t += 3) {
        ModelVertex v[3];
        for (int k = 0; k < 3; ++k) {
          const std::uint32_t i = idx[t + std::size_t(k)];
          const glm::dvec3 q = glm::dvec3(world * glm::dvec4(p[3 * i], p[3 * i + 1], p[3 * i + 2], 1.0));
          v[k].local = vehicleFromGltf(glm::vec3(q));
          v[k].colour = colour;
          v[k].paint = paint;
          if (!n.empty())
            v[k].normal = vehicleFromGltf(glm::vec3(normalMatrix * glm::dvec3(n[3 * i], n[3 * i + 1], n[3 * i + 2])));
        }
        // vehicleFromGltf is a rotation (x -> -x with y, z swapped: determinant +1), the winding stays.
        const glm::vec3 face = glm::cross(v[1].local - v[0].local, v[2].local - v[0].local);
        for (ModelVertex& w : v) {
          const float len = glm::length(w.normal);
          if (n.empty() || !(len > 0.0f) || !std::isfinite(len)) w.normal = face;
        }
        for (ModelVertex& w : v) {
          const float len = glm::length(w.normal);
          w.normal = len > 0.0f && std::isfinite(len) ? w.normal / len : glm::vec3(0.0f, 0.0f, 1.0f);
        }
        for (ModelVertex& w : v)
          for (int k = 0; k < 3; ++k)
            if (!std::isfinite(w.local[k])) fail("node transforms: expected finite positions once placed");
        out_.vertices.insert(out_.vertices.end(), v, v + 3);
      }
    }
  }

  const tinygltf::Model& m_;
  std::string source_;
  VehicleModel out_;
};

}  // namespace

VehicleModel parseGltfVehicle(const std::uint8_t* data, std::size_t size, const std::string& source) {
  if (size > kMaxGltfBytes) throw InputError(source + ": expected a glTF file of at most 64 MiB");
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(&ignoreImage, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const bool ok =
      binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, data, unsigned(size), "")
             : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(data), unsigned(size), "");
  if (!ok) {
    while (!err.empty() && (err.back() == '\n' || err.back() == ' ')) err.pop_back();
    throw InputError(source + ": expected glTF 2.0 (JSON with its buffers embedded as data: URIs, or GLB): " +
                     (err.empty() ? std::string("unreadable") : err));
  }
  return Reader(model, source).read();
}

VehicleModel readGltfVehicle(const std::string& path) {
  requireRegularFile(path, "vehicle model", kMaxGltfBytes);
  const std::vector<std::uint8_t> bytes = readFileBytes(path);
  return parseGltfVehicle(bytes.data(), bytes.size(), path);
}

}  // namespace hv
