// The section II pipeline, written once and instantiated per backend (included by StereoBackendCpu.cpp and
// StereoBackendCuda.cu only).
#include "Core/Error.h"
#include "Core/ParallelFor.h"
#include "Core/StageClock.h"
#include "AdCensusKernels.h"
#include "HighlightKernels.h"
#include "StereoPipeline.h"
#if defined(__CUDACC__)
#include "BoxFilterCuda.cuh"
#endif

#include <algorithm>
#include <cmath>
#include <memory>
#include <type_traits>
#include <vector>

namespace tissuemosaic::stereo {

/// The steps whose loop structure differs by backend (StereoPipeline.h's compute*Cpu and compute*Cuda).
struct BackendLaunchers {
  void (*znccVolume)(const ZnccVolumeInputs&);
  void (*scanlinePaths)(const ScanlineInputs&);
  void (*highlightSeeds)(const DetectHighlightSeeds&);
};

template <class Backend>
void runStereoPipeline(StereoWorkspace& w, const StereoParameters& p, StereoTimingsMs& timings,
                       const BackendLaunchers& launch, StereoExplanation* explanation);

namespace {

/// The robust functions 1 - exp(-c / lambda) in cost units, rounded.
AdCensusCostTables makeAdCensusCostTables(const StereoParameters& p) {
  AdCensusCostTables tables{};
  const auto robust = [](double c, double lambda) {
    return static_cast<int32_t>(std::lround(kAdCensusCostUnit * (1.0 - std::exp(-c / lambda))));
  };
  for (int bits = 0; bits <= kCensusMaxBits; ++bits) tables.census[bits] = robust(bits, p.censusLambda);
  for (int grey = 0; grey < 256; ++grey) tables.absoluteDifference[grey] = robust(grey, p.absoluteDifferenceLambda);
  return tables;
}

/// P1 and P2 in cost units: full where neither image has an edge along the step, a quarter where one has, a tenth
/// where both have (Mei et al.).
PathPenalties makePathPenalties(const StereoParameters& p) {
  PathPenalties penalties{};
  const double divisors[3] = {1.0, 4.0, 10.0};
  for (int edges = 0; edges < 3; ++edges) {
    penalties.small[edges] = static_cast<int32_t>(std::lround(kAdCensusCostUnit * p.pathPenaltySmall / divisors[edges]));
    penalties.large[edges] = static_cast<int32_t>(std::lround(kAdCensusCostUnit * p.pathPenaltyLarge / divisors[edges]));
  }
  return penalties;
}

/// Columns per CPU task of AD-Census's vertical aggregation passes (their prefix sums, 16 x 541 x 101 x 8 bytes at
/// 960x540, stay in cache for the windows that read them).
constexpr int kCpuAggregationColumnBlock = 16;

/// Estimates in a discrete or float map, counted on the host (explanations only: it downloads the map).
long countEstimates(const Image<int16_t>& map) {
  const std::vector<int16_t> values = map.buffer().toHost();
  return static_cast<long>(std::count_if(values.begin(), values.end(), [](int16_t d) { return d != kNoDisparity; }));
}
long countEstimates(const Image<float>& map) {
  const std::vector<float> values = map.buffer().toHost();
  return static_cast<long>(std::count_if(values.begin(), values.end(), [](float d) { return std::isfinite(d); }));
}

template <class Backend>
struct PipelineSteps {
  StereoWorkspace& w;
  const StereoParameters& p;
  const BackendLaunchers& launch;
  StereoExplanation* explain;  ///< null: count nothing (the normal path)
  int64_t pixels() const { return static_cast<int64_t>(w.width) * w.height; }

