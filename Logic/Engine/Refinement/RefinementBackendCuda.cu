// The CUDA instantiation of the refinement steps.
#include "RefinementPipeline.inl"

namespace tissuemosaic::refinement {

void evaluatePoseTermsCuda(RefinementWorkspace& workspace) { evaluatePoseTerms<CudaBackend>(workspace); }
void updatePointsCuda(RefinementWorkspace& workspace) { updatePoints<CudaBackend>(workspace); }

}  // namespace tissuemosaic::refinement
