// The refinement steps, written once and instantiated per backend (included by RefinementBackendCpu.cpp and
// RefinementBackendCuda.cu only).
#include "Core/ParallelChain.h"
#include "Core/ParallelChunkSums.h"
#include "Core/ParallelFor.h"
#include "RefinementPipeline.h"

namespace tissuemosaic::refinement {

namespace {

/// Every residual's terms: the observations' (BaPoseTerms), then the model points' (IcpPoseTerms).
struct PoseTerms {
  BaPoseTerms observations;
  IcpPoseTerms modelPoints;
  int64_t observationCount;

  TM_HOST_DEVICE void operator()(int64_t i, double terms[kTerms]) const {
    if (i < observationCount) observations(i, terms);
    else modelPoints(i - observationCount, terms);
  }
};

/// Sums every residual's terms at `poses` per chunk into partials; the per-frame sums follow in the caller's chain
/// (SumFrameTerms). Nothing once the LM has stopped (PoseLmControl::stop).
template <class Backend>
void evaluateChunkTerms(RefinementWorkspace& w, const Pose* poses, const uint8_t* fixedOnly) {
  parallelChunkSums<Backend, kTerms>(
      w.chunkCount, w.chunkBegin.data(),
      PoseTerms{BaPoseTerms{w.observations.data(), poses, w.pointsWorldMm.data(), w.pointFixed.data(), fixedOnly,
                            w.camera, w.robust},
                IcpPoseTerms{w.modelPointsWorldMm.data(), poses, w.measuredPointsCameraMm, w.measuredNormalsCamera,
                             w.camera, w.robust},
                w.observationCount},
      w.partials.data(), &w.control.data()->stop);
}

/// Per iteration two launches on the GPU: the terms' chunk sums, and one chain of the per-frame steps that
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
