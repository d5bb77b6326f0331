#pragma once
/// @file AgreementKernels.h
/// @brief The per-pixel and per-point steps of the model agreement (Fusion/ModelAgreement.h), written once for both
/// backends: the model seen from a frame's pose (the z-buffer of FusionKernels.h) against the frame's own stereo
/// depth, and the motion evidence that takes weight from model points the frames keep contradicting.
///
/// Determinism: the histogram and the counters are integer atomics (order-independent); every model point is
/// updated by its own thread only.
#include "Core/SurfaceKernels.h"
#include "FusionKernels.h"

#include <cmath>

namespace tissuemosaic::fusion {

/// The agreement's histogram: |depth difference| in bins of kAgreementBinMm; the last bin holds everything beyond.
constexpr int kAgreementBins = 512;
constexpr float kAgreementBinMm = 0.02f;
/// The counters' places in the agreement buffer: sampled pixels with a depth, of them those where the model has a
/// point, model points the motion evidence removed, markers it made live again, markers it retired, then the
/// histogram.
constexpr int kMeasuredSamples = 0, kOverlapSamples = 1, kRemovedPoints = 2, kRevivedMarkers = 3, kRetiredMarkers = 4,
              kHistogramStart = 5;
constexpr int kAgreementCounters = kHistogramStart + kAgreementBins;

/// A frame's stereo depth as the agreement reads it: its left-view disparity, turned into depth by the geometry's Q
/// exactly as measureSurface does (surface::reprojectPixel), within the fusion's working range.
struct MeasuredDepth {
  ImageView<const float> disparityPx;
  surface::Reprojection reprojection;
  float keptLowestPx, keptHighestPx;

  /// Depth (mm) along the optical axis at pixel (x, y); NaN where there is none.
  TM_HOST_DEVICE TM_FORCE_INLINE float depthMm(int x, int y) const {
    return surface::reprojectPixel(reprojection, x, y, disparityPx.at(x, y), keptLowestPx, keptHighestPx).z;
  }
};

/// The sampled pixels: one every stridePx in x and y, at the centre of its stride x stride cell.
struct AgreementGrid {
  int width, height, stridePx;
  TM_HOST_DEVICE int columns() const { return (width + stridePx - 1) / stridePx; }
  TM_HOST_DEVICE int rows() const { return (height + stridePx - 1) / stridePx; }
  TM_HOST_DEVICE int64_t count() const { return static_cast<int64_t>(columns()) * rows(); }
};

/// Per sampled pixel with a stereo depth: counted; where the z-buffer holds a model point too, the absolute
/// difference of the two depths goes into the histogram.
struct CompareWithModel {
  MeasuredDepth measured;
  const uint64_t* depthKeys;  ///< ProjectToDepthKeys' z-buffer of the model at the frame's pose
  AgreementGrid grid;
  int* counters;              ///< kAgreementCounters

  TM_HOST_DEVICE void operator()(int64_t sample) const {
    const int s = static_cast<int>(sample);
    const int gy = s / grid.columns(), gx = s - gy * grid.columns();
    const int half = grid.stridePx / 2;
    const int x = gx * grid.stridePx + half, y = gy * grid.stridePx + half;
    if (x >= grid.width || y >= grid.height) return;
    const float depth = measured.depthMm(x, y);
    if (!(depth > 0)) return;
    atomicAddInt(counters + kMeasuredSamples, 1);
    const uint64_t key = depthKeys[static_cast<int64_t>(y) * grid.width + x];
    if (key == kEmptyDepthKey) return;
    atomicAddInt(counters + kOverlapSamples, 1);
    const float difference = fabsf(depth - floatFromBits(static_cast<uint32_t>(key >> 32)));
    const float bin = difference / kAgreementBinMm;
    atomicAddInt(counters + kHistogramStart + (bin < kAgreementBins - 1 ? static_cast<int>(bin) : kAgreementBins - 1), 1);
  }
};

/// A point's motion evidence (kept in its normal's w, 0 when it is added) moves this far toward 1 on each frame that
/// contradicts it and toward 0 on each that agrees: a running share of recent contradictions. The point loses weight
/// only while the evidence is at least kMotionEvidenceToPenalise: after two contradicting frames in a row, or three
/// of four. A single frame's stereo outlier never costs weight.
constexpr float kMotionEvidenceRate = 0.5f;
constexpr float kMotionEvidenceToPenalise = 0.75f;

/// The evidence rate at which `frames` seeing-through frames in a row, from no evidence, reach
/// kMotionEvidenceToPenalise (1 - (1 - rate)^frames = 0.75, a little over so that float rounding does not need one
/// frame more); 0 for 0 frames (off).
inline float seenThroughEvidenceRate(int frames) {
  if (frames <= 0) return 0.0f;
  return static_cast<float>(1.0 - std::pow(1.0 - kMotionEvidenceToPenalise, 1.0 / frames) + 1e-4);
}

/// Per live model point seen by the frame (in front, inside the image, facing it, with a stereo depth at its
/// pixel): the frame contradicts it when the measured depth r = z_measured - z_point lies beyond thresholdMm on
/// either side, and its motion evidence rises; while the evidence is high, each contradicting frame takes `penalty`
/// of its weight, and at 0 it leaves the model: it stays as a moved-tissue marker (kMovedTissueMarker). A
/// measurement more than occlusionMarginMm in front of the point is something passing in front (an instrument):
/// no evidence either way, except against a point fused once (weight 1) behind the model's own nearest surface at
/// its pixel when the frame measures that surface there: such frames raise its evidence at seenThroughEvidenceRate,
/// and at weight 0 it retires at once (kRetiredMarker: it blocks no fusion). It is a stereo error fused behind the
/// tissue; an instrument in front is nearer than the model's surface and gives no evidence.
/// Per marker (markerRestFrames > 0): the frames in a row that measure its tissue back within thresholdMm of it, or
/// all elsewhere, are counted (a frame of the other kind starts the count again). After markerRestFrames back at
/// its place, the tissue has come back and rests: the marker is a live point again, with the weight of one
/// observation and no motion evidence, and key frames merge into it. After markerRestFrames elsewhere, the tissue
/// rests there (a held breath, tissue held aside): the marker retires and no longer keeps key frames from fusing it.
/// Breathing tissue passes its markers on every breath and leaves them as they are.
struct UpdateMotionEvidence {
  ModelArrays model;
  PointWarps warps;  ///< the frame meets the points where the tissue is now
  FramePose pose;
  PinholeCamera camera;
  MeasuredDepth measured;
  float thresholdMm, occlusionMarginMm, penalty;
  int markerRestFrames;  ///< FusionSettings::markerRestFrames
  float seenThroughEvidenceRate;  ///< FusionSettings::seenThroughEvidenceRate
  /// ProjectToDepthKeys' z-buffer of the model at this pose (read only where seenThroughEvidenceRate > 0).
  const uint64_t* depthKeys;
  /// kAgreementCounters: kRemovedPoints, kRevivedMarkers and kRetiredMarkers count this pass's changes.
  int* counters;

