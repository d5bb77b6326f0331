// The CPU instantiation of the refinement steps.
#include "RefinementPipeline.inl"

namespace tissuemosaic::refinement {

void runPoseStepsCpu(RefinementWorkspace& workspace, int iterations) {
  runPoseSteps<CpuBackend>(workspace, iterations);
}
void updatePointsCpu(RefinementWorkspace& workspace) { updatePoints<CpuBackend>(workspace); }

}  // namespace tissuemosaic::refinement
