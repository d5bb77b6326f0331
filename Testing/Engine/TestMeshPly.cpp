// Triangle mesh PLY files (IO/MeshPly.h): round trip, and corrupt headers refused with an Error before anything is
// allocated (found by fuzz_mesh_ply; the inputs are kept in Testing/Fuzz/corpus/fuzz_mesh_ply).
#include "Core/Error.h"
#include "ErrorText.h"
#include "IO/MeshPly.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace tissuemosaic {
namespace {

std::string outputPath(const std::string& name) {
  const std::string folder = std::string(TM_TEST_OUTPUT_DIR) + "/MeshPly";
  std::filesystem::create_directories(folder);
  return folder + "/" + name;
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream file(path, std::ios::binary);
  file.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

TEST(MeshPly, RoundTrip) {
  TriangleMesh mesh;
  mesh.verticesMm = {{0, 0, 50}, {1, 0, 50.5f}, {0, 1, 51}, {1, 1, 49.5f}};
  mesh.triangles = {{0, 1, 2}, {1, 3, 2}};
  const std::string path = outputPath("square.ply");
  writeMeshPly(path, mesh, "frame: world, millimetres");
  const TriangleMesh read = readMeshPly(path);
  ASSERT_EQ(read.verticesMm.size(), 4u);
  ASSERT_EQ(read.triangles.size(), 2u);
  for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(read.verticesMm[i], mesh.verticesMm[i]);
  EXPECT_EQ(read.triangles[1], mesh.triangles[1]);
}

TEST(MeshPly, CorruptCountsAreErrorsNotAllocations) {
  const std::string header = "ply\nformat ascii 1.0\n";
  const std::string xyz = "property float x\nproperty float y\nproperty float z\n";
  const std::string path = outputPath("corrupt.ply");
  // A negative count made std::vector::resize throw std::length_error (not an Error: the fuzz target's crash).
  writeBytes(path, header + "element vertex -1\n" + xyz + "end_header\n");
  EXPECT_NE(errorOf([&] { readMeshPly(path); }).find("malformed line 'element vertex -1'"), std::string::npos);
  // A huge face count reserved 4e15 triangles (allocation-size-too-big under ASan, std::bad_alloc without).
  writeBytes(path, header + "element vertex 0\n" + xyz +
                       "element face 4000000000000000\nproperty list uchar int vertex_indices\nend_header\n3 0 0 0\n");
  EXPECT_NE(errorOf([&] { readMeshPly(path); })
                .find("declares 0 vertices and 4000000000000000 faces but only 8 bytes follow it"),
            std::string::npos);
  writeBytes(path, header + "element vertex 99999999999\n" + xyz + "end_header\n1 2 3\n");
  EXPECT_NE(errorOf([&] { readMeshPly(path); }).find("99999999999 vertices"), std::string::npos);
  writeBytes(path, header + "element vertex\n" + xyz + "end_header\n");
  EXPECT_NE(errorOf([&] { readMeshPly(path); }).find("malformed line"), std::string::npos);
}

}  // namespace
}  // namespace tissuemosaic
