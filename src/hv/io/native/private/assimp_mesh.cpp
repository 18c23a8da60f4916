#include "hv/io/native/mesh_reader.h"

#include "hv/io/native/ply_points.h"

#include "hv/util/diagnostics.h"
#include "hv/util/input_file.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace hv {

namespace {

// What Assimp may read with its PLY loader: a `.ply` name, or (its content detection) a line
// starting with "ply", in any case, within the first 200 bytes.
bool readAsPly(const std::string& path) {
  auto lower = [](std::string t) {
    for (char& c : t) c = char(std::tolower(static_cast<unsigned char>(c)));
    return t;
  };
  if (lower(std::filesystem::path(path).extension().string()) == ".ply") return true;
  std::ifstream in(path, std::ios::binary);
  std::string head(200, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head = lower(head.substr(0, std::size_t(std::max<std::streamsize>(in.gcount(), 0))));
  for (std::size_t at = head.find("ply"); at != std::string::npos; at = head.find("ply", at + 1))
    if (at == 0 || head[at - 1] == '\n' || head[at - 1] == '\r') return true;
  return false;
}

// A mesh at a URL (docs/services.md): fetched whole, then read from memory with the extension of
// the URL's path as Assimp's format hint.
const aiScene* readRemoteMesh(Assimp::Importer& importer, const std::string& path, unsigned flags,
                              std::vector<std::uint8_t>& bytes) {
  bytes = readFileBytes(path);
  const std::string name = path.substr(0, path.find_first_of("?#"));
  std::string hint = std::filesystem::path(name).extension().string();
  if (!hint.empty()) hint.erase(0, 1);
  std::string head(bytes.begin(), bytes.begin() + std::ptrdiff_t(std::min<std::size_t>(bytes.size(), 200)));
  for (char& c : head) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (hint == "ply" || head.rfind("ply", 0) == 0) validatePly(bytes.data(), bytes.size(), path);
  return importer.ReadFileFromMemory(bytes.data(), bytes.size(), flags, hint.c_str());
}

const aiScene* readLocalMesh(Assimp::Importer& importer, const std::string& path, unsigned flags) {
  requireRegularFile(path, "mesh");
  // Assimp 5.2's PLY loader loops forever on some malformed headers and leaks on others (found by
  // fuzz_mesh, docs/testing.md): what Assimp would read as PLY is first read by histoview's own PLY parser
  // (io/native/ply_points.h, fuzzed on its own), which reads every element and refuses a bad
  // header, a malformed face list or truncated data with a message naming the element, before
  // Assimp sees it (Debian's Assimp aborts on an ai_assert in its triangulation otherwise).
  if (readAsPly(path)) {
    const std::vector<std::uint8_t> bytes = readFileBytes(path);
    validatePly(bytes.data(), bytes.size(), path);
  }
  return importer.ReadFile(path, flags);
}

}  // namespace

Mesh readMesh(const std::string& path) {
  // Validate first (a face index past the vertices would otherwise be followed by the steps after
  // it: a crash in JoinIdenticalVertices, or a read past the array), then triangulate polygons,
  // merge duplicate vertices, drop points and lines; keep the file's frame (no
  // aiProcess_PreTransformVertices: node transforms are applied below, in double).
  constexpr unsigned kFlags =
      aiProcess_ValidateDataStructure | aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType;
  Assimp::Importer importer;
  std::vector<std::uint8_t> remoteBytes;
  const aiScene* scene = isRemoteSource(path) ? readRemoteMesh(importer, path, kFlags, remoteBytes)
                                              : readLocalMesh(importer, path, kFlags);
  if (!scene || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode)
    throw InputError(path + ": cannot read mesh (expected PLY, OBJ, glTF or another format Assimp reads): " +
                     importer.GetErrorString());
  Mesh out;
  // Walk the node hierarchy so that node transforms place each mesh.
  struct Item {
    const aiNode* node;
    aiMatrix4x4 transform;
  };
  std::vector<Item> stack = {{scene->mRootNode, scene->mRootNode->mTransformation}};
  while (!stack.empty()) {
    const Item item = stack.back();
    stack.pop_back();
    for (unsigned m = 0; m < item.node->mNumMeshes; ++m) {
      // Checked again here, whatever Assimp's validation lets through: every index this walk follows.
      if (item.node->mMeshes[m] >= scene->mNumMeshes || !scene->mMeshes[item.node->mMeshes[m]])
        throw InputError(path + ": mesh: node '" + std::string(item.node->mName.C_Str()) + "' names mesh " +
                         std::to_string(item.node->mMeshes[m]) + " of " + std::to_string(scene->mNumMeshes));
      const aiMesh* mesh = scene->mMeshes[item.node->mMeshes[m]];
      if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
      const auto base = std::uint32_t(out.positions.size());
      for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
        const aiVector3D p = item.transform * mesh->mVertices[v];
        out.positions.emplace_back(p.x, p.y, p.z);
      }
      for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
        const aiFace& face = mesh->mFaces[f];
        if (face.mNumIndices != 3) continue;
        for (unsigned k = 0; k < 3; ++k)
          if (face.mIndices[k] >= mesh->mNumVertices)
            throw InputError(path + ": mesh: face " + std::to_string(f) + ": vertex index " +
                             std::to_string(face.mIndices[k]) + " out of range (expected below " +
                             std::to_string(mesh->mNumVertices) + ")");
        out.triangles.emplace_back(base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]);
      }
    }
    for (unsigned c = 0; c < item.node->mNumChildren; ++c)
      stack.push_back({item.node->mChildren[c], item.transform * item.node->mChildren[c]->mTransformation});
  }
  if (out.triangles.empty()) throw InputError(path + ": mesh: no triangle in the file");
  return out;
}

}  // namespace hv
