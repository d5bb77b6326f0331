#include "Deformation/DeformationTracker.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "Core/RigidTransform.h"
#include "Core/Stopwatch.h"
#include "Core/SurfaceKernels.h"
#include "Core/SurfaceMeasurement.h"
#include "Deformation/RigidPart.h"

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cmath>

namespace tissuemosaic {
namespace {

/// The frame's measurement turned into points by the rule measureSurface uses (surface::reprojectPixel), every
/// disparity kept.
struct FramePoints {
  const cv::Mat& disparityPx;
  surface::Reprojection reprojection;

  /// The camera-frame point of pixel (x, y); false outside the image or where it has no disparity.
  bool at(int x, int y, Eigen::Vector3d& point) const {
    const Float3 p = pointF(x, y);
    if (!isFinite(p)) return false;
    point = Eigen::Vector3d(p.x, p.y, p.z);
    return true;
  }
  /// The surface normal at pixel (x, y) from its neighbours `radius` pixels away (surface::normalFromNeighbours).
  bool normalAt(int x, int y, int radius, double maxJumpMm, Eigen::Vector3d& normal) const {
    Float3 n;
    if (!surface::normalFromNeighbours(pointF(x, y), pointF(x - radius, y), pointF(x + radius, y),
                                       pointF(x, y - radius), pointF(x, y + radius), static_cast<float>(maxJumpMm), n))
      return false;
    normal = Eigen::Vector3d(n.x, n.y, n.z);
    return true;
  }

private:
  Float3 pointF(int x, int y) const {
    if (x < 0 || y < 0 || x >= disparityPx.cols || y >= disparityPx.rows) return nanFloat3();
    return surface::reprojectPixel(reprojection, x, y, disparityPx.at<float>(y, x), -FLT_MAX, FLT_MAX);
  }
};

/// The pixel nearest the projection of a camera-frame point; false behind the camera or outside the image.
bool projectToPixel(const RectifiedGeometry& g, const Eigen::Vector3d& cameraPoint, int& x, int& y) {
  if (!(cameraPoint.z() > 1e-6)) return false;
  double u = 0, v = 0;
  g.leftIntrinsics().project(cameraPoint.x(), cameraPoint.y(), cameraPoint.z(), u, v);
  x = static_cast<int>(std::lround(u));
  y = static_cast<int>(std::lround(v));
  return x >= 0 && y >= 0 && x < g.imageSize.width && y < g.imageSize.height;
}

}  // namespace

void DeformationTrackerParameters::validate() const {
  graph.validate();
  fit.validate();
  const parameters::Group check{"deformation"};
  check.requireRange("sampleStridePx", sampleStridePx, 2, 256);
  check.requireRange("maxFitSamples", maxFitSamples, 16, 1000000);
  check.requireRange("associationRounds", associationRounds, 1, 20);
  check.requireRange("maxAssociationMm", maxAssociationMm, 0.1, 100.0);
  check.requireRange("agreementMm", agreementMm, 0.01, 100.0);
  check.requireRange("maxDepthJumpMm", maxDepthJumpMm, 0.01, 1000.0);
  check.requireRange("maxSampleWeight", maxSampleWeight, 1.0, 1e6);
  check.requireRange("rigidPartToleranceMm", rigidPartToleranceMm, 0.01, 100.0);
}

DeformationTracker::DeformationTracker(const RectifiedGeometry& geometry, const DeformationTrackerParameters& parameters)
    : geometry_(geometry), parameters_(parameters), graph_(parameters.graph) {
  parameters_.validate();
  require(geometry.focalPx > 0 && geometry.baselineMm > 0, "deformation: the geometry has no focal length or baseline");
}

DeformationTracker::Points DeformationTracker::livePoints() const {
  Points live;
  live.reserve(canonical_.size());
  for (const Eigen::Vector3d& p : canonical_) live.push_back(graph_.warp(p));
  return live;
}

Eigen::Matrix4d DeformationTracker::takeRigidPart(const DeformationCorrespondences& correspondences) {
  // The nodes this frame's depth reached, weighted by how much of it.
  std::vector<double> reach(static_cast<std::size_t>(graph_.nodeCount()), 0.0);
  for (const DeformationCorrespondence& c : correspondences) {
    if (!c.influence) continue;
    for (int n = 0; n < c.influence->count; ++n) reach[static_cast<std::size_t>(c.influence->node[n])] += c.influence->weight[n];
  }
  Points rest, live;
  std::vector<double> weights;
  auto& nodes = graph_.nodes();
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    if (!(reach[j] > 0)) continue;
    rest.push_back(nodes[j].positionMm);
    live.push_back(nodes[j].livePositionMm());
    weights.push_back(reach[j]);
  }
  const Eigen::Matrix4d rigid = robustRigidMotion(rest, live, weights, parameters_.rigidPartToleranceMm);
  const Eigen::Matrix4d back = inverseRigid(rigid);  // the rigid motion undone
  // live(p) = sum_j w_j (R_j (p - g_j) + g_j + t_j) is affine in each node's motion: undoing D on every reached node
  // moves the tissue they carry by D^-1 exactly.
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    if (!(reach[j] > 0)) continue;
    DeformationNode& node = nodes[j];
    const Eigen::Vector3d liveMm = back.topLeftCorner<3, 3>() * node.livePositionMm() + back.topRightCorner<3, 1>();
    node.translationMm = liveMm - node.positionMm;
    node.rotation = back.topLeftCorner<3, 3>() * node.rotation;
  }
  return back;
}

