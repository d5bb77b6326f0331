#include "RefinementSolver.h"

#include "Core/Device.h"
#include "Core/Error.h"
#include "RefinementPipeline.h"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace tissuemosaic::refinement {

namespace {

constexpr int kChunkResiduals = 256;  ///< residuals summed per reduction thread (64: no faster on the H100)
constexpr int kMinFixedForStart = 10;  ///< fixed-point observations a frame needs to start from them alone
/// A relative cost decrease below this ends the LM iterations (about 1e-4 px of reprojection error left to gain).
constexpr double kConvergedGain = 1e-9;

using FrameTerms = std::array<double, kTerms>;

Pose applyStep(const Pose& pose, const Eigen::Matrix<double, 6, 1>& step) {
  const Eigen::Vector3d w = step.tail<3>();
  const double angle = w.norm();
  const Eigen::Matrix3d exp =
      angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix() : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d R = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(pose.r);
  const Eigen::Vector3d t(pose.t[0], pose.t[1], pose.t[2]);
  Pose out;
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(out.r) = exp * R;
  Eigen::Map<Eigen::Vector3d>(out.t) = exp * t + step.head<3>();
  return out;
}

/// The damped 6x6 step -(H + lambda diag(H))^-1 g; false when the system cannot be solved.
bool poseStep(const FrameTerms& terms, double lambda, Eigen::Matrix<double, 6, 1>& step) {
  Eigen::Matrix<double, 6, 6> H;
  Eigen::Matrix<double, 6, 1> g;
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) H(i, j) = H(j, i) = terms[k++];
    g(i) = terms[kGradientOffset + i];
  }
  const double floor = 1e-12 * std::max(H.diagonal().maxCoeff(), 1e-300);
  for (int i = 0; i < 6; ++i) H(i, i) += lambda * std::max(H(i, i), floor);
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(H);
  if (ldlt.info() != Eigen::Success || !(H.diagonal().minCoeff() > 0)) return false;
  step = ldlt.solve(-g);
  return step.allFinite();
}

struct Layout {
  std::vector<Observation> observations;  ///< sorted by frame
  std::vector<int> chunkBegin, chunkFrame;
  std::vector<int> freePoints, pointObservationBegin, pointObservationIndex;
};

Layout makeLayout(const RefinementProblem& problem) {
  Layout layout;
  const int frames = static_cast<int>(problem.poses.size());
  layout.observations = problem.observations;
  std::stable_sort(layout.observations.begin(), layout.observations.end(),
                   [](const Observation& a, const Observation& b) { return a.frame < b.frame; });
  const int observations = static_cast<int>(layout.observations.size());
  const auto addChunks = [&](int begin, int end, int frame) {
    for (int c = begin; c < end; c += kChunkResiduals) {
      layout.chunkBegin.push_back(c);
      layout.chunkFrame.push_back(frame);
    }
  };
  int begin = 0;
  for (int f = 0; f < frames; ++f) {
    int end = begin;
    while (end < observations && layout.observations[end].frame == f) ++end;
    addChunks(begin, end, f);
    begin = end;
  }
  addChunks(observations, observations + static_cast<int>(problem.modelPointsWorldMm.size()), 0);
  layout.chunkBegin.push_back(observations + static_cast<int>(problem.modelPointsWorldMm.size()));

  // Free points with their observations (CSR), in point order.
  const int points = static_cast<int>(problem.pointFixed.size());
  std::vector<std::vector<int>> byPoint(points);
  for (int i = 0; i < observations; ++i) byPoint[layout.observations[i].point].push_back(i);
  layout.pointObservationBegin.push_back(0);
  for (int p = 0; p < points; ++p) {
    if (problem.pointFixed[p] || byPoint[p].empty()) continue;
    layout.freePoints.push_back(p);
    layout.pointObservationIndex.insert(layout.pointObservationIndex.end(), byPoint[p].begin(), byPoint[p].end());
    layout.pointObservationBegin.push_back(static_cast<int>(layout.pointObservationIndex.size()));
  }
  return layout;
}

template <class T>
Buffer<T> upload(Device device, const std::vector<T>& host) {
  Buffer<T> buffer(device, host.size());
  if (!host.empty()) buffer.upload(host.data());
  return buffer;
}

}  // namespace

