// The ORB extractor and matcher, written once and instantiated per backend (included by OrbBackendCpu.cpp and
// OrbBackendCuda.cu only).
#include "Core/ParallelFor.h"
#include "OrbPipeline.h"

#include <type_traits>

namespace tissuemosaic::orb {

namespace {

template <class Backend>
void runLevel(OrbLevelWorkspace& w, const OrbSettings& settings, const int8_t* pattern) {
  const int64_t pixels = w.image.view().pixelCount();
  const int cells = w.grid.cellCount();
  parallelFor<Backend>(pixels, SmoothRows{w.image.view(), w.smoothingRows.view()});
  parallelFor<Backend>(pixels, SmoothColumns{w.smoothingRows.view(), w.smoothed.view()});
  parallelFor<Backend>(pixels, FastScores{w.image.view(), w.fastScores.view(), settings.fastThreshold, settings.border});
  parallelFor<Backend>(pixels, MaximaResponses{w.image.view(), w.fastScores.view(), w.responses.view()});
  parallelFor<Backend>(static_cast<int64_t>(cells) * w.grid.cellSize,
                       CellRowBest{w.responses.view(), w.grid, w.rowCandidates.data()}, 64);
  parallelFor<Backend>(cells, CellBest{w.rowCandidates.data(), w.image.view().width, w.grid, w.slots.data()}, 1);
  w.histogram.setZero();
  parallelFor<Backend>(static_cast<int64_t>(w.slots.size()), ResponseHistogram{w.slots.data(), w.histogram.data()});
  const ResponseThreshold threshold{w.histogram.data(), w.control.data(), w.budget};
  if constexpr (std::is_same_v<Backend, CudaBackend>) responseThresholdCuda(threshold);
  else parallelFor<Backend>(1, threshold, 1);
  parallelFor<Backend>(cells, CellCounts{w.slots.data(), w.control.data(), w.grid.perCell, w.cellAbove.data(),
                                         w.cellAtThreshold.data()}, 64);
  const CellOffsets offsets{w.cellAbove.data(), w.cellAtThreshold.data(), w.cellOffsets.data(), w.control.data(), cells};
  if constexpr (std::is_same_v<Backend, CudaBackend>) cellOffsetsCuda(offsets);
  else parallelFor<Backend>(1, offsets, 1);
  parallelFor<Backend>(cells, CellWrite{w.slots.data(), w.control.data(), w.cellAtThreshold.data(),
                                        w.cellOffsets.data(), w.grid.perCell, w.selected.data()}, 64);
  parallelFor<Backend>(w.budget, Describe{w.image.view(), w.smoothed.view(), pattern, w.control.data(),
                                          w.selected.data(), w.descriptors.data()}, 16);
}

template <class Backend>
void runOrbPipeline(OrbLevelWorkspace* levels, int levelCount, const OrbSettings& settings, const int8_t* pattern) {
  for (int l = 0; l < levelCount; ++l) {
    OrbLevelWorkspace& w = levels[l];
    if (l > 0) {
      parallelFor<Backend>(w.image.view().pixelCount(), ResizeBilinear{levels[0].image.view(), w.image.view(), w.scaleQ16});
    }
    runLevel<Backend>(w, settings, pattern);
  }
}

}  // namespace

}  // namespace tissuemosaic::orb
