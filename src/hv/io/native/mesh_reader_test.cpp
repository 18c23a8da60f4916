#include "hv/io/native/mesh_reader.h"

#include "hv/util/diagnostics.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include <sys/stat.h>
#include <unistd.h>

namespace hv {
namespace {

std::string tempFile(const std::string& name, const std::string& content) {
  const auto p = std::filesystem::temp_directory_path() / ("hv-mesh-" + std::to_string(::getpid()) + "-" + name);
  std::ofstream(p) << content;
  return p.string();
}

TEST(MeshReader, ReadsAsciiPlyQuadsAsTriangles) {
  // A unit square as one quad plus a triangle above it: 3 triangles once triangulated.
  const std::string ply = tempFile("quad.ply", R"(ply
format ascii 1.0
element vertex 5
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
1 1 0
0 1 0
0.5 0.5 2
4 0 1 2 3
3 0 1 4
)");
  const Mesh m = readMesh(ply);
  EXPECT_EQ(m.triangles.size(), 3u);
  EXPECT_NEAR(m.area(), 1.0 + 0.5 * std::sqrt(2.0 * 2.0 + 0.5 * 0.5), 1e-6);  // square + triangle (base 1)
  EXPECT_NEAR(m.bounds().hi.z, 2.0, 1e-9);
}

TEST(MeshReader, BrokenFilesNameTheFile) {
  const std::string garbage = tempFile("garbage.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n");
  for (const std::string& p : {garbage, std::string("/nonexistent/mesh.ply")}) {
    try {
      readMesh(p);
      FAIL() << "read " << p;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
  }
}

TEST(MeshReader, FaceIndicesOutOfRangeAreRefusedNamingTheFile) {
  // 3 vertices: index 7 is far past them (a crash in Assimp's post-processing without validation);
  // index 3 equals the vertex count (a read one past the array).
  for (const std::string index : {"7", "3"}) {
    const std::string ply = tempFile("bad-index-" + index + ".ply", R"(ply
format ascii 1.0
element vertex 3
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
end_header
0 0 0
1 0 0
1 1 0
3 0 1 2
3 0 1 )" + index + "\n");
    try {
      readMesh(ply);
      FAIL() << "read a face with index " << index;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(ply), std::string::npos) << e.what();
    }
  }
}

TEST(MeshReader, AFifoIsRefusedWithoutBlocking) {
  const auto p = std::filesystem::temp_directory_path() / ("hv-mesh-" + std::to_string(::getpid()) + "-fifo.ply");
  std::filesystem::remove(p);
  ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
  try {
    readMesh(p.string());
    FAIL() << "read a FIFO";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("FIFO"), std::string::npos) << e.what();
  }
  std::filesystem::remove(p);
}

}  // namespace
}  // namespace hv