RefinementSolution solveRefinement(const RefinementProblem& problem, const RefinementParameters& parameters,
                                   Device device) {
  parameters.validate();
  requireUsableDevice(device, "CUDA refinement");
  const int frames = static_cast<int>(problem.poses.size());
  const int points = static_cast<int>(problem.pointFixed.size());
  require(frames > 0, "refinement: no pose to refine");
  require(problem.pointsWorldMm.size() == 3 * problem.pointFixed.size(),
          "refinement: pointsWorldMm must hold 3 values per point");
  for (const Observation& o : problem.observations) {
    require(o.frame >= 0 && o.frame < frames && o.point >= 0 && o.point < points,
            "refinement: an observation refers to a frame or point that does not exist");
  }
  const bool icp = !problem.modelPointsWorldMm.empty();
  const bool hostMaps = usableHostMaps(problem.measuredPointsCameraMm, problem.measuredNormalsCamera);
  if (icp) {
    require(hostMaps || problem.measuredOnDevice,
            "refinement: the ICP term needs CV_32FC3 measured points and normals of one size");
  }

  const Layout layout = makeLayout(problem);
  RefinementWorkspace w;
  w.device = device;
  w.camera = problem.camera;
  w.robust = problem.robust;
  w.frameCount = frames;
  w.observationCount = static_cast<int>(layout.observations.size());
  w.icpCount = static_cast<int>(problem.modelPointsWorldMm.size());
  w.freeCount = static_cast<int>(layout.freePoints.size());
  w.chunkCount = static_cast<int>(layout.chunkFrame.size());
  w.pointIterations = parameters.lmIterations;
  w.poses = upload(device, problem.poses);
  w.pointsWorldMm = upload(device, problem.pointsWorldMm);
  w.pointFixed = upload(device, problem.pointFixed);
  w.frameFixedOnly = Buffer<uint8_t>(device, static_cast<std::size_t>(frames));
  w.frameFixedOnly.setZero();
  w.observations = upload(device, layout.observations);
  w.freePoints = upload(device, layout.freePoints);
  w.pointObservationBegin = upload(device, layout.pointObservationBegin);
  w.pointObservationIndex = upload(device, layout.pointObservationIndex);
  w.pointLambdas = upload(device, std::vector<double>(layout.freePoints.size(), parameters.initialLambda));
  w.modelPointsWorldMm = upload(device, problem.modelPointsWorldMm);
  if (icp) {
    const SurfaceMapsOnDevice* onDevice = problem.measuredOnDevice.get();
    if (onDevice && device == Device::Cuda) {
      w.measuredPointsCameraMm = onDevice->pointsCameraMm.view();
      w.measuredNormalsCamera = onDevice->normalsCamera.view();
    } else {
      const int width = hostMaps ? problem.measuredPointsCameraMm.cols : onDevice->pointsCameraMm.width();
      const int height = hostMaps ? problem.measuredPointsCameraMm.rows : onDevice->pointsCameraMm.height();
      w.measuredPointsCopy = Image<Float3>(device, width, height);
      w.measuredNormalsCopy = Image<Float3>(device, width, height);
      copySurfaceMaps(problem.measuredPointsCameraMm, problem.measuredNormalsCamera, onDevice, w.measuredPointsCopy,
                      w.measuredNormalsCopy);
      w.measuredPointsCameraMm = w.measuredPointsCopy.view();
      w.measuredNormalsCamera = w.measuredNormalsCopy.view();
    }
  }
  w.terms = Buffer<double>(device, static_cast<std::size_t>(kTerms) * (w.observationCount + w.icpCount));
  w.chunkBegin = upload(device, layout.chunkBegin);
  w.partials = Buffer<double>(device, static_cast<std::size_t>(w.chunkCount) * kTerms);

  const auto evaluateCpuOrCuda = device == Device::Cuda ? evaluatePoseTermsCuda : evaluatePoseTermsCpu;
  const auto updatePointsCpuOrCuda = device == Device::Cuda ? updatePointsCuda : updatePointsCpu;
  std::vector<double> partials(w.partials.size());
  // Per-frame sums of the terms at the given poses, chunk by chunk in a fixed order.
  const auto evaluate = [&](const std::vector<Pose>& poses) {
    w.poses.upload(poses.data());
    w.keyFramePose = poses[0];
    evaluateCpuOrCuda(w);
    w.partials.download(partials.data());
    std::vector<FrameTerms> sums(frames);
    for (FrameTerms& s : sums) s.fill(0.0);
    for (int c = 0; c < w.chunkCount; ++c) {
      FrameTerms& s = sums[layout.chunkFrame[c]];
      for (int k = 0; k < kTerms; ++k) s[k] += partials[static_cast<std::size_t>(c) * kTerms + k];
    }
    return sums;
  };
  const auto totalCost = [&](const std::vector<FrameTerms>& sums) {
    double cost = 0;
    for (const FrameTerms& s : sums) cost += s[kCostOffset];
    return cost;
  };

  RefinementSolution solution;
  solution.poses = problem.poses;
  std::vector<FrameTerms> current = evaluate(solution.poses);
  solution.initialCost = totalCost(current);
  std::vector<double> lambdas(frames, parameters.initialLambda);
  // LM on every pose at once; the frames are independent given the points, so each keeps its step only when its
  // own cost falls.
  const auto poseSteps = [&](int iterations) {
    for (double& lambda : lambdas) lambda = lambda > 1e12 ? parameters.initialLambda : lambda;  // points moved
    for (int it = 0; it < iterations; ++it) {
      std::vector<Pose> candidates = solution.poses;
      bool anyStep = false;
      for (int f = 0; f < frames; ++f) {
        Eigen::Matrix<double, 6, 1> step;
        if (lambdas[f] > 1e12 || !poseStep(current[f], lambdas[f], step)) continue;
        candidates[f] = applyStep(solution.poses[f], step);
        anyStep = true;
      }
      if (!anyStep) break;
      const std::vector<FrameTerms> trial = evaluate(candidates);
      ++solution.iterations;
      double gain = 0;  // the largest relative cost decrease of a frame
      for (int f = 0; f < frames; ++f) {
        if (trial[f][kCostOffset] < current[f][kCostOffset]) {
          gain = std::max(gain, (current[f][kCostOffset] - trial[f][kCostOffset]) / current[f][kCostOffset]);
          solution.poses[f] = candidates[f];
          current[f] = trial[f];
          lambdas[f] = std::max(lambdas[f] * 0.1, 1e-12);
        } else {
          lambdas[f] *= 10.0;
        }
      }
      if (gain > 0 && gain < kConvergedGain) break;  // converged (a rejected step only raises lambda)
    }
  };

  // Start: frames that see enough fixed points take their pose from those alone (free points start where the
  // tracked key-frame pose put them, so they would hold every pose near its tracked error; alternating steps
  // converge slowly out of that).
  if (w.freeCount > 0) {
    std::vector<int> fixedSeen(frames, 0);
    for (const Observation& o : layout.observations) fixedSeen[o.frame] += problem.pointFixed[o.point];
    std::vector<uint8_t> fixedOnly(frames, 0);
    bool any = false;
    for (int f = 0; f < frames; ++f) {
      fixedOnly[f] = fixedSeen[f] >= kMinFixedForStart;
      any = any || fixedOnly[f];
    }
    if (any) {
      w.frameFixedOnly.upload(fixedOnly.data());
      current = evaluate(solution.poses);
      poseSteps(parameters.lmIterations);
      w.frameFixedOnly.setZero();
      std::fill(lambdas.begin(), lambdas.end(), parameters.initialLambda);
    }
  }

  double previousCost = std::numeric_limits<double>::infinity();
  for (int a = 0; a < parameters.alternations; ++a) {
    if (w.freeCount > 0) {
      w.poses.upload(solution.poses.data());
      updatePointsCpuOrCuda(w);
    }
    current = evaluate(solution.poses);
    poseSteps(parameters.lmIterations);
    const double cost = totalCost(current);
    if (previousCost - cost <= kConvergedGain * previousCost) break;
    previousCost = cost;
  }
  solution.finalCost = totalCost(current);
  solution.pointsWorldMm = w.pointsWorldMm.toHost();
  return solution;
}

}  // namespace tissuemosaic::refinement
