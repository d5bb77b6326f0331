// The CPU instantiation of the section II pipeline, and the CPU launcher of the ZNCC cost volume.
#include "StereoPipeline.inl"

#include "Core/ParallelFor.h"

#include <algorithm>
#include <vector>

namespace tissuemosaic::stereo {

namespace {

/// Image rows [firstRow, firstRow + rowCount) with replicated borders: rows clamped to the image, each padded on both
/// sides by `margin` replicated pixels, so the inner loops over x need no clamping.
struct PaddedRows {
  int firstRow, margin, stride;
  std::vector<float> values;

  PaddedRows(ImageView<const float> image, int firstRow_, int rowCount, int margin_)
      : firstRow(firstRow_), margin(margin_), stride(image.width + 2 * margin_),
        values(static_cast<std::size_t>(rowCount) * stride) {
    for (int k = 0; k < rowCount; ++k) {
      float* row = values.data() + static_cast<std::size_t>(k) * stride;
      const int sourceY = clampIndex(firstRow + k, image.height);
      for (int c = -margin; c < image.width + margin; ++c) row[c + margin] = image.at(clampIndex(c, image.width), sourceY);
    }
  }
  /// Pointer to column 0 of image row y (clamped rows included).
  const float* row(int y) const { return values.data() + static_cast<std::size_t>(y - firstRow) * stride + margin; }
};

/// Chessboard window sums of one row for x in [xBegin, xEnd) from column sums (even/odd indexed by column c in
/// [xBegin - r, xEnd + r)): S(x) = sum over dx of (dx even ? even : odd)[x + dx]. Grouped for fewer additions: with
/// f the array of offset -r's parity and g the other, G(j) = f(j) + g(j + 1) pairs neighbouring offsets, H(j) =
/// G(j) + G(j + 2) pairs those, and S(x) = H(x - r) + H(x - r + 4) + ... (+ G for odd r) + f(x + r). All values are
/// integers below 2^24, so the grouping changes nothing.
void chessboardWindowSumsRow(const float* even, const float* odd, int r, int xBegin, int xEnd, float* pairs,
                             float* quads, float* sums) {
  const float* __restrict f = (r & 1) ? odd : even;
  const float* __restrict g = (r & 1) ? even : odd;
  float* __restrict G = pairs;
  float* __restrict H = quads;
  const int cBegin = xBegin - r, cEnd = xEnd + r;
  for (int c = cBegin; c < cEnd - 1; ++c) G[c] = f[c] + g[c + 1];
  for (int c = cBegin; c < cEnd - 3; ++c) H[c] = G[c] + G[c + 2];
  float* __restrict out = sums;
  for (int x = xBegin; x < xEnd; ++x) out[x] = f[x + r];
  for (int m = 0; m + 1 < r; m += 2) {
    const float* __restrict term = H + (m * 2 - r);
    for (int x = xBegin; x < xEnd; ++x) out[x] += term[x];
  }
  if (r & 1) {
    const float* __restrict term = G + (2 * (r - 1) - r);
    for (int x = xBegin; x < xEnd; ++x) out[x] += term[x];
  }
}

/// Rows per CPU task of the cost volume: the column sums of each disparity are carried down the band.
constexpr int kBandRows = 16;

/// One band of image rows of the cost volume, every disparity. Per disparity the chessboard column sums of L * R
/// (even and odd rows) start with a full sum at the band's first row and move down by the exact recurrences
/// Ce(y+1) = Co(y) -/+ one product, Co(y+1) = Ce(y) +/- one product (integer-valued floats: no rounding, as in the
/// CUDA kernel); then window sums, the quantised ZNCC (the shared per-pixel function) and the running winners.
struct ZnccVolumeBand {
  const ZnccVolumeInputs& in;

