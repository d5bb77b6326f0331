#pragma once
/// @file FusionPipeline.h
/// @brief The device-resident state of the point fusion and the backend entry points that run it. The steps are one
/// template (FusionPipeline.inl) instantiated for the CPU (FusionBackendCpu.cpp) and for CUDA (FusionBackendCuda.cu);
/// only the prefix sum has a launcher per backend. FusionBackendCudaAbsent.cpp stands in without CUDA.
#include "Core/Buffer.h"
#include "Core/Image.h"
#include "AgreementKernels.h"
#include "FusionKernels.h"

#include <cstddef>
#include <vector>

namespace tissuemosaic::fusion {

/// The model's arrays on one device; capacity() points, of which FusionModel::count are used.
struct ModelStore {
  ModelStore() = default;
  ModelStore(Device device, std::size_t capacity)
      : positionWeight(device, capacity), normal(device, capacity), colourWeight(device, capacity) {}
  std::size_t capacity() const { return positionWeight.size(); }
  ModelArrays arrays() { return {positionWeight.data(), normal.data(), colourWeight.data()}; }

  Buffer<Float4> positionWeight, normal, colourWeight;
};

struct FusionModel {
  FusionModel(Device device, int width, int height);
  /// Bytes of every buffer (the caller reports 0 on the CPU).
  std::size_t bytes() const;

  Device device;
  int width, height;
  std::size_t count = 0;       ///< entries in use: live points and moved-tissue markers
  std::size_t markers = 0;     ///< of them, points that left the model by motion evidence (kMovedTissueMarker)
  std::size_t retiredMarkers = 0;  ///< of those, markers retired (kRetiredMarker)
  bool budgetReached = false;  ///< new points were refused for the budget
  ModelStore store;            ///< grows by doubling up to the budget (allocated at the first integrate)
  /// The points' motions to where the tissue is now (PointWarps: three rows per point, for the first warpedCount
  /// points), when the model deforms; empty otherwise.
  Buffer<Float4> warpRows;
  std::size_t warpedCount = 0;
  bool deforming = false;

  // Per key frame, one pixel each.
  Image<Float3> pointsMm, normals;  ///< the uploaded measurement
  Buffer<uint8_t> colourBgr;        ///< 3 per pixel
  Buffer<uint8_t> covered;          ///< pixels an agreeing model point lands in or next to
  Buffer<int> flags, offsets;       ///< prefix-sum compaction (new pixels, sample cells)
  Buffer<uint64_t> depthKeys;       ///< z-buffer at depthKeysPose (sampleVisible, the agreement, motion evidence)
  FramePose depthKeysPose{};
  bool depthKeysCurrent = false;    ///< depthKeys is the model's at depthKeysPose: no point changed since it was drawn
  Buffer<int> counters;             ///< [0] merged points
  Buffer<uint8_t> scanScratch;      ///< CUDA prefix-sum scratch
  Buffer<Float4> samplePositions, sampleNormals;  ///< sampleVisible's output
  Buffer<int> agreementCounters;         ///< kAgreementCounters (AgreementKernels.h)
  Image<float> disparity;                ///< a frame's disparity uploaded for the agreement (when it is on the host)

  /// The warps the kernels apply: none unless the model deforms.
  PointWarps warps() const { return {deforming ? warpRows.data() : nullptr}; }

  MeasurementView measurement() const {
    return {pointsMm.view(), normals.view(), colourBgr.data()};
  }
};

struct IntegrateCounts {
  int merged = 0, added = 0, refused = 0;
};

/// Merges the uploaded measurement into the model and appends its uncovered pixels while maxPoints allows.
IntegrateCounts integrateCpu(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxPoints);
IntegrateCounts integrateCuda(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxPoints);

/// Fills model.samplePositions/sampleNormals with up to maxSamples visible model points spread over the image;
/// returns how many.
int sampleVisibleCpu(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxSamples);
int sampleVisibleCuda(FusionModel& model, const FramePose& pose, const FusionSettings& settings, int maxSamples);

/// The model agreement of a frame (AgreementKernels.h): the model's z-buffer at the pose, then the sampled pixels.
/// Returns the counters (kAgreementCounters) on the host.
std::vector<int> measureAgreementCpu(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                                     const MeasuredDepth& measured, const AgreementGrid& grid);
std::vector<int> measureAgreementCuda(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                                      const MeasuredDepth& measured, const AgreementGrid& grid);

/// Takes weight from the model points the frame contradicts (UpdateMotionEvidence); returns how many left.
int updateMotionCpu(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                    const MeasuredDepth& measured, float thresholdMm, float occlusionMarginMm, float penalty);
int updateMotionCuda(FusionModel& model, const FramePose& pose, const FusionSettings& settings,
                     const MeasuredDepth& measured, float thresholdMm, float occlusionMarginMm, float penalty);

/// Backend prefix sums: offsets[i] = flags[0] + ... + flags[i - 1]; returns the total of all count flags.
int exclusiveScanCpu(const int* flags, int* offsets, int count);
int exclusiveScanCuda(const int* flags, int* offsets, int count, Buffer<uint8_t>& scratch);

}  // namespace tissuemosaic::fusion