DeformationFrame DeformationTracker::update(const cv::Mat& disparityPx, const Eigen::Matrix4d& T_world_camera) {
  const auto start = std::chrono::steady_clock::now();
  require(disparityPx.type() == CV_32F && disparityPx.size() == geometry_.imageSize,
          "deformation: the disparity must be CV_32F of the geometry's size");
  DeformationFrame frame;
  Eigen::Matrix3d R_wc = T_world_camera.block<3, 3>(0, 0);
  Eigen::Vector3d t_wc = T_world_camera.block<3, 1>(0, 3);
  Eigen::Matrix3d R_cw = R_wc.transpose();
  Eigen::Vector3d t_cw = -R_cw * t_wc;
  const int stride = parameters_.sampleStridePx;
  const FramePoints framePoints{disparityPx, reprojectionOf(geometry_)};

  // The samples in view (their live position projects into the image), evenly thinned to maxFitSamples.
  std::vector<int> inView;
  influences_.update(graph_, canonical_);
  const InfluenceCache& influences = influences_;
  for (std::size_t i = 0; i < canonical_.size(); ++i) {
    int x = 0, y = 0;
    if (projectToPixel(geometry_, R_cw * graph_.warp(canonical_[i], influences[i]) + t_cw, x, y))
      inView.push_back(static_cast<int>(i));
  }
  std::vector<int> fitSamples;
  const double keepEvery = std::max(1.0, static_cast<double>(inView.size()) / parameters_.maxFitSamples);
  for (double k = 0; k < inView.size(); k += keepEvery) fitSamples.push_back(inView[static_cast<std::size_t>(k)]);

  // The frame's surface point on the ray through a sample's live position, and the sample's live normal.
  const auto measuredFor = [&](int i, bool warped, Eigen::Vector3d& point, Eigen::Vector3d& normal,
                               Eigen::Vector3d& measured) {
    const NodeInfluence influence = warped ? influences[static_cast<std::size_t>(i)] : NodeInfluence{};
    point = graph_.warp(canonical_[static_cast<std::size_t>(i)], influence);
    normal = graph_.warpNormal(normals_[static_cast<std::size_t>(i)], influence);
    int x = 0, y = 0;
    Eigen::Vector3d camera;
    if (!projectToPixel(geometry_, R_cw * point + t_cw, x, y) || !framePoints.at(x, y, camera)) return false;
    measured = R_wc * camera + t_wc;
    return true;
  };
  const auto shareWithin = [&](bool warped) {
    int measuredCount = 0, within = 0;
    for (const int i : fitSamples) {
      Eigen::Vector3d point, normal, measured;
      if (!measuredFor(i, warped, point, normal, measured)) continue;
      ++measuredCount;
      if (std::abs(normal.dot(point - measured)) <= parameters_.agreementMm) ++within;
    }
    return measuredCount > 0 ? static_cast<double>(within) / measuredCount : 0.0;
  };

  if (!fitSamples.empty()) {
    frame.rigidShareWithin1mm = shareWithin(false);
    DeformationCorrespondences correspondences;
    DeformationFitResult fit;
    for (int round = 0; round < parameters_.associationRounds; ++round) {
      correspondences.clear();
      for (const int i : fitSamples) {
        Eigen::Vector3d point, normal, measured;
        if (!measuredFor(i, true, point, normal, measured)) continue;
        if (!(std::abs(normal.dot(point - measured)) <= parameters_.maxAssociationMm)) continue;
        DeformationCorrespondence c;
        c.canonicalMm = canonical_[static_cast<std::size_t>(i)];
        c.targetMm = measured;
        c.targetNormal = normal;
        c.influence = influences[static_cast<std::size_t>(i)];
        correspondences.push_back(c);
      }
      if (correspondences.empty()) break;
      fit = fitDeformation(graph_, correspondences, parameters_.fit);
    }
    if (!correspondences.empty()) {
      // Fusion through the inverse warp: each associated sample moves along its rest normal toward its measurement
      // (a running average), so the canonical surface averages the frames' noise away.
      for (const int i : fitSamples) {
        Eigen::Vector3d point, normal, measured;
        if (!measuredFor(i, true, point, normal, measured)) continue;
        const double offsetMm = normal.dot(measured - point);
        if (!(std::abs(offsetMm) <= parameters_.agreementMm)) continue;
        float& weight = weights_[static_cast<std::size_t>(i)];
        canonical_[static_cast<std::size_t>(i)] += (offsetMm / (weight + 1.0)) * normals_[static_cast<std::size_t>(i)];
        weight = std::min(weight + 1.0f, static_cast<float>(parameters_.maxSampleWeight));
      }
      frame.fitted = true;
      frame.correspondences = static_cast<int>(correspondences.size());
      frame.liveShareWithin1mm = shareWithin(true);
      frame.meanNodeMotionMm = fit.meanNodeMotionMm;
      frame.maxNodeMotionMm = fit.maxNodeMotionMm;
      frame.dataRmsMm = fit.dataRmsMm;
      if (parameters_.cameraTakesRigidPart) {
        frame.cameraCorrection = takeRigidPart(correspondences);
        // The rest of the frame (its new samples) at the corrected pose.
        const Eigen::Matrix4d corrected = frame.cameraCorrection * T_world_camera;
        R_wc = corrected.block<3, 3>(0, 0);
        t_wc = corrected.block<3, 1>(0, 3);
        R_cw = R_wc.transpose();
        t_cw = -R_cw * t_wc;
      }
    }
  }

  // New samples where no sample's live position lands within a stride, stored where the field says they rest.
  const int cellsX = (geometry_.imageSize.width + stride - 1) / stride;
  const int cellsY = (geometry_.imageSize.height + stride - 1) / stride;
  std::vector<char> covered(static_cast<std::size_t>(cellsX) * cellsY, 0);
  for (const int i : inView) {
    int x = 0, y = 0;
    if (projectToPixel(geometry_, R_cw * graph_.warp(canonical_[static_cast<std::size_t>(i)], influences[static_cast<std::size_t>(i)]) + t_cw, x, y))
      covered[static_cast<std::size_t>(y / stride) * cellsX + x / stride] = 1;
  }
  const std::size_t before = canonical_.size();
  for (int cy = 0; cy < cellsY; ++cy) {
    for (int cx = 0; cx < cellsX; ++cx) {
      if (covered[static_cast<std::size_t>(cy) * cellsX + cx]) continue;
      const int x = cx * stride + stride / 2, y = cy * stride + stride / 2;
      Eigen::Vector3d camera, normalCamera;
      if (!framePoints.at(x, y, camera) || !framePoints.normalAt(x, y, 2, parameters_.maxDepthJumpMm, normalCamera))
        continue;
      const Eigen::Vector3d live = R_wc * camera + t_wc;
      NodeInfluence influence;
      const Eigen::Vector3d rest = graph_.inverseWarp(live, influence);
      Eigen::Vector3d normal = R_wc * normalCamera;
      // Back through the blended rotation: the normal at rest.
      Eigen::Matrix3d blended = Eigen::Matrix3d::Zero();
      for (int n = 0; n < influence.count; ++n)
        blended += influence.weight[n] * graph_.nodes()[static_cast<std::size_t>(influence.node[n])].rotation;
      if (influence.count > 0) normal = (blended.transpose() * normal).normalized();
      canonical_.push_back(rest);
      normals_.push_back(normal);
      weights_.push_back(1.0f);
    }
  }
  frame.samplesAdded = static_cast<int>(canonical_.size() - before);
  if (frame.samplesAdded > 0) {
    graph_.cover(Points(canonical_.begin() + static_cast<std::ptrdiff_t>(before), canonical_.end()),
                 Points(normals_.begin() + static_cast<std::ptrdiff_t>(before), normals_.end()));
  }
  frame.samples = static_cast<int>(canonical_.size());
  frame.nodes = graph_.nodeCount();
  frame.milliseconds = millisecondsSince(start);
  return frame;
}

}  // namespace tissuemosaic
