// Triangle mesh PLY files (IO/MeshPly.h): round trip, and corrupt headers refused with an Error before anything is
// allocated (found by fuzz_mesh_ply; the inputs are kept in Testing/Fuzz/corpus/fuzz_mesh_ply).
#include "Core/Error.h"
#include "ErrorText.h"
#include "IO/MeshPly.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
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

// Through the shared PLY layer (IO/PlyFormat.h): other elements and properties are read past, and ascii and
// big-endian files read as the little-endian ones do.
TEST(MeshPly, ReadsPastOtherElementsAndPropertiesInEveryFormat) {
  const std::string path = outputPath("extras.ply");
  writeBytes(path,
             "ply\nformat ascii 1.0\nelement material 1\nproperty list uchar float values\n"
             "element vertex 3\nproperty double x\nproperty uchar flag\nproperty double y\nproperty double z\n"
             "element face 2\nproperty int group\nproperty list uchar int vertex_indices\nend_header\n"
             "2 0.5 0.25\n0 7 0 50\n1 7 0 50.5\n0 7 1 51\n4 3 0 1 2\n5 3 2 1 0\n");
  TriangleMesh mesh = readMeshPly(path);
  ASSERT_EQ(mesh.verticesMm.size(), 3u);
  EXPECT_EQ(mesh.verticesMm[1], cv::Point3f(1, 0, 50.5f));
  ASSERT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangles[1], cv::Vec3i(2, 1, 0));

  std::string big = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                    "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
  const auto appendBig = [&](auto value) {
    char raw[sizeof(value)];
    std::memcpy(raw, &value, sizeof(value));
    std::reverse(raw, raw + sizeof(value));
    big.append(raw, sizeof(value));
  };
  for (float v : {0.f, 0.f, 50.f, 1.f, 0.f, 50.5f, 0.f, 1.f, 51.f}) appendBig(v);
  big.push_back(3);
  for (int v : {0, 1, 2}) appendBig(v);
  writeBytes(path, big);
  mesh = readMeshPly(path);
  ASSERT_EQ(mesh.verticesMm.size(), 3u);
  EXPECT_EQ(mesh.verticesMm[2], cv::Point3f(0, 1, 51));
  ASSERT_EQ(mesh.triangles.size(), 1u);
  EXPECT_EQ(mesh.triangles[0], cv::Vec3i(0, 1, 2));
  writeBytes(path, big.substr(0, big.size() - 2));
  EXPECT_NE(errorOf([&] { readMeshPly(path); }).find("truncated"), std::string::npos);
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
