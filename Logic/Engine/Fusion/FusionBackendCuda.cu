// The CUDA instantiation of the point fusion, and its prefix sum (CUB).
#include "Core/CudaRuntime.h"
#include "FusionPipeline.inl"

#include <cub/device/device_scan.cuh>

namespace tissuemosaic::fusion {

int exclusiveScanCuda(const int* flags, int* offsets, int count, Buffer<uint8_t>& scratch) {
  if (count <= 0) return 0;
  std::size_t bytes = 0;
  if (cub::DeviceScan::ExclusiveSum(nullptr, bytes, flags, offsets, count) != cudaSuccess)
    throw Error("CUDA error in the fusion prefix sum (scratch size)");
  if (scratch.size() < bytes) scratch = Buffer<uint8_t>(Device::Cuda, bytes);
  if (cub::DeviceScan::ExclusiveSum(scratch.data(), bytes, flags, offsets, count) != cudaSuccess)
    throw Error("CUDA error in the fusion prefix sum");
  int last[2] = {0, 0};
  cuda::copyDeviceToHost(&last[0], offsets + count - 1, sizeof(int));
  cuda::copyDeviceToHost(&last[1], flags + count - 1, sizeof(int));
  return last[0] + last[1];
}

IntegrateCounts integrateCuda(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxPoints) {
  return integrateOn<CudaBackend>(model, pose, settings, maxPoints);
}

int sampleVisibleCuda(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxSamples) {
  return sampleVisibleOn<CudaBackend>(model, pose, settings, maxSamples);
}

std::vector<int> measureAgreementCuda(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                                     const MeasuredDepth& measured, const AgreementGrid& grid) {
  return measureAgreementOn<CudaBackend>(model, pose, settings, measured, grid);
}

int updateMotionCuda(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                    const MeasuredDepth& measured, float thresholdMm, float occlusionMarginMm, float penalty) {
  return updateMotionOn<CudaBackend>(model, pose, settings, measured, thresholdMm, occlusionMarginMm, penalty);
}


}  // namespace tissuemosaic::fusion
