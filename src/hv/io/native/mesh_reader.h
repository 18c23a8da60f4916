// Arbitrary triangle meshes (PLY, OBJ, glTF, ... : whatever Assimp reads) as scene geometry, e.g.
// a photogrammetric mesh of a façade. Assimp is only included in io/native/private/.
#pragma once

#include "hv/scene/mesh.h"

#include <string>

namespace hv {

// All meshes of the file, triangulated, in the file's coordinates (no unit or axis conversion:
// the scene's frame is the file's). Throws InputError naming the file when it cannot be read or
// holds no triangle.
Mesh readMesh(const std::string& path);

}  // namespace hv
