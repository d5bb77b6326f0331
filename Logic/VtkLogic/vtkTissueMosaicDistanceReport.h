#pragma once
/// @file vtkTissueMosaicDistanceReport.h
/// @brief The accuracy report's files: per-point distances as CSV and as point arrays of the registered model (the
/// distance map, which Slicer colours by), and the error histogram as a PNG bar plot (drawn with OpenCV: VTK's
/// charts need a display).
#include "vtkTissueMosaicSurfaceDistance.h"

#include <Eigen/Core>

#include <string>
#include <vector>

class vtkPolyData;

namespace tissuemosaic {

/// Names of the point arrays addDistanceArrays adds.
constexpr const char* kDistanceArrayName = "DistanceMm";
constexpr const char* kSignedDistanceArrayName = "SignedDistanceMm";

/// CSV "index,x_mm,y_mm,z_mm,distance_mm,signed_distance_mm", one row per point (LPS, registered positions).
void writeDistanceCsv(const std::string& path, const std::vector<Eigen::Vector3d>& pointsLps,
                      const std::vector<double>& distancesMm, const std::vector<double>& signedDistancesMm);

/// Adds the distances as float point arrays ("DistanceMm" becomes the active scalars).
void addDistanceArrays(vtkPolyData* polyData, const std::vector<double>& distancesMm,
                       const std::vector<double>& signedDistancesMm);

/// A bar plot of the histogram (x: distance in mm, y: share of points in %) with the statistics in the title.
void writeHistogramPng(const std::string& path, const DistanceHistogram& histogram,
                       const DistanceStatistics& statistics);

}  // namespace tissuemosaic
