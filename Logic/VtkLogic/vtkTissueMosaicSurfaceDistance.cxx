#include "vtkTissueMosaicSurfaceDistance.h"

#include "Core/Error.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkGenericCell.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkStaticCellLocator.h>
#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkTriangle.h>
#include <vtkTriangleFilter.h>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace tissuemosaic {
namespace {

/// The triangles of `triangles` with a non-zero area (same points).
vtkSmartPointer<vtkPolyData> withoutDegenerateTriangles(vtkPolyData* triangles) {
  vtkNew<vtkCellArray> kept;
  vtkNew<vtkIdList> ids;
  vtkCellArray* polys = triangles->GetPolys();
  polys->InitTraversal();
  while (polys->GetNextCell(ids)) {
    if (ids->GetNumberOfIds() != 3) continue;
    double a[3], b[3], c[3];
    triangles->GetPoint(ids->GetId(0), a);
    triangles->GetPoint(ids->GetId(1), b);
    triangles->GetPoint(ids->GetId(2), c);
    if (vtkTriangle::TriangleArea(a, b, c) > 0) kept->InsertNextCell(ids);
  }
  auto output = vtkSmartPointer<vtkPolyData>::New();
  output->SetPoints(triangles->GetPoints());
  output->SetPolys(kept);
  return output;
}

/// The barycentric weights of `point` (on the triangle's plane) in triangle `cell`, and its vertex ids; false for a
/// triangle that is not one.
bool barycentricWeights(vtkPolyData* triangles, vtkIdType cell, const Eigen::Vector3d& point, const vtkIdType*& ids,
                        double weight[3]) {
  vtkIdType count = 0;
  triangles->GetCellPoints(cell, count, ids);
  if (count != 3) return false;
  Eigen::Vector3d v[3];
  for (int k = 0; k < 3; ++k) triangles->GetPoint(ids[k], v[k].data());
  const Eigen::Vector3d e0 = v[1] - v[0], e1 = v[2] - v[0], p = point - v[0];
  const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1), d20 = p.dot(e0), d21 = p.dot(e1);
  const double denominator = d00 * d11 - d01 * d01;
  if (!(denominator > 0)) return false;
  const double w1 = (d11 * d20 - d01 * d21) / denominator, w2 = (d00 * d21 - d01 * d20) / denominator;
  weight[0] = 1 - w1 - w2;
  weight[1] = w1;
  weight[2] = w2;
  return true;
}

}  // namespace

TargetSurface::TargetSurface(vtkPolyData* surfaceLps) {
  require(surfaceLps != nullptr && surfaceLps->GetNumberOfPoints() > 0, "the target surface is empty");
  require(surfaceLps->GetNumberOfPolys() + surfaceLps->GetNumberOfStrips() > 0,
          "the target model has no polygons: it must be a surface mesh (e.g. a segmentation exported as STL), not a "
          "point cloud");
  for (vtkIdType i = 0; i < surfaceLps->GetNumberOfPoints(); ++i) {
    double p[3];
    surfaceLps->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      throw Error("the target surface's vertex " + std::to_string(i) + " has a NaN or infinite coordinate");
    }
  }
  vtkNew<vtkTriangleFilter> triangulate;
  triangulate->SetInputData(surfaceLps);
  triangulate->PassVertsOff();
  triangulate->PassLinesOff();
  triangulate->Update();
  // Zero-area triangles carry no surface, and vtkPolyDataNormals' consistency pass loops on a mesh made of them.
  const vtkSmartPointer<vtkPolyData> nonDegenerate = withoutDegenerateTriangles(triangulate->GetOutput());
  require(nonDegenerate->GetNumberOfPolys() > 0,
          "the target model has no non-degenerate triangles: all " +
              std::to_string(triangulate->GetOutput()->GetNumberOfPolys()) +
              " have zero area (repeated or collinear vertices)");
  // Face normals only: point normals would be unused, splitting would duplicate points.
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(nonDegenerate);
  normals->ComputeCellNormalsOn();
  normals->ComputePointNormalsOff();
  normals->SplittingOff();
  normals->ConsistencyOn();
  normals->AutoOrientNormalsOff();
  normals->Update();
  triangles_ = normals->GetOutput();
  require(triangles_->GetNumberOfCells() > 0, "the target model has no non-degenerate triangles");
  normals_ = triangles_->GetCellData()->GetNormals();
  require(normals_ != nullptr, "could not compute the target surface's normals");
  // The surface's edges: edges that only one triangle has (its outline, and the rims of its holes).
  const vtkIdType cells = triangles_->GetNumberOfCells();
  std::unordered_map<uint64_t, int> trianglesPerEdge;
  const auto edgeKey = [](vtkIdType a, vtkIdType b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint64_t>(std::max(a, b));
  };
  vtkNew<vtkIdList> ids;
  for (vtkIdType c = 0; c < cells; ++c) {
    triangles_->GetCellPoints(c, ids);
    for (int k = 0; k < 3; ++k) ++trianglesPerEdge[edgeKey(ids->GetId(k), ids->GetId((k + 1) % 3))];
  }
  edgeOfSurface_.assign(static_cast<std::size_t>(cells), 0);
  vertexOnEdge_.assign(static_cast<std::size_t>(triangles_->GetNumberOfPoints()), 0);
  for (vtkIdType c = 0; c < cells; ++c) {
    triangles_->GetCellPoints(c, ids);
    for (int k = 0; k < 3; ++k) {
      const vtkIdType a = ids->GetId(k), b = ids->GetId((k + 1) % 3);
      if (trianglesPerEdge[edgeKey(a, b)] != 1) continue;
      edgeOfSurface_[static_cast<std::size_t>(c)] |= static_cast<uint8_t>(1 << k);
      vertexOnEdge_[static_cast<std::size_t>(a)] = vertexOnEdge_[static_cast<std::size_t>(b)] = 1;
    }
  }
  triangles_->BuildLinks();  // the triangles around a point or an edge (lowestTriangleHolding)
  neighbours_ = vtkSmartPointer<vtkIdList>::New();
  locator_ = vtkSmartPointer<vtkStaticCellLocator>::New();
  locator_->SetDataSet(triangles_);
  locator_->BuildLocator();
  scratch_ = vtkSmartPointer<vtkGenericCell>::New();
}

