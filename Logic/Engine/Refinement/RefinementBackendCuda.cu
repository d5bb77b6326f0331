// The CUDA instantiation of the refinement steps.
#include "RefinementPipeline.inl"

namespace tissuemosaic::refinement {

void runPoseStepsCuda(RefinementWorkspace& workspace, const PoseRun& run) {
  runPoseSteps<CudaBackend>(workspace, run);
}
void updatePointsCuda(RefinementWorkspace& workspace) { updatePoints<CudaBackend>(workspace); }

}  // namespace tissuemosaic::refinement
