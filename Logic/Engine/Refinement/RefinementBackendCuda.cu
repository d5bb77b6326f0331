// The CUDA instantiation of the refinement steps.
#include "RefinementPipeline.inl"

namespace tissuemosaic::refinement {

void runPoseStepsCuda(RefinementWorkspace& workspace, int iterations) {
  runPoseSteps<CudaBackend>(workspace, iterations);
}
void updatePointsCuda(RefinementWorkspace& workspace) { updatePoints<CudaBackend>(workspace); }

}  // namespace tissuemosaic::refinement
