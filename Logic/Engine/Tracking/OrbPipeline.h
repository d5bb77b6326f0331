#pragma once
/// @file OrbPipeline.h
/// @brief The device-resident working set of one ORB pyramid level and the backend entry points that run the
/// extractor and the matcher on it. The steps are one template (OrbPipeline.inl) instantiated for the CPU
/// (OrbBackendCpu.cpp) and for CUDA (OrbBackendCuda.cu); OrbBackendCudaAbsent.cpp stands in without CUDA.
#include "Core/Buffer.h"
#include "Core/Image.h"
#include "OrbKernels.h"
#include "SubPixelKernels.h"

namespace tissuemosaic::orb {

struct OrbLevelWorkspace {
  OrbLevelWorkspace(Device device, int width, int height, const CellGrid& grid, int budget);

  CellGrid grid;
  int budget;                     ///< features this level keeps at most
  int64_t scaleQ16;               ///< level size = full size / (scaleQ16 / 65536) (level 0: 65536)
  Image<uint8_t> image;           ///< level grey image (level 0: the input)
  Image<uint16_t> smoothingRows;  ///< horizontal pass of the smoothing
  Image<uint8_t> smoothed;
  Image<uint8_t> fastScores;
  Image<int64_t> responses;
  Buffer<CellCandidate> rowCandidates;  ///< grid.cellCount() * grid.cellSize * grid.perCell (CellRowBest)
  Buffer<LevelKeypoint> slots;    ///< grid.cellCount() * grid.perCell
  Buffer<int> histogram;          ///< kResponseBins
  Buffer<int> cellAbove, cellAtThreshold, cellOffsets;
  Buffer<int> control;            ///< kControlCount
  Buffer<LevelKeypoint> selected; ///< budget
  Buffer<uint8_t> descriptors;    ///< budget * kDescriptorBytes
};

struct OrbSettings {
  int fastThreshold;
  int border;
};

/// Runs every level: level 0's image must hold the input; levels > 0 are resized from it. pattern: device
/// buffer of kPatternPairs * 4 offsets. Results stay in each level's selected/descriptors/control.
void runOrbPipelineCpu(OrbLevelWorkspace* levels, int levelCount, const OrbSettings& settings, const int8_t* pattern);
void runOrbPipelineCuda(OrbLevelWorkspace* levels, int levelCount, const OrbSettings& settings, const int8_t* pattern);
/// The GPU's forms of the two selection scans (ResponseThreshold, CellOffsets): the same integers from one block's
/// parallel prefix sums instead of one thread's loop (38 and 24 us per frame at 960x540 on one GPU thread).
void responseThresholdCuda(const ResponseThreshold& step);
void cellOffsetsCuda(const CellOffsets& step);

/// The k nearest rows of its pair's B for every stacked row of A (HammingKnn); indices/distances: rowsA * k.
void hammingKnnCpu(const HammingKnn& knn, int rowsA);
void hammingKnnCuda(const HammingKnn& knn, int rowsA);

/// Sub-pixel refinement of `count` matches (SubPixelKernels.h); the functor's pointers are on the backend's device.
void refineSubPixelCpu(const subpixel::LucasKanadeRefine& refine, int count);
void refineSubPixelCuda(const subpixel::LucasKanadeRefine& refine, int count);

}  // namespace tissuemosaic::orb