TargetSurface::~TargetSurface() = default;

vtkPolyData* TargetSurface::triangles() const { return triangles_; }

TargetSurface::Closest TargetSurface::closest(const Eigen::Vector3d& queryLps) const {
  Closest result;
  vtkIdType cellId = -1;
  int subId = 0;
  double distance2 = 0;
  locator_->FindClosestPoint(queryLps.data(), result.pointLps.data(), scratch_, cellId, subId, distance2);
  if (cellId >= 0) cellId = lowestTriangleHolding(cellId, result.pointLps);
  double normal[3] = {0, 0, 1};
  if (cellId >= 0) normals_->GetTuple(cellId, normal);
  result.normal = Eigen::Vector3d(normal[0], normal[1], normal[2]).normalized();
  result.distanceMm = std::sqrt(distance2);
  result.signedDistanceMm = result.normal.dot(queryLps - result.pointLps) < 0 ? -result.distanceMm : result.distanceMm;
  result.cellId = cellId;
  return result;
}

vtkIdType TargetSurface::lowestTriangleHolding(vtkIdType cell, const Eigen::Vector3d& pointLps) const {
  const vtkIdType* ids = nullptr;
  double weight[3];
  if (!barycentricWeights(triangles_, cell, pointLps, ids, weight)) return cell;
  constexpr double kOnBoundary = 1e-9;
  int zeros = 0, inside = -1;
  for (int k = 0; k < 3; ++k) {
    if (std::abs(weight[k]) <= kOnBoundary) ++zeros;
    else inside = k;
  }
  if (zeros == 0) return cell;  // inside the triangle: no other holds the point
  if (zeros == 2) {
    triangles_->GetPointCells(ids[inside], neighbours_);  // at vertex `inside`
  } else {
    int a = -1, b = -1;  // the edge: the two vertices with non-zero weights
    for (int k = 0; k < 3; ++k) {
      if (std::abs(weight[k]) > kOnBoundary) (a < 0 ? a : b) = k;
    }
    triangles_->GetCellEdgeNeighbors(cell, ids[a], ids[b], neighbours_);
  }
  vtkIdType lowest = cell;
  for (vtkIdType i = 0; i < neighbours_->GetNumberOfIds(); ++i) lowest = std::min(lowest, neighbours_->GetId(i));
  return lowest;
}