  /// Explanation of the matching step: pixels without a winner (no candidate match inside the right image, or
  /// textureless windows; AD-Census has a winner everywhere), winners near the range's ends, and winners the
  /// left-right check removed.
  void explainWinners() {
    const std::vector<int16_t> winners = w.znccDisparity.buffer().toHost();
    const std::vector<float> inverseNorm = w.paper() ? w.inverseNormLeft.buffer().toHost() : std::vector<float>();
    const KeepWinners keep = keepWinners();
    long outside = 0, textureless = 0, withWinner = 0, nearRangeEnd = 0;
    for (int64_t i = 0; i < pixels(); ++i) {
      if (winners[i] != kNoDisparity) {
        ++withWinner;
        if (keep.nearRangeEnd(winners[i])) ++nearRangeEnd;
        continue;
      }
      const int x = static_cast<int>(i % w.width);
      // Candidates x - d, d in [min, max]: none inside [0, width) when x - min < 0 or x - max > width - 1.
      const bool noCandidateInside = x - p.minDisparityPx < 0 || x - p.maxDisparityPx > w.width - 1;
      const bool leftTextureless = !inverseNorm.empty() && inverseNorm[i] == 0.0f;
      if (noCandidateInside && !leftTextureless) ++outside;
      else ++textureless;
    }
    explain->pixels = pixels();
    explain->outsideRightImage = outside;
    explain->texturelessWindow = textureless;
    explain->rangeEnd = nearRangeEnd;
    explain->leftRightCheck = withWinner - nearRangeEnd - countEstimates(w.discrete);
  }

  void windowStatistics(Image<float>& image, Image<float>& sum, Image<float>& inverseNorm) {
    if constexpr (std::is_same_v<Backend, CpuBackend>) {
      computeWindowStatisticsCpu(image.view(), sum.view(), inverseNorm.view(), p.znccRadiusPx(), p.minWindowStdDev);
    } else {
      parallelFor<Backend>(pixels(), WindowColumnSums{image.view(), w.columnEven.view(), w.columnOdd.view(),
                                                      w.columnEvenSq.view(), w.columnOddSq.view(), p.znccRadiusPx()});
      parallelFor<Backend>(pixels(), WindowStatistics{w.columnEven.view(), w.columnOdd.view(), w.columnEvenSq.view(),
                                                      w.columnOddSq.view(), sum.view(), inverseNorm.view(),
                                                      p.znccRadiusPx(), p.minWindowStdDev});
    }
  }

  /// Box sums of value over radius, handed per pixel to consumer(index, sum, count): running sums on the CPU
  /// (rows, then row-contiguous blocks of columns), shared-memory tiles on the GPU (direct per-pixel passes where a
  /// tile does not fit); exact integers, so all give the same result.
  template <class Value, class Consumer>
  void boxSums(const Value& value, int radius, const Consumer& consumer) {
    if constexpr (std::is_same_v<Backend, CpuBackend>) {
      parallelFor<Backend>(w.height, BoxRowSums<Value>{value, w.width, radius, w.rowSum.data(), w.rowCount.data()}, 1);
      using ColumnSums = BoxColumnSums<kCpuBoxColumnBlock, Consumer>;
      parallelFor<Backend>(ColumnSums::taskCount(w.width),
                           ColumnSums{w.rowSum.data(), w.rowCount.data(), w.width, w.height, radius, consumer}, 1);
    } else {
#if defined(__CUDACC__)
      if (boxFilterTiledCuda(value, radius, consumer, w.width, w.height)) return;
#endif
      parallelFor<Backend>(pixels(), BoxRowSumsDirect<Value>{value, w.width, radius, w.rowSum.data(), w.rowCount.data()});
      parallelFor<Backend>(pixels(), BoxColumnSumsDirect<Consumer>{w.rowSum.data(), w.rowCount.data(), w.width,
                                                                   w.height, radius, consumer});
    }
  }

  /// Runs a discrete-map step from w.discrete into w.discreteScratch, then swaps them.
  template <class Step>
  void discreteStep(const Step& step) {
    parallelFor<Backend>(pixels(), step);
    std::swap(w.discrete, w.discreteScratch);
  }

  /// w.discrete = the left winners without those near the range's ends or failing the left-right check, where
  /// those tests are on (KeepWinners).
  void keptWinners() {
    parallelFor<Backend>(pixels(), keepWinners());
  }
  KeepWinners keepWinners() const {
    return KeepWinners{w.znccDisparity.view(), w.rightZnccDisparity.view(), w.discrete.view(), p.minDisparityPx,
                       p.maxDisparityPx, p.rangeEndMarginPx, p.leftRightMaxDifferencePx};
  }

  bool specularMasking() const { return p.specularMinGrey <= 255.0f; }

