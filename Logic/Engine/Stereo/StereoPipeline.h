#pragma once
/// @file StereoPipeline.h
/// @brief The device-resident working set of the stereo matcher and the backend entry points that run section II
/// on it. The steps are one template (StereoPipeline.inl) instantiated for the CPU (StereoBackendCpu.cpp) and
/// for CUDA (StereoBackendCuda.cu); only the ZNCC cost volume has a launcher per backend (shared-memory tiling on
/// the GPU), built from the same per-pixel functions.
#include "Core/Buffer.h"
#include "Core/Image.h"
#include "Core/PinnedHostBuffer.h"
#include "AdCensusKernels.h"
#include "GuidedSearchKernels.h"
#include "HighlightKernels.h"
#include "StereoKernels.h"
#include "StereoMatcher.h"
#include "StereoParameters.h"

#include <memory>

namespace tissuemosaic::stereo {

/// The working set of the AD-Census method (StereoParameters::method; AdCensusKernels.h).
/// Volumes are pixel-major, width x height x disparityCount elements.
struct AdCensusWorkspace {
  AdCensusWorkspace(Device device, int width, int height, int disparityCount);
  Buffer<uint64_t> leftCensus, rightCensus;
  Buffer<uint8_t> leftArms, rightArms;  ///< 4 planes each (ArmPlane)
  Buffer<int32_t> cost;                 ///< matching cost, then the aggregated cost
  Buffer<int64_t> packedWindows;        ///< first pass of an aggregation round: packed (sum, count)
  Buffer<int64_t> prefix;               ///< prefix sums along rows or columns (one more entry per line)
  Buffer<int32_t> pathCost;             ///< the four scanline directions summed
};

struct StereoWorkspace;

/// The working set of the guided search (StereoSearch::Guided; GuidedSearchKernels.h): the half-resolution
/// matcher's own working set, and each pixel's candidate window and fallback mark.
struct GuidedWorkspace {
  GuidedWorkspace(Device device, int width, int height, int coarseDisparityCount);
  std::unique_ptr<StereoWorkspace> coarse;  ///< (width + 1) / 2 x (height + 1) / 2
  Image<int16_t> windowLow, windowHigh;     ///< each pixel's candidates, disparities inclusive
  Image<uint8_t> fellBack;                  ///< 1 where the window's winner failed and the whole range was scored
};

/// The working set of one matcher: sized for its images, disparity range and method. The buffers that only the
/// paper's method uses are empty under AD-Census (the ZNCC volume alone is about 100 MB at 960x540), and the
/// AD-Census working set exists only under AD-Census.
struct StereoWorkspace {
  StereoWorkspace(Device device, StereoMethod method, int width, int height, int disparityCount);
  VolumeLayout volumeLayout() const {
    return device == Device::Cpu ? VolumeLayout::rowMajor(width, disparityCount) : VolumeLayout::sliceMajor(width, height);
  }

  bool paper() const { return method == StereoMethod::Paper; }
  int paperWidth() const { return paper() ? width : 0; }  ///< width of the images only the paper's method uses

