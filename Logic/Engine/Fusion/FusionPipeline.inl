// The point fusion, written once and instantiated per backend (included by FusionBackendCpu.cpp and
// FusionBackendCuda.cu only).
#include "Core/Error.h"
#include "Core/ParallelFor.h"
#include "FusionPipeline.h"

#include <algorithm>
#include <cstring>
#include <type_traits>

namespace tissuemosaic::fusion {

namespace {

template <class Backend>
int exclusiveScan(FusionModel& model, const int* flags, int* offsets, int count) {
  if constexpr (std::is_same_v<Backend, CpuBackend>) return exclusiveScanCpu(flags, offsets, count);
  else return exclusiveScanCuda(flags, offsets, count, model.scanScratch);
}

/// Makes room for `needed` points: capacity doubles (from one image's pixels) up to maxPoints.
template <class Backend>
void reserve(FusionModel& model, std::size_t needed, int maxPoints) {
  const std::size_t capacity = model.store.capacity();
  if (needed <= capacity) return;
  const std::size_t budget = static_cast<std::size_t>(maxPoints);
  std::size_t grown = capacity > 0 ? capacity : std::min(budget, static_cast<std::size_t>(model.width) * model.height);
  while (grown < needed) grown = std::min(budget, grown * 2);
  ModelStore larger(model.device, grown);
  parallelFor<Backend>(static_cast<int64_t>(model.count), CopyModelPoints{model.store.arrays(), larger.arrays()});
  model.store = std::move(larger);
}

}  // namespace

template <class Backend>
IntegrateCounts integrateOn(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxPoints) {
  model.depthKeysCurrent = false;  // points merge (move) and are added
  const int64_t pixels = static_cast<int64_t>(model.width) * model.height;
  const MeasurementView measurement = model.measurement();
  model.covered.setZero();
  model.counters.setZero();
  parallelFor<Backend>(static_cast<int64_t>(model.count),
                       MergeModelPoints{model.store.arrays(), model.warps(), measurement, pose, settings, model.covered.data(),
                                        model.counters.data()});
  parallelFor<Backend>(pixels, FlagNewPixels{measurement, model.covered.data(), model.flags.data(),
                                             settings.newPointStepPx});
  const int fresh = exclusiveScan<Backend>(model, model.flags.data(), model.offsets.data(), static_cast<int>(pixels));

  IntegrateCounts counts;
  model.counters.download(&counts.merged);  // counters[0]; the buffer holds one int
  const std::size_t room = static_cast<std::size_t>(maxPoints) - std::min<std::size_t>(model.count, maxPoints);
  counts.added = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(fresh), room));
  counts.refused = fresh - counts.added;
  if (counts.refused > 0) model.budgetReached = true;
  if (counts.added == 0) return counts;
  reserve<Backend>(model, model.count + counts.added, maxPoints);
  parallelFor<Backend>(pixels, AppendNewPoints{model.store.arrays(), measurement, pose, settings, model.flags.data(),
                                               model.offsets.data(), static_cast<int64_t>(model.count), counts.added});
  model.count += counts.added;
  return counts;
}

/// The model's z-buffer at `pose` (ProjectToDepthKeys) in model.depthKeys. Drawn again only when the pose or the
/// model's points changed since it was last drawn: the motion evidence reads the one the frame's agreement drew.
template <class Backend>
void drawDepthKeys(FusionModel& model, const FramePose& pose, const PinholeCamera& camera) {
  if (model.depthKeysCurrent && std::memcmp(&model.depthKeysPose, &pose, sizeof pose) == 0) return;
  const ModelArrays arrays = model.store.arrays();
  parallelFor<Backend>(static_cast<int64_t>(model.width) * model.height, ClearDepthKeys{model.depthKeys.data()});
  parallelFor<Backend>(static_cast<int64_t>(model.count),
                       ProjectToDepthKeys{arrays.positionWeight, arrays.normal, model.warps(), pose, camera, model.depthKeys.data()});
  model.depthKeysPose = pose;
  model.depthKeysCurrent = true;
}