  void operator()(int64_t bandIndex) const {
    const int width = in.left.width, height = in.left.height, r = in.radius;
    const int y0 = static_cast<int>(bandIndex) * kBandRows;
    const int rows = std::min(kBandRows, height - y0);
    const int maxShift = std::max(std::abs(in.minDisparity), std::abs(in.minDisparity + in.disparityCount - 1));
    const PaddedRows left(in.left, y0 - r, rows + 2 * r, r);
    const PaddedRows right(in.right, y0 - r, rows + 2 * r, r + maxShift);
    const int n = chessboardPixelCount(r);
    std::vector<float> evenStore(width + 2 * r), oddStore(width + 2 * r), windowSum(width);
    std::vector<float> pairs(width + 2 * r), quads(width + 2 * r);
    float* __restrict even = evenStore.data() + r;  // even[c] for c in [-r, width + r)
    float* __restrict odd = oddStore.data() + r;
    const std::size_t bandPixels = static_cast<std::size_t>(rows) * width;
    std::vector<int16_t> best(bandPixels, kNoZncc), bestDisparity(bandPixels, kNoDisparity);
    std::vector<int16_t> rightBest(bandPixels, kNoZncc), rightBestDisparity(bandPixels, kNoDisparity);

    for (int i = 0; i < in.disparityCount; ++i) {
      const int d = in.minDisparity + i;
      const int xBegin = std::max(0, d), xEnd = std::min(width, width + d);  // x - d inside the right image
      if (xBegin >= xEnd) {
        for (int k = 0; k < rows; ++k) {
          int16_t* scores = in.volume + in.volumeIndex(i, 0, y0 + k);
          std::fill(scores, scores + width, kNoZncc);
        }
        continue;
      }
      const int cBegin = xBegin - r, cEnd = xEnd + r;
      // Full column sums at the band's first row.
      std::fill(even + cBegin, even + cEnd, 0.0f);
      std::fill(odd + cBegin, odd + cEnd, 0.0f);
      for (int dy = -r; dy <= r; ++dy) {
        const float* __restrict l = left.row(y0 + dy);
        const float* __restrict rr = right.row(y0 + dy) - d;
        float* __restrict target = (dy & 1) == 0 ? even : odd;
        for (int c = cBegin; c < cEnd; ++c) target[c] += l[c] * rr[c];
      }
      for (int k = 0; k < rows; ++k) {
        const int y = y0 + k;
        if (k > 0) {
          // Move the column sums from row y - 1 to row y: row y - 1 - r leaves, row y + r enters.
          const float* __restrict leaveL = left.row(y - 1 - r);
          const float* __restrict leaveR = right.row(y - 1 - r) - d;
          const float* __restrict enterL = left.row(y + r);
          const float* __restrict enterR = right.row(y + r) - d;
          const bool oddRadius = (r & 1) != 0;
          for (int c = cBegin; c < cEnd; ++c) {
            const float leaving = leaveL[c] * leaveR[c], entering = enterL[c] * enterR[c];
            const float e = even[c], o = odd[c];
            even[c] = oddRadius ? o - leaving : o + entering;
            odd[c] = oddRadius ? e + entering : e - leaving;
          }
        }
        chessboardWindowSumsRow(even, odd, r, xBegin, xEnd, pairs.data() + r, quads.data() + r, windowSum.data());
        float* __restrict sums = windowSum.data();
        int16_t* __restrict scores = in.volume + in.volumeIndex(i, 0, y);  // row y's slice for d
        std::fill(scores, scores + xBegin, kNoZncc);
        std::fill(scores + xEnd, scores + width, kNoZncc);
        const float* __restrict sumL = &in.sumLeft.at(0, y);
        const float* __restrict normL = &in.inverseNormLeft.at(0, y);
        const float* __restrict sumR = &in.sumRight.at(0, y) - d;
        const float* __restrict normR = &in.inverseNormRight.at(0, y) - d;
        for (int x = xBegin; x < xEnd; ++x) scores[x] = quantisedZncc(sums[x], sumL[x], sumR[x], normL[x], normR[x], n);
        // Separate loops so they vectorise: the running winners, strictly better (the lowest disparity wins
        // ties), for the left pixel x and for the right pixel x - d.
        int16_t* __restrict bestScore = best.data() + static_cast<std::size_t>(k) * width;
        int16_t* __restrict bestD = bestDisparity.data() + static_cast<std::size_t>(k) * width;
        const int16_t disparity = static_cast<int16_t>(d);
        for (int x = xBegin; x < xEnd; ++x) {
          const int16_t q = scores[x];
          bestD[x] = q > bestScore[x] ? disparity : bestD[x];
          bestScore[x] = q > bestScore[x] ? q : bestScore[x];
        }
        int16_t* __restrict rightScore = rightBest.data() + static_cast<std::size_t>(k) * width - d;
        int16_t* __restrict rightD = rightBestDisparity.data() + static_cast<std::size_t>(k) * width - d;
        for (int x = xBegin; x < xEnd; ++x) {
          const int16_t q = scores[x];
          rightD[x] = q > rightScore[x] ? disparity : rightD[x];
          rightScore[x] = q > rightScore[x] ? q : rightScore[x];
        }
      }
    }
    for (int k = 0; k < rows; ++k) {
      std::copy_n(bestDisparity.data() + static_cast<std::size_t>(k) * width, width, &in.bestDisparity.at(0, y0 + k));
      std::copy_n(rightBestDisparity.data() + static_cast<std::size_t>(k) * width, width,
                  &in.rightBestDisparity.at(0, y0 + k));
    }
  }
};

/// Window statistics of one band of rows: chessboard sums of I and I^2 per pixel (column sums carried down the band
/// as in ZnccVolumeBand, window sums vectorised over x), then the shared windowInverseNorm.
struct WindowStatisticsBand {
  ImageView<const float> image;
  ImageView<float> sum, inverseNorm;
  int radius;
  float minStdDev;