  ZnccVolumeInputs znccVolumeInputs() {
    return ZnccVolumeInputs{w.left.view(), w.right.view(), w.sumLeft.view(), w.inverseNormLeft.view(),
                            w.sumRight.view(), w.inverseNormRight.view(), p.znccRadiusPx(), p.minDisparityPx,
                            p.disparityCount(), w.volume.data(), w.volumeLayout(), w.znccDisparity.view(),
                            w.rightZnccDisparity.view(), w.rightWinnerKeys.data()};
  }

  /// The guided search (GuidedSearchKernels.h) where the half-resolution pair holds a matching window, else the
  /// exhaustive one. Guided: the whole section II at half resolution (exhaustive over the halved range), its filled
  /// disparities as each pixel's prior, the windows' cells, the whole range where a window failed, and the right-view
  /// winners from the volume.
  void znccVolume() {
    const int coarseWidth = (w.width + 1) / 2, coarseHeight = (w.height + 1) / 2;
    const bool guided = p.search == StereoSearch::Guided && coarseWidth >= p.znccWindowPx &&
                        coarseHeight >= p.znccWindowPx;
    w.lastSearchGuided = guided;
    if (!guided) {
      launch.znccVolume(znccVolumeInputs());
      return;
    }
    const StereoParameters coarseParameters = guidedCoarseParameters(p);
    if (!w.guided || w.guided->coarse->disparityCount != coarseParameters.disparityCount()) {
      w.guided = std::make_unique<GuidedWorkspace>(w.device, w.width, w.height, coarseParameters.disparityCount());
    }
    GuidedWorkspace& g = *w.guided;
    StereoWorkspace& coarse = *g.coarse;
    parallelFor<Backend>(coarseWidth * static_cast<int64_t>(coarseHeight),
                         HalveGrey{w.leftGrey.view(), w.rightGrey.view(), coarse.leftGrey.view(), coarse.rightGrey.view()});
    StereoTimingsMs coarseTimings;
    runStereoPipeline<Backend>(coarse, coarseParameters, coarseTimings, launch, nullptr);
    parallelFor<Backend>(pixels(), CandidateWindows{coarse.filledDisparity.view(), g.windowLow.view(),
                                                    g.windowHigh.view(), p.minDisparityPx, p.maxDisparityPx,
                                                    kGuidedWindowMarginPx});
    ScoreGuidedCells score{w.left.view(), w.right.view(), w.sumLeft.view(), w.inverseNormLeft.view(),
                           w.sumRight.view(), w.inverseNormRight.view(), p.znccRadiusPx(), p.minDisparityPx,
                           p.disparityCount(), w.volume.data(), w.volumeLayout(), g.windowLow.view(),
                           g.windowHigh.view(), w.znccDisparity.view(), g.fellBack.view(), false};
    parallelFor<Backend>(pixels(), score);
    score.fallbackPass = true;
    parallelFor<Backend>(pixels(), score);
    parallelFor<Backend>(pixels(), RightWinnersFromVolume{w.volume.data(), w.volumeLayout(), p.minDisparityPx,
                                                          p.disparityCount(), w.rightZnccDisparity.view()});
  }

  /// The highlight masks of both eyes: the seeds (HighlightKernels.h), tested at the disparity of each view's own
  /// winners (w.discrete, the left winners after the left-right check, and the right-view winners), grown by
  /// specularMarginPx.
  void specularMasks() {
    // The ring lies just beyond the matching windows that see the spot.
    const int windowRadius = w.paper() ? p.znccRadiusPx() : std::max(p.censusWidthPx, p.censusHeightPx) / 2;
    const HighlightRule rule{p.specularMinGrey, p.specularMaxRadiusPx, windowRadius + 1, p.specularMinContrastGrey,
                             p.specularViewToleranceGrey};
    launch.highlightSeeds(DetectHighlightSeeds{w.left.view(), w.right.view(), w.discrete.view(),
                                               w.rightZnccDisparity.view(), w.leftHighlightSeeds.view(),
                                               w.rightHighlightSeeds.view(), rule});
    boxSums(DiscreteDisparityValue{w.leftHighlightSeeds.view()}, p.specularMarginPx,
            MarkNearHighlight{w.leftNearHighlight.view()});
    boxSums(DiscreteDisparityValue{w.rightHighlightSeeds.view()}, p.specularMarginPx,
            MarkNearHighlight{w.rightNearHighlight.view()});
    boxSums(DiscreteDisparityValue{w.leftHighlightSeeds.view()}, p.trackingHighlightMarginPx,
            MarkHighlightNeighbourhood{w.highlightNeighbourhood.view()});
  }

