#pragma once
/// @file StageClock.h
/// @brief Times consecutive stages of work on one device without waiting between them: on the CPU by the steady
/// clock at each mark; on the GPU by time marks queued behind each stage's kernels and read once at the end, so
/// that the device never idles while the host waits for a stage to finish.
#include "Device.h"

#include <chrono>
#include <vector>

namespace tissuemosaic {

class StageClock {
public:
  /// Starts the first stage.
  explicit StageClock(Device device);
  ~StageClock();
  StageClock(const StageClock&) = delete;
  StageClock& operator=(const StageClock&) = delete;

  /// Ends the current stage and starts the next.
  void mark();
  /// Milliseconds of each stage ended by mark(), in order; waits for the device to finish them.
  std::vector<double> stageMilliseconds();

private:
  Device device_;
  std::vector<std::chrono::steady_clock::time_point> times_;  ///< CPU
  std::vector<void*> events_;                                 ///< GPU
};

}  // namespace tissuemosaic