template <class Backend>
int sampleVisibleOn(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxSamples) {
  if (model.count == 0 || maxSamples <= 0) return 0;
  ModelArrays arrays = model.store.arrays();
  drawDepthKeys<Backend>(model, pose, settings.camera);
  // Visible pixels first, then the coarsest grid stride that keeps the samples within maxSamples.
  const auto flagGrid = [&](const SampleGrid& grid) {
    parallelFor<Backend>(grid.cellCount(), FlagGridSamples{model.depthKeys.data(), arrays.normal, grid, model.flags.data()});
    return exclusiveScan<Backend>(model, model.flags.data(), model.offsets.data(), static_cast<int>(grid.cellCount()));
  };
  SampleGrid grid{model.width, model.height, 1};
  int samples = flagGrid(grid);
  if (samples > maxSamples) {
    grid.stride = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(samples) / maxSamples))));
    samples = flagGrid(grid);
    while (samples > maxSamples) {
      ++grid.stride;
      samples = flagGrid(grid);
    }
  }
  if (samples == 0) return 0;
  if (model.samplePositions.size() < static_cast<std::size_t>(samples)) {
    model.samplePositions = Buffer<Float4>(model.device, samples);
    model.sampleNormals = Buffer<Float4>(model.device, samples);
  }
  parallelFor<Backend>(grid.cellCount(),
                       GatherGridSamples{model.depthKeys.data(), grid, model.flags.data(), model.offsets.data(),
                                         arrays.positionWeight, arrays.normal, model.warps(),
                                         model.samplePositions.data(),
                                         model.sampleNormals.data()});
  return samples;
}

template <class Backend>
std::vector<int> measureAgreementOn(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                                    const MeasuredDepth& measured, const AgreementGrid& grid) {
  if (model.agreementCounters.size() != static_cast<std::size_t>(kAgreementCounters)) {
    model.agreementCounters = Buffer<int>(model.device, kAgreementCounters);
  }
  model.agreementCounters.setZero();
  drawDepthKeys<Backend>(model, pose, settings.camera);
  parallelFor<Backend>(grid.count(), CompareWithModel{measured, model.depthKeys.data(), grid,
                                                      model.agreementCounters.data()});
  return model.agreementCounters.toHost();
}

template <class Backend>
int updateMotionOn(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                   const MeasuredDepth& measured, float thresholdMm, float occlusionMarginMm, float penalty) {
  if (model.count == 0) return 0;
  if (model.agreementCounters.size() != static_cast<std::size_t>(kAgreementCounters)) {
    model.agreementCounters = Buffer<int>(model.device, kAgreementCounters);
  }
  model.agreementCounters.setZero();
  // The seen-through test reads the model's nearest surface per pixel at this pose.
  if (settings.seenThroughEvidenceRate > 0) drawDepthKeys<Backend>(model, pose, settings.camera);
  parallelFor<Backend>(static_cast<int64_t>(model.count),
                       UpdateMotionEvidence{model.store.arrays(), model.warps(), pose, settings.camera, measured, thresholdMm,
                                            occlusionMarginMm, penalty, settings.markerRestFrames,
                                            settings.seenThroughEvidenceRate, model.depthKeys.data(),
                                            model.agreementCounters.data()});
  int head[kHistogramStart] = {};
  model.agreementCounters.downloadPart(head, kHistogramStart);
  model.markers += static_cast<std::size_t>(head[kRemovedPoints]);
  model.markers -= static_cast<std::size_t>(head[kRevivedMarkers]);
  model.retiredMarkers += static_cast<std::size_t>(head[kRetiredMarkers]);
  if (head[kRemovedPoints] > 0 || head[kRevivedMarkers] > 0) model.depthKeysCurrent = false;  // points left or came back
  return head[kRemovedPoints];
}

}  // namespace tissuemosaic::fusion
