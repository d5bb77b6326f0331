// The CPU instantiation of the point fusion, and its prefix sum.
#include "FusionPipeline.inl"

#include <numeric>

namespace tissuemosaic::fusion {

int exclusiveScanCpu(const int* flags, int* offsets, int count) {
  if (count <= 0) return 0;
  std::exclusive_scan(flags, flags + count, offsets, 0);
  return offsets[count - 1] + flags[count - 1];
}

IntegrateCounts integrateCpu(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxPoints) {
  return integrateOn<CpuBackend>(model, pose, settings, maxPoints);
}

int sampleVisibleCpu(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxSamples) {
  return sampleVisibleOn<CpuBackend>(model, pose, settings, maxSamples);
}

std::vector<int> measureAgreementCpu(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                                     const MeasuredDepth& measured, const AgreementGrid& grid) {
  return measureAgreementOn<CpuBackend>(model, pose, settings, measured, grid);
}

int updateMotionCpu(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                    const MeasuredDepth& measured, float thresholdMm, float occlusionMarginMm, float penalty) {
  return updateMotionOn<CpuBackend>(model, pose, settings, measured, thresholdMm, occlusionMarginMm, penalty);
}


}  // namespace tissuemosaic::fusion