  TM_HOST_DEVICE void operator()(int64_t index) const {
    Float4 positionWeight = model.positionWeight[index];
    const bool live = isLive(positionWeight);
    if (!live && markerRestFrames <= 0) return;
    const Float3 pc = pose.worldToCamera(warps.live(index, xyz(positionWeight)));
    int x, y;
    if (!camera.project(pc, x, y)) return;
    Float4 normal = model.normal[index];
    if (!live && !isMovedTissueMarker(positionWeight, normal)) return;
    if (dot(pose.worldToCamera.rotate(warps.liveDirection(index, xyz(normal))), pc) >= 0) return;  // back-facing
    const float depth = measured.depthMm(x, y);
    if (!(depth > 0)) return;
    const float r = depth - pc.z;
    const bool seenThrough = r < -occlusionMarginMm;
    if (seenThrough && !(live && positionWeight.w <= 1.0f && seenThroughEvidenceRate > 0.0f &&
                         measuresTheModelsFront(x, y, depth))) {
      return;
    }
    const bool contradicts = seenThrough || fabsf(r) > thresholdMm;
    if (!live) {
      restMarker(index, positionWeight, normal, contradicts);
      return;
    }
    if (!contradicts && normal.w == 0.0f) return;  // nothing to record
    const float rate = seenThrough ? seenThroughEvidenceRate : kMotionEvidenceRate;
    normal.w = normal.w + rate * ((contradicts ? 1.0f : 0.0f) - normal.w);
    model.normal[index] = normal;
    if (!contradicts || normal.w < kMotionEvidenceToPenalise) return;
    positionWeight.w = positionWeight.w > penalty ? positionWeight.w - penalty : 0.0f;
    model.positionWeight[index] = positionWeight;
    if (isLive(positionWeight)) return;
    model.normal[index] = {normal.x, normal.y, normal.z, seenThrough ? kRetiredMarker : kMovedTissueMarker};
    atomicAddInt(counters + kRemovedPoints, 1);
    if (seenThrough) atomicAddInt(counters + kRetiredMarkers, 1);
  }

  /// Whether the frame's depth at (x, y) is the model's own nearest surface there (within thresholdMm): then a point
  /// behind it is seen through. Something passing in front (an instrument) is nearer than the model's front.
  TM_HOST_DEVICE bool measuresTheModelsFront(int x, int y, float depth) const {
    const uint64_t key = depthKeys[static_cast<int64_t>(y) * camera.width + x];
    if (key == kEmptyDepthKey) return false;
    return fabsf(depth - floatFromBits(static_cast<uint32_t>(key >> 32))) <= thresholdMm;
  }

  TM_HOST_DEVICE void restMarker(int64_t index, Float4 positionWeight, Float4 normal, bool contradicts) const {
    // The run so far of frames of this kind (small integers: exact in float), and this frame.
    const float back = normal.w >= kMovedTissueMarker ? normal.w - kMovedTissueMarker : 0.0f;
    const float elsewhere = normal.w <= -kMovedTissueMarker ? -normal.w - kMovedTissueMarker : 0.0f;
    const float run = (contradicts ? elsewhere : back) + 1.0f;
    if (run < static_cast<float>(markerRestFrames)) {
      const float state = kMovedTissueMarker + run;
      model.normal[index] = {normal.x, normal.y, normal.z, contradicts ? -state : state};
      return;
    }
    if (contradicts) {
      model.normal[index] = {normal.x, normal.y, normal.z, kRetiredMarker};
      atomicAddInt(counters + kRetiredMarkers, 1);
      return;
    }
    model.positionWeight[index] = {positionWeight.x, positionWeight.y, positionWeight.z, 1.0f};
    model.normal[index] = {normal.x, normal.y, normal.z, 0.0f};
    atomicAddInt(counters + kRevivedMarkers, 1);
  }
};

}  // namespace tissuemosaic::fusion