bool TargetSurface::onSurfaceEdge(const Closest& closest) const {
  const vtkIdType* ids = nullptr;
  double weight[3];
  if (closest.cellId < 0 || !barycentricWeights(triangles_, closest.cellId, closest.pointLps, ids, weight)) return false;
  const auto onEdge = [&](vtkIdType point) { return vertexOnEdge_[static_cast<std::size_t>(point)] != 0; };
  if (!(onEdge(ids[0]) || onEdge(ids[1]) || onEdge(ids[2]))) return false;
  // Where on its triangle the closest point lies: on edge k when the barycentric weight of the vertex opposite it is
  // zero (to rounding), on vertex k when its own weight is one.
  constexpr double kTolerance = 1e-6;
  const uint8_t edges = edgeOfSurface_[static_cast<std::size_t>(closest.cellId)];
  for (int k = 0; k < 3; ++k) {
    // Edge k runs from vertex k to k + 1: the weight of vertex k + 2 is zero on it.
    const bool onEdgeK = std::abs(weight[(k + 2) % 3]) <= kTolerance;
    const bool atVertexK = std::abs(weight[k] - 1) <= kTolerance;
    if ((onEdgeK && (edges >> k & 1)) || (atVertexK && onEdge(ids[k]))) return true;
  }
  return false;
}

std::vector<double> distancesToSurface(const TargetSurface& surface, const std::vector<Eigen::Vector3d>& pointsLps,
                                       std::vector<double>* signedDistancesMm) {
  std::vector<double> distances(pointsLps.size());
  if (signedDistancesMm) signedDistancesMm->resize(pointsLps.size());
  for (std::size_t i = 0; i < pointsLps.size(); ++i) {
    const auto closest = surface.closest(pointsLps[i]);
    distances[i] = closest.distanceMm;
    if (signedDistancesMm) (*signedDistancesMm)[i] = closest.signedDistanceMm;
  }
  return distances;
}

double percentile(std::vector<double> values, double q) {
  require(!values.empty(), "percentile of an empty list");
  require(q >= 0 && q <= 100, "percentile must be within 0..100");
  const double position = q / 100.0 * static_cast<double>(values.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(position));
  const auto above = std::min(below + 1, values.size() - 1);
  std::nth_element(values.begin(), values.begin() + static_cast<long>(below), values.end());
  const double low = values[below];
  const double high = above == below ? low : *std::min_element(values.begin() + static_cast<long>(below) + 1, values.end());
  return low + (position - static_cast<double>(below)) * (high - low);
}

DistanceStatistics distanceStatistics(const std::vector<double>& distancesMm) {
  require(!distancesMm.empty(), "no distances to evaluate: the model has no points");
  DistanceStatistics statistics;
  statistics.count = distancesMm.size();
  double sum = 0, sumSquares = 0;
  std::size_t within1mm = 0;
  for (double d : distancesMm) {
    require(std::isfinite(d), "a distance is not finite");
    sum += d;
    sumSquares += d * d;
    statistics.maxMm = std::max(statistics.maxMm, d);
    within1mm += d <= 1.0;
  }
  const auto n = static_cast<double>(distancesMm.size());
  statistics.shareWithin1mm = within1mm / n;
  statistics.meanMm = sum / n;
  statistics.rmseMm = std::sqrt(sumSquares / n);
  statistics.medianMm = percentile(distancesMm, 50);
  statistics.p95Mm = percentile(distancesMm, 95);
  return statistics;
}

DistanceHistogram distanceHistogram(const std::vector<double>& distancesMm, double binWidthMm, int maxBins) {
  require(binWidthMm > 0 && std::isfinite(binWidthMm), "the histogram bin width must be a positive number of mm");
  require(maxBins >= 1, "the histogram needs at least one bin");
  DistanceHistogram histogram;
  histogram.binWidthMm = binWidthMm;
  double largest = 0;
  for (double d : distancesMm) largest = std::max(largest, d);
  // In double first: a tiny bin width (1e-300 mm) gives a count no integer holds.
  const double needed = std::floor(largest / binWidthMm) + 1;
  histogram.counts.assign(static_cast<std::size_t>(std::min(needed, static_cast<double>(maxBins))), 0);
  for (double d : distancesMm) {
    const auto bin = static_cast<std::size_t>(std::floor(std::max(d, 0.0) / binWidthMm));
    if (bin < histogram.counts.size()) {
      ++histogram.counts[bin];
    } else {
      ++histogram.overflow;
    }
  }
  return histogram;
}

}  // namespace tissuemosaic
