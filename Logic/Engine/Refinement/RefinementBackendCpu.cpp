// The CPU instantiation of the refinement steps.
#include "RefinementPipeline.inl"

namespace tissuemosaic::refinement {

void runPoseStepsCpu(RefinementWorkspace& workspace, const PoseRun& run) {
  runPoseSteps<CpuBackend>(workspace, run);
}
void updatePointsCpu(RefinementWorkspace& workspace) { updatePoints<CpuBackend>(workspace); }

}  // namespace tissuemosaic::refinement
