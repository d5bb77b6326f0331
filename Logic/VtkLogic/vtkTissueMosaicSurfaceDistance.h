#pragma once
/// @file vtkTissueMosaicSurfaceDistance.h
/// @brief Distances from points to a triangulated target surface (the CT/MR model), and the statistics and
/// histogram of the paper's accuracy evaluation. All in LPS millimetres.
#include <Eigen/Core>
#include <vtkSmartPointer.h>

#include <cstddef>
#include <cstdint>
#include <vector>

class vtkGenericCell;
class vtkIdList;
class vtkPolyData;
class vtkStaticCellLocator;
class vtkDataArray;

namespace tissuemosaic {

/// A target surface prepared for closest-point queries: triangulated, with consistently oriented face normals
/// (vtkPolyDataNormals) and a vtkStaticCellLocator. Queries are not thread-safe (one scratch cell).
class TargetSurface {
public:
  /// Throws Error when the model has no polygons (a point cloud is not a surface).
  explicit TargetSurface(vtkPolyData* surfaceLps);
  ~TargetSurface();
  TargetSurface(const TargetSurface&) = delete;
  TargetSurface& operator=(const TargetSurface&) = delete;

  struct Closest {
    Eigen::Vector3d pointLps;       ///< the closest point on the surface
    Eigen::Vector3d normal;         ///< unit normal of the triangle holding it
    double distanceMm = 0;          ///< |query - pointLps|
    double signedDistanceMm = 0;    ///< distanceMm, negative when the query lies behind the triangle's normal
    vtkIdType cellId = -1;          ///< the triangle holding it
  };
  Closest closest(const Eigen::Vector3d& queryLps) const;
  /// Whether closest.pointLps lies on the surface's edge (an edge of one triangle only, or a vertex on one): the query
  /// is beyond the surface's outline or over a hole in it, where its distance measures the gap, not its error. Kept
  /// out of closest(), which ICP calls for every point at every step.
  bool onSurfaceEdge(const Closest& closest) const;

  vtkPolyData* triangles() const;

private:
  /// A closest point on an edge or at a vertex lies on every triangle that shares it, all at the same distance, and
  /// the locator (its bins filled in parallel) returns any of them from one build to the next: the lowest id holding
  /// the point is taken, so that the normal, and ICP's result, are the same on every run.
  vtkIdType lowestTriangleHolding(vtkIdType cell, const Eigen::Vector3d& pointLps) const;

  vtkSmartPointer<vtkPolyData> triangles_;
  vtkSmartPointer<vtkStaticCellLocator> locator_;
  vtkSmartPointer<vtkGenericCell> scratch_;
  vtkSmartPointer<vtkIdList> neighbours_;
  vtkDataArray* normals_ = nullptr;
  std::vector<uint8_t> edgeOfSurface_;    ///< per triangle: bit k set when its edge k (vertex k to k+1) is on no other
  std::vector<uint8_t> vertexOnEdge_;     ///< per point: 1 when it ends such an edge
};

/// Unsigned distance of every point to the surface; the signed ones too when `signedDistancesMm` is given.
std::vector<double> distancesToSurface(const TargetSurface& surface, const std::vector<Eigen::Vector3d>& pointsLps,
                                       std::vector<double>* signedDistancesMm = nullptr);

struct DistanceStatistics {
  std::size_t count = 0;
  double rmseMm = 0;
  double meanMm = 0;
  double medianMm = 0;
  double p95Mm = 0;  ///< 95th percentile
  double maxMm = 0;
  /// Share of the distances at most 1 mm: against a reference of what must NOT be in a model (the instruments of a
  /// synthetic scan, groundtruth/instruments.ply), the share of the model that is such an artefact.
  double shareWithin1mm = 0;
};

/// The statistics of unsigned distances. Percentiles interpolate linearly between order statistics (as NumPy's
/// default). Throws Error for an empty list or a non-finite value.
DistanceStatistics distanceStatistics(const std::vector<double>& distancesMm);

/// The q-th percentile (0..100) of values, linear interpolation between order statistics.
double percentile(std::vector<double> values, double q);

/// Bins [i * binWidthMm, (i + 1) * binWidthMm) from 0; values beyond maxBins bins are counted in `overflow`.
struct DistanceHistogram {
  double binWidthMm = 0;
  std::vector<std::size_t> counts;
  std::size_t overflow = 0;
};

/// binWidthMm > 0; the bins cover 0 .. the largest distance, at most maxBins of them.
DistanceHistogram distanceHistogram(const std::vector<double>& distancesMm, double binWidthMm, int maxBins = 100);

}  // namespace tissuemosaic
