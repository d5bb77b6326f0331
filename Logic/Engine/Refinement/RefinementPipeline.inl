// The refinement steps, written once and instantiated per backend (included by RefinementBackendCpu.cpp and
// RefinementBackendCuda.cu only).
#include "Core/ParallelChain.h"
#include "Core/ParallelFor.h"
#include "RefinementPipeline.h"

namespace tissuemosaic::refinement {

namespace {

/// Every residual's terms: the observations' (BaPoseTerms), then the model points' (IcpPoseTerms), in one loop.
struct PoseTerms {
  BaPoseTerms observations;
  IcpPoseTerms modelPoints;
  int64_t observationCount;

  TM_HOST_DEVICE void operator()(int64_t i) const {
    if (i < observationCount) observations(i);
    else modelPoints(i - observationCount);
  }
};

/// Writes every residual's terms at `poses` and sums them per chunk (ReduceTerms); the per-frame sums follow in the
/// caller's chain (SumFrameTerms).
template <class Backend>
void evaluateChunkTerms(RefinementWorkspace& w, const Pose* poses, const uint8_t* fixedOnly) {
  const int64_t stride = static_cast<int64_t>(w.observationCount) + w.icpCount;
  if (stride == 0) return;
  const int* stop = &w.control.data()->stop;
  parallelFor<Backend>(stride,
                       PoseTerms{BaPoseTerms{w.observations.data(), poses, w.pointsWorldMm.data(),
                                             w.pointFixed.data(), fixedOnly, w.camera, w.robust, w.terms.data(),
                                             stride, stop},
                                 IcpPoseTerms{w.modelPointsWorldMm.data(), poses, w.measuredPointsCameraMm,
                                              w.measuredNormalsCamera, w.camera, w.robust, w.terms.data(), stride,
                                              w.observationCount, stop},
                                 w.observationCount},
                       256);
  parallelFor<Backend>(static_cast<int64_t>(w.chunkCount) * kTerms,
                       ReduceTerms{w.terms.data(), stride, w.chunkBegin.data(), w.partials.data(), stop}, 8);
}

/// Per iteration three launches on the GPU: the terms, their chunk sums, and one chain of the per-frame steps that
/// ends with the next iteration's proposal (ProposePoseSteps after the last iteration is never read).
template <class Backend>
void runPoseSteps(RefinementWorkspace& w, const PoseRun& run) {
  PoseLmControl* control = w.control.data();
  const uint8_t* fixedOnly = run.fixedPointsOnly ? w.frameFixedOnly.data() : nullptr;
  const int frames = w.frameCount;
  const int64_t frameTermCount = static_cast<int64_t>(frames) * kTerms;
  const auto sumFrameTerms = [&](double* frameTerms) {
    return chainLoop(frameTermCount,
                     SumFrameTerms{w.partials.data(), w.frameChunkBegin.data(), w.frameChunks.data(), frameTerms,
                                   control});
  };
  const auto propose = chainLoop(frames, ProposePoseSteps{w.poses.data(), w.currentTerms.data(),
                                                          w.poseLambdas.data(), w.candidatePoses.data(),
                                                          w.stepped.data(), control});

  parallelFor<Backend>(frames, BeginPoseSteps{w.poseLambdas.data(), w.initialLambda, run.resetLambdas, control}, 1);
  evaluateChunkTerms<Backend>(w, w.poses.data(), fixedOnly);
  parallelChain<Backend>(sumFrameTerms(w.currentTerms.data()), propose);
  for (int it = 0; it < run.iterations; ++it) {
    evaluateChunkTerms<Backend>(w, w.candidatePoses.data(), fixedOnly);
    parallelChain<Backend>(sumFrameTerms(w.trialTerms.data()),
                           chainLoop(frames, AcceptPoseSteps{w.poses.data(), w.candidatePoses.data(),
                                                             w.stepped.data(), w.currentTerms.data(),
                                                             w.trialTerms.data(), w.poseLambdas.data(),
                                                             w.gains.data(), frames, control}),
                           chainLoop(1, FinishPoseIteration{w.stepped.data(), w.gains.data(), frames, control}),
                           propose);
  }
}

template <class Backend>
void updatePoints(RefinementWorkspace& w) {
  parallelFor<Backend>(w.freeCount, UpdatePoints{w.observations.data(), w.poses.data(), w.freePoints.data(),
                                                 w.pointObservationBegin.data(), w.pointObservationIndex.data(),
                                                 w.pointsWorldMm.data(), w.pointLambdas.data(), w.camera, w.robust,
                                                 w.pointIterations}, 16);
}

}  // namespace

}  // namespace tissuemosaic::refinement