  /// The disparity for tracking and fusion (DisparityAwayFromHighlights): with highlight removal off the
  /// neighbourhood is all 0 and this is a copy.
  void awayFromHighlights() {
    parallelFor<Backend>(pixels(), DisparityAwayFromHighlights{w.smoothed.view(), w.highlightNeighbourhood.view(),
                                                               w.awayFromHighlights.view()});
  }

  void outliersAndHoles() {
    keptWinners();
    if (explain) explainWinners();
    long estimates = explain ? countEstimates(w.discrete) : 0;
    /// With an explanation: the change in the number of estimates since the last call.
    const auto estimatesChange = [&]() {
      const long now = countEstimates(w.discrete), change = now - estimates;
      estimates = now;
      return change;
    };
    if (specularMasking()) {
      specularMasks();
      parallelFor<Backend>(pixels(), DropHighlightDiscrete{w.leftNearHighlight.view(), w.rightNearHighlight.view(),
                                                           w.discrete.view()});
      if (explain) explain->highlight = -estimatesChange();
    }
    for (int iteration = 0; iteration < p.outlierIterations; ++iteration) {
      const int radius = p.outlierRadiusStartPx + iteration * p.outlierRadiusStepPx;
      if constexpr (std::is_same_v<Backend, CpuBackend>) {
        removeOutliersCpu(w.discrete.view(), w.discreteScratch.view(), radius, p.outlierSmoothnessPx, w.rayPasses.data());
        std::swap(w.discrete, w.discreteScratch);
      } else {
        discreteStep(RemoveOutliers{w.discrete.view(), w.discreteScratch.view(), radius, p.outlierSmoothnessPx});
      }
      if (explain) explain->outlierSweeps -= estimatesChange();
      const float gate = p.holeMaxEdgeDifferencePx < 0 ? 1e9f : p.holeMaxEdgeDifferencePx;
      if (p.holeRadialRadiusPx > 0) {
        if constexpr (std::is_same_v<Backend, CpuBackend>) {
          fillHolesRadialCpu(w.discrete.view(), w.discreteScratch.view(), p.holeRadialRadiusPx, p.holeRadialMinLines,
                             gate, w.radialHitDistance.data(), w.radialHitValue.data());
          std::swap(w.discrete, w.discreteScratch);
        } else {
          discreteStep(FillHolesRadial{w.discrete.view(), w.discreteScratch.view(), p.holeRadialRadiusPx,
                                       p.holeRadialMinLines, gate});
        }
      }
      if (p.holeDiscRadiusPx > 0) {
        boxSums(DiscreteDisparityValue{w.discrete.view()}, p.holeDiscRadiusPx,
                FillHolesDisc{w.discrete.view(), w.discreteScratch.view(), p.holeDiscRadiusPx,
                              p.holeDiscMinValidFraction});
        std::swap(w.discrete, w.discreteScratch);
      }
      if (explain) explain->filledBack += estimatesChange();
    }
    if (explain) explain->notFilled = pixels() - estimates;
  }

