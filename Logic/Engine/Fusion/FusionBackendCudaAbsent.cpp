// Built only without the CUDA backend: the CUDA entry points say so instead of running.
#include "Core/Error.h"
#include "FusionPipeline.h"

namespace tissuemosaic::fusion {

int exclusiveScanCuda(const int*, int*, int, Buffer<uint8_t>&) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

IntegrateCounts integrateCuda(FusionModel&, const FramePose&, const FusionSettings&, int) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

int sampleVisibleCuda(FusionModel&, const FramePose&, const FusionSettings&, int) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

std::vector<int> measureAgreementCuda(FusionModel&, const FramePose&, const FusionSettings&, const MeasuredDepth&,
                                      const AgreementGrid&) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

int updateMotionCuda(FusionModel&, const FramePose&, const FusionSettings&, const MeasuredDepth&, float, float, float) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}


}  // namespace tissuemosaic::fusion
