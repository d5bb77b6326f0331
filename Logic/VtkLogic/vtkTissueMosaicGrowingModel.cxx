#include "vtkTissueMosaicGrowingModel.h"

#include "vtkTissueMosaicPointCloud.h"

#include "Core/StereoRig.h"

#include <vtkCellArray.h>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cstring>
#include <numeric>

namespace tissuemosaic {

namespace {

/// Sets the array's count to `values` without giving memory back, and returns its data. VTK's SetNumberOfValues
/// squeezes the buffer (a realloc to the exact size) whenever the count falls within the capacity, so the next
/// growth reallocates again (and with an allocator that moves on every realloc, such as ASan's, every update moved
/// the whole model: ReconstructionGrowingModel.AppendsInPlaceAndRefreshesEarlierPoints). Reset keeps the memory;
/// WritePointer grows it to more than twice its capacity only when needed, by realloc, so the contents stay.
template <class Array>
typename Array::ValueType* setCountKeepingCapacity(Array* array, vtkIdType values) {
  array->Reset();
  return values > 0 ? array->WritePointer(0, values) : array->GetPointer(0);
}

/// Resizes (keeping the capacity) and copies n packed tuples in: a model growing by a key frame's points at a time
/// reallocates a few times per scan, never the whole model's pages again at every key frame on the GUI thread.
template <class Array>
void copyInto(Array* array, const void* data, vtkIdType n) {
  const vtkIdType values = n * array->GetNumberOfComponents();
  typename Array::ValueType* target = setCountKeepingCapacity(array, values);
  if (n > 0) std::memcpy(target, data, static_cast<std::size_t>(values) * sizeof(typename Array::ValueType));
}

vtkFloatArray* floatPoints(vtkPolyData* polyData) {
  vtkPoints* points = polyData->GetPoints();
  if (!points || points->GetDataType() != VTK_FLOAT) {
    vtkNew<vtkPoints> floatPoints;
    floatPoints->SetDataTypeToFloat();
    polyData->SetPoints(floatPoints);
    points = floatPoints;
  }
  return vtkFloatArray::SafeDownCast(points->GetData());
}

/// The vertex cells as 64-bit offsets and connectivity that can be extended in place.
vtkCellArray* vertexCells(vtkPolyData* polyData) {
  // Without vertex cells, GetVerts() returns VTK's shared empty dummy array: never resize that one.
  vtkCellArray* verts = polyData->GetNumberOfVerts() > 0 ? polyData->GetVerts() : nullptr;
  if (!verts || !verts->IsStorage64Bit() || verts->GetNumberOfCells() != polyData->GetNumberOfPoints()) {
    vtkNew<vtkCellArray> cells;
    cells->Use64BitStorage();
    polyData->SetVerts(cells);
    verts = cells;
  }
  return verts;
}

}  // namespace

GrowingModelUpdate updateGrowingModel(vtkPolyData* polyData, const ColoredPointCloud& model) {
  static_assert(sizeof(cv::Point3f) == 3 * sizeof(float) && sizeof(cv::Vec3b) == 3, "packed OpenCV vectors");
  const auto n = static_cast<vtkIdType>(model.pointsMm.size());
  vtkCellArray* verts = vertexCells(polyData);  // checked against the old point count, before the points change
  const vtkIdType before = verts->GetNumberOfCells();

  GrowingModelUpdate update;
  update.keptPoints = static_cast<std::size_t>(std::min(before, n));
  update.appendedPoints = static_cast<std::size_t>(std::max<vtkIdType>(n - before, 0));
  update.removedPoints = static_cast<std::size_t>(std::max<vtkIdType>(before - n, 0));

  vtkFloatArray* points = floatPoints(polyData);
  copyInto(points, model.pointsMm.data(), n);
  polyData->GetPoints()->Modified();

  // Vertex cell i is point i: offsets 0..n, connectivity 0..n-1. Only the new tail is written.
  auto* offsets = vtkTypeInt64Array::SafeDownCast(verts->GetOffsetsArray());
  auto* connectivity = vtkTypeInt64Array::SafeDownCast(verts->GetConnectivityArray());
  setCountKeepingCapacity(offsets, n + 1);
  setCountKeepingCapacity(connectivity, n);
  if (n > before) {
    std::iota(offsets->GetPointer(before), offsets->GetPointer(n + 1), vtkTypeInt64(before));
    std::iota(connectivity->GetPointer(before), connectivity->GetPointer(n), vtkTypeInt64(before));
  }
  offsets->SetValue(0, 0);
  verts->Modified();

  vtkPointData* pointData = polyData->GetPointData();
  if (model.colorsRgb.size() == model.pointsMm.size() && n > 0) {
    auto* colors = vtkUnsignedCharArray::SafeDownCast(pointData->GetArray(kPointCloudColorArrayName));
    if (!colors) {
      vtkNew<vtkUnsignedCharArray> newColors;
      newColors->SetName(kPointCloudColorArrayName);
      newColors->SetNumberOfComponents(3);
      pointData->SetScalars(newColors);
      colors = newColors;
    }
    copyInto(colors, model.colorsRgb.data(), n);
    colors->Modified();
  } else {
    pointData->RemoveArray(kPointCloudColorArrayName);
  }
  if (model.normals.size() == model.pointsMm.size() && n > 0) {
    auto* normals = vtkFloatArray::SafeDownCast(pointData->GetNormals());
    if (!normals) {
      vtkNew<vtkFloatArray> newNormals;
      newNormals->SetName("Normals");
      newNormals->SetNumberOfComponents(3);
      pointData->SetNormals(newNormals);
      normals = newNormals;
    }
    copyInto(normals, model.normals.data(), n);
    normals->Modified();
  } else {
    pointData->SetNormals(nullptr);
  }
  polyData->Modified();
  return update;
}

ModelArrays makeModelArrays(const ColoredPointCloud& model) {
  ModelArrays arrays;
  const auto n = static_cast<vtkIdType>(model.pointsMm.size());
  arrays.points = vtkSmartPointer<vtkPoints>::New();
  arrays.points->SetDataTypeToFloat();
  copyInto(vtkFloatArray::SafeDownCast(arrays.points->GetData()), model.pointsMm.data(), n);
  // Vertex cell i is point i: offsets 0..n, connectivity 0..n-1 (64-bit, so that updateGrowingModel can extend it).
  arrays.vertices = vtkSmartPointer<vtkCellArray>::New();
  arrays.vertices->Use64BitStorage();
  auto* offsets = vtkTypeInt64Array::SafeDownCast(arrays.vertices->GetOffsetsArray());
  auto* connectivity = vtkTypeInt64Array::SafeDownCast(arrays.vertices->GetConnectivityArray());
  offsets->SetNumberOfValues(n + 1);
  connectivity->SetNumberOfValues(n);
  std::iota(offsets->GetPointer(0), offsets->GetPointer(0) + n + 1, vtkTypeInt64(0));
  std::iota(connectivity->GetPointer(0), connectivity->GetPointer(0) + n, vtkTypeInt64(0));
  if (model.colorsRgb.size() == model.pointsMm.size() && n > 0) {
    arrays.colours = vtkSmartPointer<vtkUnsignedCharArray>::New();
    arrays.colours->SetName(kPointCloudColorArrayName);
    arrays.colours->SetNumberOfComponents(3);
    copyInto(arrays.colours.Get(), model.colorsRgb.data(), n);
  }
  if (model.normals.size() == model.pointsMm.size() && n > 0) {
    arrays.normals = vtkSmartPointer<vtkFloatArray>::New();
    arrays.normals->SetName("Normals");
    arrays.normals->SetNumberOfComponents(3);
    copyInto(arrays.normals.Get(), model.normals.data(), n);
  }
  return arrays;
}

ModelArrays swapModelArrays(vtkPolyData* polyData, ModelArrays arrays) {
  ModelArrays previous;
  vtkPointData* pointData = polyData->GetPointData();
  previous.points = polyData->GetPoints();
  previous.vertices = polyData->GetNumberOfVerts() > 0 ? polyData->GetVerts() : nullptr;
  previous.colours = vtkUnsignedCharArray::SafeDownCast(pointData->GetArray(kPointCloudColorArrayName));
  previous.normals = vtkFloatArray::SafeDownCast(pointData->GetNormals());
  polyData->SetPoints(arrays.points);
  polyData->SetVerts(arrays.vertices);
  if (arrays.colours) pointData->SetScalars(arrays.colours);
  else pointData->RemoveArray(kPointCloudColorArrayName);
  pointData->SetNormals(arrays.normals);
  polyData->Modified();
  return previous;
}

}  // namespace tissuemosaic