  void refinement() {
    parallelFor<Backend>(pixels(), InitialiseSmoothed{w.discrete.view(), w.smoothed.view()});
    for (int iteration = 0; iteration < p.refineIterations; ++iteration) {
      std::swap(w.smoothed, w.smoothedPrevious);
      boxSums(DiscreteDisparityValue{w.discrete.view()}, p.refineRadiusPx,
              LaplacianStep{w.discrete.view(), w.smoothedPrevious.view(), w.smoothed.view(), w.correction.view(),
                            p.refineAlpha});
      ReselectDiscrete reselect{w.volume.data(), w.volumeLayout(), p.minDisparityPx, p.disparityCount(),
                                p.refineSearchPx, p.refineEta, w.smoothed.view(), w.discrete.view()};
      if (specularMasking()) {
        reselect.leftHighlights = w.leftNearHighlight.view();
        reselect.rightHighlights = w.rightNearHighlight.view();
      }
      if constexpr (std::is_same_v<Backend, CpuBackend>) {
        boxSums(FloatValue{w.correction.view()}, p.refineRadiusPx, ReselectDiscreteRows{reselect});
      } else {
        boxSums(FloatValue{w.correction.view()}, p.refineRadiusPx, reselect);
      }
    }
    if (p.refineMaxDeviationPx >= 0) {
      parallelFor<Backend>(pixels(), FinalDisparity{w.discrete.view(), w.smoothed.view(), p.refineMaxDeviationPx});
    }
    const long beforeBorderCheck = explain ? countEstimates(w.smoothed) : 0;
    parallelFor<Backend>(pixels(), DropOutsideRightView{w.smoothed.view(), p.znccRadiusPx()});
    if (explain) {
      explain->estimated = countEstimates(w.smoothed);
      explain->outsideRightImage += beforeBorderCheck - explain->estimated;
    }
  }

  // AD-Census (AdCensusKernels.h): cost and aggregation; scanline optimisation and winners; median, left-right
  // check and highlights.
  /// An AD-Census element functor over the whole volume: by rows on the CPU, by elements on the GPU.
  template <class ElementFunctor>
  void forEachVolumeElement(const VolumeGeometry& g, const ElementFunctor& f) {
    if constexpr (std::is_same_v<Backend, CpuBackend>) {
      parallelFor<Backend>(g.height, VolumeRows<ElementFunctor>{g, f}, 1);
    } else {
      parallelFor<Backend>(g.elementCount(), VolumeElements<ElementFunctor>{g, f});
    }
  }

  VolumeGeometry adCensusGeometry() const { return {w.width, w.height, p.minDisparityPx, p.disparityCount()}; }

  void adCensusCostAndAggregation() {
    AdCensusWorkspace& a = *w.adCensus;
    const VolumeGeometry g = adCensusGeometry();
    const int halfWidth = p.censusWidthPx / 2, halfHeight = p.censusHeightPx / 2;
    parallelFor<Backend>(pixels(), CensusTransform{w.leftGrey.view(), a.leftCensus.data(), halfWidth, halfHeight});
    parallelFor<Backend>(pixels(), CensusTransform{w.rightGrey.view(), a.rightCensus.data(), halfWidth, halfHeight});
    parallelFor<Backend>(pixels(), CrossArms{w.leftGrey.view(), a.leftArms.data(), p.armMaxPx, p.armLongPx,
                                             p.armLimitGrey, p.armLongLimitGrey});
    parallelFor<Backend>(pixels(), CrossArms{w.rightGrey.view(), a.rightArms.data(), p.armMaxPx, p.armLongPx,
                                             p.armLimitGrey, p.armLongLimitGrey});
    forEachVolumeElement(g, AdCensusCost{g, w.leftGrey.view(), w.rightGrey.view(), a.leftCensus.data(),
                                         a.rightCensus.data(), makeAdCensusCostTables(p), a.cost.data()});
    for (int iteration = 0; iteration < p.aggregationIterations; ++iteration) {
      const bool horizontalFirst = iteration % 2 == 0;  // Mei et al. alternate the order
      for (int pass = 0; pass < 2; ++pass) {
        const AggregationLines lines{g, (pass == 0) == horizontalFirst};
        const PrefixAlongLines prefix{lines, pass == 0 ? a.cost.data() : nullptr,
                                      pass == 0 ? nullptr : a.packedWindows.data(), a.prefix.data()};
        const WindowAlongLines window{lines, a.leftArms.data(), a.rightArms.data(), a.prefix.data(),
                                      pass == 0 ? a.packedWindows.data() : nullptr,
                                      pass == 0 ? nullptr : a.cost.data()};
        if constexpr (std::is_same_v<Backend, CpuBackend>) {
          // A task's prefix sums, then its windows while those sums are still in cache (the windows read them at
          // rows and columns that vary with each pixel's arms: from memory they waited on every load). Rows one per
          // task; columns in blocks, which lie side by side in memory at each row.
          const int block = lines.horizontal ? 1 : kCpuAggregationColumnBlock;
          parallelFor<Backend>((lines.lineCount() + block - 1) / block, [prefix, window, block, lines](int64_t task) {
            const int first = static_cast<int>(task) * block, end = std::min(first + block, lines.lineCount());
            prefix.lineBlock(first, end);
            window.lineBlock(first, end);
          }, 1);
        } else {
          parallelFor<Backend>(static_cast<int64_t>(lines.lineCount()) * g.disparityCount, prefix);
          forEachVolumeElement(g, window);
        }
      }
    }
  }