  void operator()(int64_t bandIndex) const {
    const int width = image.width, height = image.height, r = radius;
    const int y0 = static_cast<int>(bandIndex) * kBandRows;
    const int rows = std::min(kBandRows, height - y0);
    const PaddedRows padded(image, y0 - r, rows + 2 * r, r);
    const int n = chessboardPixelCount(r);
    const int columns = width + 2 * r;
    std::vector<float> store(4 * static_cast<std::size_t>(columns)), sums(width), sumsSq(width);
    float* __restrict even = store.data() + r;  // index c in [-r, width + r)
    float* __restrict odd = even + columns;
    float* __restrict evenSq = odd + columns;
    float* __restrict oddSq = evenSq + columns;
    for (int dy = -r; dy <= r; ++dy) {
      const float* __restrict row = padded.row(y0 + dy);
      float* __restrict target = (dy & 1) == 0 ? even : odd;
      float* __restrict targetSq = (dy & 1) == 0 ? evenSq : oddSq;
      for (int c = -r; c < width + r; ++c) {
        target[c] += row[c];
        targetSq[c] += row[c] * row[c];
      }
    }
    const bool oddRadius = (r & 1) != 0;
    for (int k = 0; k < rows; ++k) {
      const int y = y0 + k;
      if (k > 0) {
        const float* __restrict leave = padded.row(y - 1 - r);
        const float* __restrict enter = padded.row(y + r);
        for (int c = -r; c < width + r; ++c) {
          const float e = even[c], o = odd[c], e2 = evenSq[c], o2 = oddSq[c];
          even[c] = oddRadius ? o - leave[c] : o + enter[c];
          odd[c] = oddRadius ? e + enter[c] : e - leave[c];
          evenSq[c] = oddRadius ? o2 - leave[c] * leave[c] : o2 + enter[c] * enter[c];
          oddSq[c] = oddRadius ? e2 + enter[c] * enter[c] : e2 - leave[c] * leave[c];
        }
      }
      float* __restrict s = sums.data();
      float* __restrict s2 = sumsSq.data();
      std::fill(s, s + width, 0.0f);
      std::fill(s2, s2 + width, 0.0f);
      for (int dx = -r; dx <= r; ++dx) {
        const float* __restrict column = ((dx & 1) == 0 ? even : odd) + dx;
        const float* __restrict columnSq = ((dx & 1) == 0 ? evenSq : oddSq) + dx;
        for (int x = 0; x < width; ++x) {
          s[x] += column[x];
          s2[x] += columnSq[x];
        }
      }
      float* __restrict outSum = &sum.at(0, y);
      float* __restrict outNorm = &inverseNorm.at(0, y);
      for (int x = 0; x < width; ++x) {
        outSum[x] = s[x];
        outNorm[x] = windowInverseNorm(s[x], s2[x], n, minStdDev);
      }
    }
  }
};

/// Nearest estimate along ray direction k for every pixel, within radius steps and inside the image: the hit at p
/// is p + delta itself when that carries an estimate, else the hit at p + delta one step further. One sweep in the
/// order that visits p + delta before p gives every ray walk's answer at O(1) per pixel.
/// A task is one direction and one band of rows, so that more than 8 threads have work. A band of a direction that
/// steps across rows starts its sweep `radius` rows early (knowing nothing before that): a hit is never farther than
/// radius, so the band's own rows come out exactly as from one sweep over the image. Rows outside the band are kept
/// in two row buffers and never written.
struct NearestAlongRay {
  ImageView<const int16_t> input;
  int radius;
  int rowBands;
  int16_t* hitDistance;  ///< [8][pixels]; 0 = none
  int16_t* hitValue;

