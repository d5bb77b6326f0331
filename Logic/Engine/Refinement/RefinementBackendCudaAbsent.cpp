// Built only without the CUDA backend: the CUDA entry points say so instead of running.
#include "Core/Error.h"
#include "RefinementPipeline.h"

namespace tissuemosaic::refinement {

void runPoseStepsCuda(RefinementWorkspace&, const PoseRun&) { throw Error("this build of TissueMosaic has no CUDA backend"); }
void updatePointsCuda(RefinementWorkspace&) { throw Error("this build of TissueMosaic has no CUDA backend"); }

}  // namespace tissuemosaic::refinement
