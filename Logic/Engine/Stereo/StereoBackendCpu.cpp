// The CPU instantiation of the section II pipeline, and the CPU launcher of the ZNCC cost volume.
#include "StereoPipeline.inl"

#include <algorithm>
#include <vector>

namespace tissuemosaic::stereo {

namespace {

/// Rows y-r..y+r of an image, each padded on both sides by `margin` replicated pixels, so the inner loops over x
/// need no clamping.
struct PaddedRows {
  int radius, margin, stride;
  std::vector<float> values;

  PaddedRows(ImageView<const float> image, int y, int radius_, int margin_)
      : radius(radius_), margin(margin_), stride(image.width + 2 * margin_),
        values(static_cast<std::size_t>(2 * radius_ + 1) * stride) {
    for (int dy = -radius; dy <= radius; ++dy) {
      float* row = values.data() + static_cast<std::size_t>(dy + radius) * stride;
      const int sourceY = clampIndex(y + dy, image.height);
      for (int c = -margin; c < image.width + margin; ++c) row[c + margin] = image.at(clampIndex(c, image.width), sourceY);
    }
  }
  /// Pointer to column 0 of row offset dy.
  const float* row(int dy) const { return values.data() + static_cast<std::size_t>(dy + radius) * stride + margin; }
};

/// One image row of the cost volume, every disparity: column sums of L * R(shifted) into even/odd arrays, then the
/// chessboard window sums and the quantised ZNCC (same per-pixel functions as the CUDA kernel).
struct ZnccVolumeRow {
  const ZnccVolumeInputs& in;

  void operator()(int64_t rowIndex) const {
    const int y = static_cast<int>(rowIndex);
    const int width = in.left.width, r = in.radius;
    const int maxShift = std::max(std::abs(in.minDisparity), std::abs(in.minDisparity + in.disparityCount - 1));
    const PaddedRows left(in.left, y, r, r);
    const PaddedRows right(in.right, y, r, r + maxShift);
    const int n = chessboardPixelCount(r);
    std::vector<float> evenStore(width + 2 * r), oddStore(width + 2 * r);
    float* even = evenStore.data() + r;  // even[c] for c in [-r, width + r)
    float* odd = oddStore.data() + r;
    std::vector<float> windowSum(width);
    std::vector<int16_t> best(width, kNoZncc);
    std::vector<int16_t> bestDisparity(width, kNoDisparity);
    const float* sumL = &in.sumLeft.at(0, y);
    const float* normL = &in.inverseNormLeft.at(0, y);
    const float* sumR = &in.sumRight.at(0, y);
    const float* normR = &in.inverseNormRight.at(0, y);

    std::vector<int16_t> rightBest(width, kNoZncc);
    std::vector<int16_t> rightBestDisparity(width, kNoDisparity);
    for (int i = 0; i < in.disparityCount; ++i) {
      const int d = in.minDisparity + i;
      int16_t* __restrict scores = in.volume + in.volumeIndex(i, 0, y);  // this row's slice for d
      const int xBegin = std::max(0, d), xEnd = std::min(width, width + d);  // x - d inside the right image
      std::fill(scores, scores + width, kNoZncc);
      if (xBegin >= xEnd) continue;
      const int cBegin = xBegin - r, cEnd = xEnd + r;
      std::fill(even + cBegin, even + cEnd, 0.0f);
      std::fill(odd + cBegin, odd + cEnd, 0.0f);
      for (int dy = -r; dy <= r; ++dy) {
        const float* __restrict l = left.row(dy);
        const float* __restrict rr = right.row(dy) - d;
        float* __restrict target = (dy & 1) == 0 ? even : odd;
        for (int c = cBegin; c < cEnd; ++c) target[c] += l[c] * rr[c];
      }
      // Window sums: columns x+dx with dx even add their even-row sums, dx odd their odd-row sums.
      float* __restrict sums = windowSum.data();
      std::fill(sums + xBegin, sums + xEnd, 0.0f);
      for (int dx = -r; dx <= r; ++dx) {
        const float* __restrict column = ((dx & 1) == 0 ? even : odd) + dx;
        for (int x = xBegin; x < xEnd; ++x) sums[x] += column[x];
      }
      const float* sumRShifted = sumR - d;
      const float* normRShifted = normR - d;
      for (int x = xBegin; x < xEnd; ++x) {
        scores[x] = quantisedZncc(sums[x], sumL[x], sumRShifted[x], normL[x], normRShifted[x], n);
      }
      // Separate loops so they vectorise: the running winners, strictly better (the lowest disparity wins ties),
      // for the left pixel x and for the right pixel x - d.
      int16_t* __restrict bestScore = best.data();
      int16_t* __restrict bestD = bestDisparity.data();
      const int16_t disparity = static_cast<int16_t>(d);
      for (int x = xBegin; x < xEnd; ++x) {
        const int16_t q = scores[x];
        bestD[x] = q > bestScore[x] ? disparity : bestD[x];
        bestScore[x] = q > bestScore[x] ? q : bestScore[x];
      }
      int16_t* __restrict rightScore = rightBest.data() - d;
      int16_t* __restrict rightD = rightBestDisparity.data() - d;
      for (int x = xBegin; x < xEnd; ++x) {
        const int16_t q = scores[x];
        rightD[x] = q > rightScore[x] ? disparity : rightD[x];
        rightScore[x] = q > rightScore[x] ? q : rightScore[x];
      }
    }
    std::copy(rightBestDisparity.begin(), rightBestDisparity.end(), &in.rightBestDisparity.at(0, y));
    std::copy(bestDisparity.begin(), bestDisparity.end(), &in.bestDisparity.at(0, y));
  }
};

}  // namespace

void computeZnccVolumeCpu(const ZnccVolumeInputs& inputs) {
  parallelFor<CpuBackend>(inputs.left.height, ZnccVolumeRow{inputs}, 1);
}

void runStereoPipelineCpu(StereoWorkspace& workspace, const StereoParameters& parameters, StereoTimingsMs& timings) {
  runStereoPipeline<CpuBackend>(workspace, parameters, timings, computeZnccVolumeCpu);
}

}  // namespace tissuemosaic::stereo
