#pragma once
/// @file BatchRunner.h
/// @brief Runs manifest rows on this machine, `jobs` at a time, each as its own process (RowProcess.h): rows with a
/// done record are skipped, each finished row leaves its record, a failed row does not stop the others. SIGINT and
/// SIGTERM stop the batch: its running rows are killed and left without a record, so that the next run of the batch
/// does them again and only them. A progress line on stderr after every start and end.
#include "BatchManifest.h"

#include <vector>

namespace tissuemosaic::cli {

struct BatchRunResult {
  int done = 0;     ///< rows that finished with their outputs complete
  int failed = 0;   ///< rows that failed (recorded with the reason)
  int skipped = 0;  ///< rows already done before the run
  int stopped = 0;  ///< rows stopped by a signal (no record)
  int signal = 0;   ///< the signal that stopped the batch, 0 when none did
};

/// Runs the rows numbered `rowNumbers` (all of them when empty) of `manifest`.
BatchRunResult runBatchRows(const BatchManifest& manifest, const std::vector<int>& rowNumbers, int jobs);

/// The default --jobs: one per GPU this build can use (CUDA_VISIBLE_DEVICES or the driver's list), else one.
int defaultBatchJobs();

}  // namespace tissuemosaic::cli
