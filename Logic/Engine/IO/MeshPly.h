#pragma once
/// @file MeshPly.h
/// @brief Triangle meshes as PLY files: binary little-endian float x y z per vertex and a face list (uchar count,
/// int indices). For ground-truth surfaces and reconstructed models that carry connectivity; point clouds without
/// faces go through PointCloudPly.h.
#include <opencv2/core.hpp>

#include <string>
#include <vector>

namespace tissuemosaic {

struct TriangleMesh {
  std::vector<cv::Point3f> verticesMm;
  std::vector<cv::Vec3i> triangles;  ///< vertex indices, counter-clockwise seen from the side the normal points to
};

/// Writes a binary little-endian PLY with element vertex (float x y z) and element face (list uchar int
/// vertex_indices). Each line of comment becomes a PLY comment: say which frame and units the vertices are in.
/// Throws Error for an index outside the vertices or an unwritable path.
void writeMeshPly(const std::string& path, const TriangleMesh& mesh, const std::string& comment = {});

/// Reads a PLY (ascii, or binary of either byte order; PlyFormat.h) with x y z of any numeric type per vertex and
/// triangular faces (list 'vertex_indices' or 'vertex_index'); other properties and elements are read past. Throws
/// Error for a missing, malformed or truncated file, non-triangular faces, or indices outside the vertices.
TriangleMesh readMeshPly(const std::string& path);

}  // namespace tissuemosaic
