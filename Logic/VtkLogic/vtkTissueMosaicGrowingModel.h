#pragma once
/// @file vtkTissueMosaicGrowingModel.h
/// @brief Keeps a vtkPolyData equal to the engine's growing point model without rebuilding it at every update:
/// the arrays grow in place (amortised doubling), new points are appended with one vertex cell each, and only
/// the cells of new points are written. Same layout as pointCloudToPolyData (vtkTissueMosaicPointCloud.h):
/// points (float, mm), vertex cells, "RGB" colour scalars (when the cloud has colours), "Normals" (when it has
/// normals).
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

}  // namespace tissuemosaic
