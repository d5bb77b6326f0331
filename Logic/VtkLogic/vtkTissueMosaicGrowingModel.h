#pragma once
/// @file vtkTissueMosaicGrowingModel.h
/// @brief Keeps a vtkPolyData equal to the engine's growing point model without rebuilding it at every update:
/// the arrays grow in place (amortised doubling), new points are appended with one vertex cell each, and only
/// the cells of new points are written. Same layout as pointCloudToPolyData (vtkTissueMosaicPointCloud.h):
/// points (float, mm), vertex cells, "RGB" colour scalars (when the cloud has colours), "Normals" (when it has
/// normals).
// Complete types: ModelArrays' smart pointers are moved and released wherever it is used.
#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkUnsignedCharArray.h>

#include <cstddef>

class vtkPolyData;

namespace tissuemosaic {

struct ColoredPointCloud;

/// What an update did.
struct GrowingModelUpdate {
  std::size_t keptPoints = 0;     ///< points that were there before (their values are refreshed)
  std::size_t appendedPoints = 0; ///< new points at the end
  std::size_t removedPoints = 0;  ///< the model got smaller (e.g. after a reset): points dropped from the end
};

/// Makes polyData hold `model` (the whole current model, in its own order). The fusion may move, recolour or
/// re-weight earlier points, so their values are copied again (one memcpy per array); the vertex cells of points
/// that were there before are left as they are. An empty model empties polyData.
GrowingModelUpdate updateGrowingModel(vtkPolyData* polyData, const ColoredPointCloud& model);

/// The arrays of a model polydata (the layout above), made on one thread and handed to another. Double
/// buffering for a live view: the engine's worker fills new arrays for each new model, and the owner swaps them in
/// without copying the model or touching its memory (filling 1.4 M points, about 60 MB, had cost the GUI thread
/// 0.8-1.2 s of page faults on a 2-core virtual machine), then hands the old ones back for release elsewhere.
struct ModelArrays {
  vtkSmartPointer<vtkPoints> points;
  vtkSmartPointer<vtkCellArray> vertices;
  vtkSmartPointer<vtkUnsignedCharArray> colours;  ///< null when the model has none
  vtkSmartPointer<vtkFloatArray> normals;         ///< null when the model has none
};

/// New arrays holding `model` (safe on any thread: touches no shared object).
ModelArrays makeModelArrays(const ColoredPointCloud& model);
/// Puts `arrays` into polyData in constant time (owner thread) and returns the arrays it held before.
ModelArrays swapModelArrays(vtkPolyData* polyData, ModelArrays arrays);

}  // namespace tissuemosaic