  void adCensusPathsAndWinners() {
    AdCensusWorkspace& a = *w.adCensus;
    const VolumeGeometry g = adCensusGeometry();
    launch.scanlinePaths(ScanlineInputs{g, w.leftGrey.view(), w.rightGrey.view(), a.cost.data(), a.pathCost.data(),
                                        makePathPenalties(p), p.pathEdgeGrey});
    parallelFor<Backend>(pixels(), AdCensusWinners{g, a.pathCost.data(), w.znccDisparity.view(),
                                                   w.rightZnccDisparity.view(), w.correction.view()});
  }

  void adCensusFinish() {
    parallelFor<Backend>(pixels(), Median3x3{w.correction.view(), w.smoothed.view()});
    keptWinners();
    if (explain) explainWinners();
    // Always: pixels without a winner (uniform costs) are dropped even where the left-right check is off.
    parallelFor<Backend>(pixels(), DropWhereNoDiscrete{w.discrete.view(), w.smoothed.view()});
    const long beforeHighlights = explain ? countEstimates(w.smoothed) : 0;
    if (specularMasking()) {
      specularMasks();
      parallelFor<Backend>(pixels(), DropHighlightFloat{w.leftNearHighlight.view(), w.rightNearHighlight.view(),
                                                        w.smoothed.view()});
    }
    if (explain) {
      explain->estimated = countEstimates(w.smoothed);
      explain->highlight = beforeHighlights - explain->estimated;
      explain->notFilled = pixels() - explain->estimated;
    }
  }
};

}  // namespace

template <class Backend>
void runStereoPipeline(StereoWorkspace& w, const StereoParameters& p, StereoTimingsMs& timings,
                       const BackendLaunchers& launch, StereoExplanation* explanation) {
  require(w.method == p.method && w.disparityCount == p.disparityCount(),
          "internal: the stereo workspace was made for other parameters");
  if (explanation) *explanation = StereoExplanation{};
  PipelineSteps<Backend> steps{w, p, launch, explanation};
  StageClock clock(w.device);

  parallelFor<Backend>(steps.pixels(), GreyToFloat{w.leftGrey.view(), w.rightGrey.view(), w.left.view(), w.right.view()});
  if (!steps.specularMasking()) w.highlightNeighbourhood.buffer().setZero();  // no seeds: nothing to leave out

  if (p.method == StereoMethod::AdCensus) {
    // The same three timed stages: cost and aggregation; scanline optimisation and winners; median, checks.
    steps.adCensusCostAndAggregation();
    clock.mark();
    steps.adCensusPathsAndWinners();
    clock.mark();
    steps.adCensusFinish();
    w.filledDisparity.buffer().copyFrom(w.discrete.buffer());
    steps.awayFromHighlights();
    clock.mark();
  } else {
    steps.windowStatistics(w.left, w.sumLeft, w.inverseNormLeft);
    steps.windowStatistics(w.right, w.sumRight, w.inverseNormRight);
    steps.znccVolume();
    clock.mark();

    steps.outliersAndHoles();
    w.filledDisparity.buffer().copyFrom(w.discrete.buffer());
    clock.mark();

    steps.refinement();
    steps.awayFromHighlights();
    clock.mark();
  }
  parallelFor<Backend>(w.height, CountRangeEndWinners{w.znccDisparity.view(), p.minDisparityPx, p.maxDisparityPx,
                                                      w.rangeEndRowCounts.data()}, 1);
  const std::vector<double> stageMs = clock.stageMilliseconds();  // waits for the device
  timings.zncc = stageMs[0];
  timings.outliersHoles = stageMs[1];
  timings.refinement = stageMs[2];
}

}  // namespace tissuemosaic::stereo