  Device device;
  StereoMethod method;
  int width, height, disparityCount;
  /// CUDA: the host side of leftGrey and rightGrey, page-locked, where the grey conversion writes and the upload
  /// reads while the host converts the other image (empty on the CPU, where the conversion writes leftGrey itself).
  PinnedHostBuffer<uint8_t> leftGreyStaging, rightGreyStaging;
  Image<uint8_t> leftGrey, rightGrey;              ///< the rectified pair as uploaded: 8-bit grey
  Image<float> left, right;                        ///< the same grey levels 0..255 as floats (exact integers)
  Image<float> columnEven, columnOdd, columnEvenSq, columnOddSq;
  Image<float> sumLeft, inverseNormLeft, sumRight, inverseNormRight;
  Buffer<int16_t> volume;                          ///< quantised ZNCC, laid out by volumeLayout()
  Image<int16_t> znccDisparity;                    ///< best ZNCC disparity per pixel
  Image<int16_t> rightZnccDisparity;               ///< best ZNCC disparity per right-image pixel
  Buffer<uint32_t> rightWinnerKeys;                ///< GPU scratch of the right-view winners
  Image<int16_t> discrete, discreteScratch;        ///< o_i and a ping-pong partner
  Image<int16_t> filledDisparity;                  ///< o_i after outlier removal and hole filling
  Image<float> smoothed, smoothedPrevious, correction;
  /// Highlights (HighlightKernels.h), kNoDisparity elsewhere: the seeds' surroundings disparity, and its mean within
  /// specularMarginPx of them.
  Image<int16_t> leftHighlightSeeds, rightHighlightSeeds;
  Image<int16_t> leftNearHighlight, rightNearHighlight;
  /// 1 within trackingHighlightMarginPx of a left seed, else 0 (all 0 with highlight removal off): what tracking
  /// and fusion leave out (MarkHighlightNeighbourhood).
  Image<uint8_t> highlightNeighbourhood;
  Image<float> awayFromHighlights;  ///< smoothed with NaN in highlightNeighbourhood (DisparityAwayFromHighlights)
  Buffer<int16_t> radialHitDistance, radialHitValue;  ///< CPU radial filling: nearest estimate per ray [8][pixels]
  Buffer<uint8_t> rayPasses;  ///< CPU outlier test: 1 where a pixel's ray of direction k passes [8][pixels]
  Buffer<int64_t> rowSum;  ///< fixed-point row sums of the box filters (exact)
  Buffer<int> rowCount;
  std::unique_ptr<AdCensusWorkspace> adCensus;  ///< AD-Census only
  /// The guided search only, made at its first frame; null while a frame is searched exhaustively, and so whether
  /// the last frame was guided (a pair too small for a half-resolution window is searched exhaustively).
  std::unique_ptr<GuidedWorkspace> guided;
  bool lastSearchGuided = false;
  Buffer<int32_t> rangeEndRowCounts;  ///< CountRangeEndWinners: 3 per row
};

/// The half-resolution matcher's parameters for the guided search at full-resolution parameters p: the exhaustive
/// search over the halved range (its ends rounded outward) with halved highlight sizes.
StereoParameters guidedCoarseParameters(const StereoParameters& p);
/// (pixel, disparity) cells the last frame scored: every cell of the range under the exhaustive search; the windows
/// and the fallbacks' whole ranges under the guided one (downloads the windows).
long long cellsScored(const StereoWorkspace& workspace);

/// Runs the whole of section II on workspace.left/right; the result is workspace.smoothed (NaN = none). explanation
/// (optional): filled with the frame's counts (StereoExplanation.h), at the cost of downloads between the steps.
void runStereoPipelineCpu(StereoWorkspace& workspace, const StereoParameters& parameters, StereoTimingsMs& timings,
                          StereoExplanation* explanation = nullptr);
/// The same on the GPU; throws Error in a build without CUDA.
void runStereoPipelineCuda(StereoWorkspace& workspace, const StereoParameters& parameters, StereoTimingsMs& timings,
                           StereoExplanation* explanation = nullptr);

/// Columns per task of the CPU's box filters (BoxColumnSums), and so the longest row segment a consumeRow gets.
constexpr int kCpuBoxColumnBlock = 64;

/// The CPU's form of ReselectDiscrete: the same rule for a row segment of pixels at once, candidates looped outside
/// the pixels so that the volume is read contiguously and the costs vectorise (the per-pixel form is latency-bound:
/// eleven dependent loads and branches per pixel). Same results as ReselectDiscrete, pixel for pixel.
struct ReselectDiscreteRows {
  ReselectDiscrete rule;
  void consumeRow(int64_t firstIndex, const int64_t* boxSums, const int* boxCounts, int columns) const;
};

/// Backend-specific ZNCC cost volume + winner (argmax, lowest disparity on ties) from the window statistics. The
/// right-view winners are found in the same pass (rightBestDisparity).
void computeZnccVolumeCpu(const ZnccVolumeInputs& inputs);
void computeZnccVolumeCuda(const ZnccVolumeInputs& inputs);
/// Backend-specific launchers of AD-Census's scanline optimisation (ScanlineInputs): the same pathCost, bit for bit.
void computeScanlinePathsCpu(const ScanlineInputs& inputs);
void computeScanlinePathsCuda(const ScanlineInputs& inputs);
/// Backend launchers of the highlight seeds of both eyes (HighlightKernels.h): the same per-pixel rule, bit for bit.
void detectHighlightSeedsCpu(const DetectHighlightSeeds& seeds);
void detectHighlightSeedsCuda(const DetectHighlightSeeds& seeds);
/// The CPU launcher of the window statistics (banded and vectorised; the same sums as WindowColumnSums +
/// WindowStatistics, which the GPU runs).
void computeWindowStatisticsCpu(ImageView<const float> image, ImageView<float> sum, ImageView<float> inverseNorm,
                                int radius, float minStdDev);
/// The CPU launcher of II.B's outlier test: one sweep per direction gives every pixel's ray answers (the same
/// answers as the ray walks of RemoveOutliers, which the GPU runs). rayPasses: [8][pixels] scratch; rowBands as in
/// fillHolesRadialCpu.
void removeOutliersCpu(ImageView<const int16_t> input, ImageView<int16_t> output, int radius, float maxStepPx,
                       uint8_t* rayPasses, int rowBands = 0);
/// The CPU launcher of radial hole filling: per-direction sweeps for the nearest estimates (same answers as the
/// ray walks of FillHolesRadial, which the GPU runs), then radialFillValue per hole. rowBands: bands of rows per
/// direction (tasks = 8 x bands; 0: from the thread count; any count gives the same answers).
void fillHolesRadialCpu(ImageView<const int16_t> input, ImageView<int16_t> output, int radius, int minLines,
                        float maxEndDifferencePx, int16_t* hitDistance, int16_t* hitValue, int rowBands = 0);

}  // namespace tissuemosaic::stereo
