#pragma once
/// @file PointCloudPly.h
/// @brief Coloured point clouds as PLY files: binary little-endian output with float x y z, uchar red green blue
/// and float nx ny nz; input from ascii or binary (either endianness) PLY with at least x y z per vertex.
#include "Core/StereoRig.h"

#include <string>

namespace tissuemosaic {

/// Writes a binary little-endian PLY: float x y z, then uchar red green blue when the cloud has colours, then
/// float nx ny nz when it has normals. Each line of `comment` becomes a PLY comment: say which frame and units the
/// points are in (e.g. "frame: left rectified camera, millimetres"). Throws Error when colours or normals are
/// neither empty nor one per point, or when the path cannot be written.
void writePly(const std::string& path, const ColoredPointCloud& cloud, const std::string& comment = {});

/// Reads the vertices of a PLY file (ascii, binary_little_endian or binary_big_endian): x y z (required, any
/// numeric type), red green blue (optional; uchar as is, other types: integers clamped to 0..255, floats in 0..1
/// scaled by 255) and nx ny nz (optional). Other vertex properties and other elements (faces, edges) are
/// skipped. Throws Error for a missing, malformed or truncated file.
ColoredPointCloud readPly(const std::string& path);
/// readPly that also reads (and skips) every element after the vertices, so that a file truncated or malformed
/// anywhere is an Error: a check to run before readers that are not so careful (VTK 9.1's PLY reader fills a
/// truncated file's missing vertices with zeros, or crashes). It also requires faces to have a list
/// 'vertex_indices' of existing vertices, and an ASCII file to hold each row on one line, as VTK reads them.
ColoredPointCloud readPlyWholeFile(const std::string& path);

}  // namespace tissuemosaic
