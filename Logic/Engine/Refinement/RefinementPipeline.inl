// The refinement steps, written once and instantiated per backend (included by RefinementBackendCpu.cpp and
// RefinementBackendCuda.cu only).
#include "Core/ParallelFor.h"
#include "RefinementPipeline.h"

namespace tissuemosaic::refinement {

namespace {

template <class Backend>
void evaluatePoseTerms(RefinementWorkspace& w) {
  const int64_t stride = static_cast<int64_t>(w.observationCount) + w.icpCount;
  if (stride == 0) return;
  parallelFor<Backend>(w.observationCount, BaPoseTerms{w.observations.data(), w.poses.data(), w.pointsWorldMm.data(),
                                                       w.pointFixed.data(), w.frameFixedOnly.data(), w.camera, w.robust, w.terms.data(), stride}, 256);
  if (w.icpCount > 0) {
    parallelFor<Backend>(w.icpCount, IcpPoseTerms{w.modelPointsWorldMm.data(), w.keyFramePose,
                                                  w.measuredPointsCameraMm, w.measuredNormalsCamera,
                                                  w.camera, w.robust, w.terms.data(), stride, w.observationCount},
                         256);
  }
  parallelFor<Backend>(static_cast<int64_t>(w.chunkCount) * kTerms,
                       ReduceTerms{w.terms.data(), stride, w.chunkBegin.data(), w.partials.data()}, 8);
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
