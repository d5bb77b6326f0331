#pragma once
/// @file vtkTissueMosaicSurfaceModelFile.h
/// @brief Surface models (CT/MR segmentations, our reconstructed scans) read from and written to the files 3D
/// Slicer reads: STL, legacy VTK, VTP, PLY and OBJ. In memory, models are always in LPS millimetres.
///
/// Frames: Slicer 4.11+ writes models in LPS and marks the file ("SPACE=LPS" in the STL/VTK header, a PLY comment,
/// an OBJ comment, or a VTP field-data string array "SPACE"); a file without a mark is read as LPS by Slicer.
/// Our reconstructed models are in the camera/world frame (mm) with no anatomical meaning: their coordinates are
/// taken as they are, i.e. as LPS, which is what Slicer does when it loads them, so landmarks picked on them in
/// Slicer match. The caller may override the frame (ModelFrameChoice::LPS/RAS) to flip a file that is marked
/// wrongly or not at all.
#include "vtkTissueMosaicAnatomicalFrame.h"

#include <Eigen/Core>
#include <vtkSmartPointer.h>

#include <string>
#include <vector>

class vtkPolyData;

namespace tissuemosaic {

/// A model read from a file: its geometry in LPS, and which frame the file held it in.
struct SurfaceModelFile {
  vtkSmartPointer<vtkPolyData> polyDataLps;
  AnatomicalFrame fileFrame = AnatomicalFrame::LPS;
  bool frameDeclaredInFile = false;  ///< the file carried a SPACE mark (used when the choice was FromFile)
};

/// Reads .stl, .vtk (legacy poly data), .vtp, .ply or .obj (extension, any case). Throws Error when the file is
/// missing, unreadable, of another extension or has no points.
SurfaceModelFile readSurfaceModel(const std::string& path, ModelFrameChoice frame = ModelFrameChoice::FromFile);

/// Writes an LPS model as .vtp, .ply (binary), .stl (binary, polygons only) or .vtk, in `fileFrame`, with
/// Slicer's SPACE mark so Slicer places it without asking. Throws Error when writing fails.
void writeSurfaceModel(const std::string& path, vtkPolyData* polyDataLps,
                       AnatomicalFrame fileFrame = AnatomicalFrame::LPS);

/// A deep copy with every point mapped by the 4x4 transform (rigid or similarity) and its point/cell normals
/// rotated and renormalised.
vtkSmartPointer<vtkPolyData> transformedPolyData(vtkPolyData* polyData, const Eigen::Matrix4d& transform);

/// The points of a model, in its frame.
std::vector<Eigen::Vector3d> polyDataPoints(vtkPolyData* polyData);

/// The points with finite coordinates; those with a NaN or infinite one are left out and counted in *leftOut. A
/// model's NaN points (a disparity without estimate) must never count as points at some finite distance.
std::vector<Eigen::Vector3d> finitePoints(const std::vector<Eigen::Vector3d>& points, std::size_t* leftOut);

}  // namespace tissuemosaic
