// The CPU instantiation of the refinement steps.
#include "RefinementPipeline.inl"

namespace tissuemosaic::refinement {

void evaluatePoseTermsCpu(RefinementWorkspace& workspace) { evaluatePoseTerms<CpuBackend>(workspace); }
void updatePointsCpu(RefinementWorkspace& workspace) { updatePoints<CpuBackend>(workspace); }

}  // namespace tissuemosaic::refinement
