// The refinement steps, written once and instantiated per backend (included by RefinementBackendCpu.cpp and
// RefinementBackendCuda.cu only).
#include "Core/ParallelFor.h"
#include "RefinementPipeline.h"

namespace tissuemosaic::refinement {

namespace {

/// Writes every residual's terms at `poses` and sums them per frame into frameTerms (chunk by chunk, in a fixed
/// order).
template <class Backend>
void evaluatePoseTerms(RefinementWorkspace& w, const Pose* poses, double* frameTerms) {
  const int64_t stride = static_cast<int64_t>(w.observationCount) + w.icpCount;
  const int* stop = &w.control.data()->stop;
  if (stride > 0) {
    parallelFor<Backend>(w.observationCount,
                         BaPoseTerms{w.observations.data(), poses, w.pointsWorldMm.data(), w.pointFixed.data(),
                                     w.frameFixedOnly.data(), w.camera, w.robust, w.terms.data(), stride, stop},
                         256);
    parallelFor<Backend>(w.icpCount,
                         IcpPoseTerms{w.modelPointsWorldMm.data(), poses, w.measuredPointsCameraMm,
                                      w.measuredNormalsCamera, w.camera, w.robust, w.terms.data(), stride,
                                      w.observationCount, stop},
                         256);
    parallelFor<Backend>(static_cast<int64_t>(w.chunkCount) * kTerms,
                         ReduceTerms{w.terms.data(), stride, w.chunkBegin.data(), w.partials.data(), stop}, 8);
  }
  parallelFor<Backend>(static_cast<int64_t>(w.frameCount) * kTerms,
                       SumFrameTerms{w.partials.data(), w.frameChunkBegin.data(), w.frameChunks.data(), frameTerms,
                                     w.control.data()},
                       8);
}

template <class Backend>
void runPoseSteps(RefinementWorkspace& w, int iterations) {
  PoseLmControl* control = w.control.data();
  parallelFor<Backend>(w.frameCount, BeginPoseSteps{w.poseLambdas.data(), w.initialLambda, control}, 1);
  evaluatePoseTerms<Backend>(w, w.poses.data(), w.currentTerms.data());
  for (int it = 0; it < iterations; ++it) {
    parallelFor<Backend>(w.frameCount,
                         ProposePoseSteps{w.poses.data(), w.currentTerms.data(), w.poseLambdas.data(),
                                          w.candidatePoses.data(), w.stepped.data(), control},
                         1);
    evaluatePoseTerms<Backend>(w, w.candidatePoses.data(), w.trialTerms.data());
    parallelFor<Backend>(w.frameCount,
                         AcceptPoseSteps{w.poses.data(), w.candidatePoses.data(), w.stepped.data(),
                                         w.currentTerms.data(), w.trialTerms.data(), w.poseLambdas.data(),
                                         w.gains.data(), w.frameCount, control},
                         1);
    parallelFor<Backend>(1, FinishPoseIteration{w.stepped.data(), w.gains.data(), w.frameCount, control}, 1);
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
