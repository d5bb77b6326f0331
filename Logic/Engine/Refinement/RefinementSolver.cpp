#include "RefinementSolver.h"

#include "Core/CountingSort.h"
#include "Core/Device.h"
#include "Core/Error.h"
#include "Core/KernelProfiler.h"
#include "Core/ParallelChunkSums.h"
#include "RefinementPipeline.h"

#include <algorithm>
#include <limits>
#include <optional>

namespace tissuemosaic::refinement {

namespace {

/// Residuals summed per chunk: one per thread of parallelChunkSums' CUDA block.
constexpr int kChunkResiduals = kChunkSumThreads;
constexpr int kMinFixedForStart = 10;  ///< fixed-point observations a frame needs to start from them alone

struct Layout {
  std::vector<Observation> observations;  ///< sorted by frame
  std::vector<int> chunkBegin, chunkFrame;
  std::vector<int> frameChunkBegin, frameChunks;  ///< the chunks of each frame, in chunk order
  std::vector<int> freePoints, pointObservationBegin, pointObservationIndex;
};

/// Counting sorts (stable, linear): the layout is built once per key frame on the solve's critical path.
Layout makeLayout(const RefinementProblem& problem) {
  Layout layout;
  const int frames = static_cast<int>(problem.poses.size());
  const int observations = static_cast<int>(problem.observations.size());
  const Buckets byFrame =
      bucketByKey(observations, frames, [&](int i) { return problem.observations[static_cast<std::size_t>(i)].frame; });
  for (int i : byFrame.order) layout.observations.push_back(problem.observations[static_cast<std::size_t>(i)]);

  const auto addChunks = [&](int begin, int end, int frame) {
    for (int c = begin; c < end; c += kChunkResiduals) {
      layout.chunkBegin.push_back(c);
      layout.chunkFrame.push_back(frame);
    }
  };
  for (int f = 0; f < frames; ++f) addChunks(byFrame.begin[f], byFrame.begin[f + 1], f);
  const int residuals = observations + static_cast<int>(problem.modelPointsWorldMm.size());
  addChunks(observations, residuals, 0);
  layout.chunkBegin.push_back(residuals);
  Buckets chunksByFrame = bucketByKey(static_cast<int>(layout.chunkFrame.size()), frames,
                                      [&](int c) { return layout.chunkFrame[static_cast<std::size_t>(c)]; });
  layout.frameChunkBegin = std::move(chunksByFrame.begin);
  layout.frameChunks = std::move(chunksByFrame.order);

  // Free points with their observations (CSR), in point order.
  const int points = static_cast<int>(problem.pointFixed.size());
  const Buckets byPoint =
      bucketByKey(observations, points, [&](int i) { return layout.observations[static_cast<std::size_t>(i)].point; });
  layout.pointObservationBegin.push_back(0);
  for (int p = 0; p < points; ++p) {
    if (problem.pointFixed[p] || byPoint.begin[p] == byPoint.begin[p + 1]) continue;
    layout.freePoints.push_back(p);
    layout.pointObservationIndex.insert(layout.pointObservationIndex.end(), byPoint.order.begin() + byPoint.begin[p],
                                        byPoint.order.begin() + byPoint.begin[p + 1]);
    layout.pointObservationBegin.push_back(static_cast<int>(layout.pointObservationIndex.size()));
  }
  return layout;
}

/// Queued on the calling thread's stream without waiting for it (the host data is staged at once), so that the
/// setup's copies do not each wait for the device.
template <class T>
Buffer<T> upload(Device device, const std::vector<T>& host) {
  Buffer<T> buffer(device, host.size());
  if (!host.empty()) buffer.uploadQueued(host.data());
  return buffer;
}

/// 1 for each frame that sees enough fixed-point observations to take its first pose step from those alone.
std::vector<uint8_t> framesStartingFromFixedPoints(const RefinementProblem& problem, const Layout& layout) {
  std::vector<int> fixedSeen(problem.poses.size(), 0);
  for (const Observation& o : layout.observations) fixedSeen[o.frame] += problem.pointFixed[o.point];
  std::vector<uint8_t> fixedOnly(problem.poses.size(), 0);
  for (std::size_t f = 0; f < fixedSeen.size(); ++f) fixedOnly[f] = fixedSeen[f] >= kMinFixedForStart;
  return fixedOnly;
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

  std::optional<profiling::ScopedTimer> setupTimer(std::in_place, "host: refinement solve, layout and uploads");
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
  const std::vector<uint8_t> fixedOnly = framesStartingFromFixedPoints(problem, layout);
  const bool startFromFixedPoints =
      w.freeCount > 0 && std::find(fixedOnly.begin(), fixedOnly.end(), 1) != fixedOnly.end();
  w.frameFixedOnly = upload(device, fixedOnly);
  w.observations = upload(device, layout.observations);
  w.freePoints = upload(device, layout.freePoints);
  w.pointObservationBegin = upload(device, layout.pointObservationBegin);
  w.pointObservationIndex = upload(device, layout.pointObservationIndex);
  // The uploads are queued: their host data stays alive to the end (cuda::copyHostToDeviceQueued needs it only
  // until it returns, but that is cheap insurance).
  const std::vector<double> initialPointLambdas(layout.freePoints.size(), parameters.initialLambda);
  const std::vector<double> initialPoseLambdas(frames, parameters.initialLambda);
  const std::vector<PoseLmControl> initialControl{PoseLmControl{0, 0}};
  w.pointLambdas = upload(device, initialPointLambdas);
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
  w.chunkBegin = upload(device, layout.chunkBegin);
  w.partials = Buffer<double>(device, static_cast<std::size_t>(w.chunkCount) * kTerms);
  w.frameChunkBegin = upload(device, layout.frameChunkBegin);
  w.frameChunks = upload(device, layout.frameChunks);
  w.initialLambda = parameters.initialLambda;
  w.candidatePoses = Buffer<Pose>(device, static_cast<std::size_t>(frames));
  w.stepped = Buffer<uint8_t>(device, static_cast<std::size_t>(frames));
  w.poseLambdas = upload(device, initialPoseLambdas);
  w.currentTerms = Buffer<double>(device, static_cast<std::size_t>(frames) * kTerms);
  w.trialTerms = Buffer<double>(device, static_cast<std::size_t>(frames) * kTerms);
  w.gains = Buffer<double>(device, static_cast<std::size_t>(frames));
  w.control = upload(device, initialControl);

  const auto runPoseSteps = device == Device::Cuda ? runPoseStepsCuda : runPoseStepsCpu;
  const auto updatePoints = device == Device::Cuda ? updatePointsCuda : updatePointsCpu;
  // The total cost of per-frame terms: waits for the queued iterations.
  const auto totalCost = [&](const Buffer<double>& frameTerms) {
    const std::vector<double> terms = frameTerms.toHost();
    double cost = 0;
    for (int f = 0; f < frames; ++f) cost += terms[static_cast<std::size_t>(f) * kTerms + kCostOffset];
    return cost;
  };

  setupTimer.reset();
  std::optional<profiling::ScopedTimer> iterationTimer(std::in_place, "host: refinement solve, iterations");
  // The initial cost is read at the end: no wait for the device before the iterations are queued.
  runPoseSteps(w, PoseRun{});
  Buffer<double> initialTerms(device, w.currentTerms.size());
  initialTerms.copyFrom(w.currentTerms);
  // Start: frames that see enough fixed points take their pose from those alone (free points start where the
  // tracked key-frame pose put them, so they would hold every pose near its tracked error; alternating steps
  // converge slowly out of that).
  if (startFromFixedPoints) runPoseSteps(w, PoseRun{parameters.lmIterations, true, false});

  // Alternations: the free points, then every pose at once (the frames are independent given the points, so each
  // keeps its step only when its own cost falls).
  double previousCost = std::numeric_limits<double>::infinity();
  double cost = 0;
  for (int a = 0; a < parameters.alternations; ++a) {
    if (w.freeCount > 0) updatePoints(w);
    // After the start every frame starts from initialLambda again.
    runPoseSteps(w, PoseRun{parameters.lmIterations, false, a == 0 && startFromFixedPoints});
    cost = totalCost(w.currentTerms);
    // Not after the first round: inf - cost <= gain * inf would hold, and one round would always be all.
    if (a > 0 && previousCost - cost <= kConvergedGain * previousCost) break;
    previousCost = cost;
  }
  iterationTimer.reset();
  profiling::ScopedTimer downloadTimer("host: refinement solve, downloads");
  RefinementSolution solution;
  solution.initialCost = totalCost(initialTerms);
  solution.finalCost = cost;
  solution.poses = w.poses.toHost();
  solution.pointsWorldMm = w.pointsWorldMm.toHost();
  solution.iterations = w.control.toHost()[0].iterations;
  return solution;
}

}  // namespace tissuemosaic::refinement