  void operator()(int64_t task) const {
    const int k = static_cast<int>(task % 8), band = static_cast<int>(task / 8);
    int dx, dy;
    radialDirection(k, dx, dy);
    const int width = input.width, height = input.height;
    const int64_t offset = static_cast<int64_t>(k) * input.pixelCount();
    int16_t* __restrict distance = hitDistance + offset;
    int16_t* __restrict value = hitValue + offset;
    // The band's rows as steps of the sweep (step s is row height - 1 - s when dy > 0, else row s).
    const int bandBegin = static_cast<int>(static_cast<int64_t>(height) * band / rowBands);
    const int bandEnd = static_cast<int>(static_cast<int64_t>(height) * (band + 1) / rowBands);
    const int firstStep = dy == 0 ? bandBegin : std::max(0, bandBegin - radius);
    std::vector<int16_t> rows(4 * static_cast<std::size_t>(width));
    int16_t* previousDistance = rows.data();  // the row swept before (the neighbours' row when dy != 0)
    int16_t* previousValue = previousDistance + width;
    int16_t* rowDistance = previousValue + width;
    int16_t* rowValue = rowDistance + width;
    std::fill(previousDistance, previousDistance + width, int16_t{0});  // nothing known before the first step
    for (int step = firstStep; step < bandEnd; ++step) {
      const int y = dy > 0 ? height - 1 - step : step;  // rows: the neighbour's row first
      for (int i = 0; i < width; ++i) {
        const int x = dx > 0 ? width - 1 - i : i;  // within a row, for dy == 0: the neighbour first
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= width || ny >= height) {
          rowDistance[x] = 0;
          continue;
        }
        const int16_t neighbour = input[static_cast<int64_t>(ny) * width + nx];
        // The neighbour's own hit: in this row (dy == 0, swept already) or in the row swept before.
        const int16_t* neighbourDistance = dy == 0 ? rowDistance : previousDistance;
        const int16_t* neighbourValue = dy == 0 ? rowValue : previousValue;
        if (neighbour != kNoDisparity) {
          rowDistance[x] = 1;
          rowValue[x] = neighbour;
        } else if (neighbourDistance[nx] > 0 && neighbourDistance[nx] < radius) {
          rowDistance[x] = static_cast<int16_t>(neighbourDistance[nx] + 1);
          rowValue[x] = neighbourValue[nx];
        } else {
          rowDistance[x] = 0;
        }
      }
      if (step >= bandBegin) {
        const int64_t rowStart = static_cast<int64_t>(y) * width;
        std::copy(rowDistance, rowDistance + width, distance + rowStart);
        std::copy(rowValue, rowValue + width, value + rowStart);
      }
      std::swap(previousDistance, rowDistance);
      std::swap(previousValue, rowValue);
    }
  }
};

}  // namespace

void fillHolesRadialCpu(ImageView<const int16_t> input, ImageView<int16_t> output, int radius, int minLines,
                        float maxEndDifferencePx, int16_t* hitDistance, int16_t* hitValue, int rowBands) {
  // 8 directions give 8 tasks: with more threads than that, cut each direction into bands of rows (each band
  // sweeps radius rows more, so only where threads would otherwise idle).
  if (rowBands <= 0) rowBands = std::max(1, (cpuThreadCount() + 7) / 8);
  rowBands = std::min(rowBands, std::max(1, input.height));
  parallelFor<CpuBackend>(8 * static_cast<int64_t>(rowBands),
                          NearestAlongRay{input, radius, rowBands, hitDistance, hitValue}, 1);
  parallelFor<CpuBackend>(input.pixelCount(),
                          FillHolesRadialFromHits{input, output, hitDistance, hitValue, minLines, maxEndDifferencePx});
}

void computeWindowStatisticsCpu(ImageView<const float> image, ImageView<float> sum, ImageView<float> inverseNorm,
                                int radius, float minStdDev) {
  parallelFor<CpuBackend>((image.height + kBandRows - 1) / kBandRows,
                          WindowStatisticsBand{image, sum, inverseNorm, radius, minStdDev}, 1);
}

void computeZnccVolumeCpu(const ZnccVolumeInputs& inputs) {
  parallelFor<CpuBackend>((inputs.left.height + kBandRows - 1) / kBandRows, ZnccVolumeBand{inputs}, 1);
}

void runStereoPipelineCpu(StereoWorkspace& workspace, const StereoParameters& parameters, StereoTimingsMs& timings) {
  runStereoPipeline<CpuBackend>(workspace, parameters, timings, computeZnccVolumeCpu);
}

}  // namespace tissuemosaic::stereo
