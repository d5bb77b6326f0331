// The CPU launcher of AD-Census's scanline optimisation: one task per path, the recurrence carried along the path
// in two rows of disparities.
#include "Core/ParallelFor.h"
#include "StereoPipeline.h"

#include <algorithm>
#include <climits>
#include <vector>

namespace tissuemosaic::stereo {

namespace {

struct ScanlinePathCpu {
  ScanlineInputs in;
  ScanlineDirection direction;
  bool first;  ///< the first direction writes pathCost, the others add to it

  void operator()(int64_t path) const {
    const VolumeGeometry& g = in.g;
    const int D = g.disparityCount, length = direction.length(g);
    std::vector<int32_t> rows(2 * static_cast<std::size_t>(D));
    int32_t* previous = rows.data();
    int32_t* current = previous + D;
    int x, y;
    direction.start(g, static_cast<int>(path), x, y);
    int32_t previousMin = 0;
    for (int s = 0; s < length; ++s, x += direction.dx, y += direction.dy) {
      const int32_t* cost = in.cost + (static_cast<int64_t>(y) * g.width + x) * D;
      int32_t* sum = in.pathCost + (static_cast<int64_t>(y) * g.width + x) * D;
      if (s == 0) {
        std::copy(cost, cost + D, current);
      } else {
        const int px = x - direction.dx, py = y - direction.dy;
        const bool leftEdge = greyEdge(in.leftGrey, x, y, px, py, in.edgeGrey);
        for (int i = 0; i < D; ++i) {
          const int edges = pathEdges(in, leftEdge, x, y, px, py, i);
          current[i] = pathCostStep(cost[i], i > 0 ? previous[i - 1] : kPathUnreachable, previous[i],
                                    i + 1 < D ? previous[i + 1] : kPathUnreachable, previousMin,
                                    in.penalties.small[edges], in.penalties.large[edges]);
        }
      }
      int32_t currentMin = INT_MAX;
      for (int i = 0; i < D; ++i) {
        currentMin = std::min(currentMin, current[i]);
        sum[i] = first ? current[i] : sum[i] + current[i];
      }
      previousMin = currentMin;
      std::swap(previous, current);
    }
  }
};

}  // namespace

void computeScanlinePathsCpu(const ScanlineInputs& inputs) {
  for (int k = 0; k < kScanlineDirectionCount; ++k) {
    const ScanlineDirection direction = ScanlineDirection::number(k);
    parallelFor<CpuBackend>(direction.pathCount(inputs.g), ScanlinePathCpu{inputs, direction, k == 0}, 1);
  }
}

}  // namespace tissuemosaic::stereo
