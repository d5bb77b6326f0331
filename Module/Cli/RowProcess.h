#pragma once
/// @file RowProcess.h
/// @brief One manifest row as its own process: `tissuemosaic reconstruct` (this very executable) with the row's
/// options, run in the manifest's folder, its stdout and stderr in the row's log. The child is in a process group of
/// its own (a Ctrl-C at the terminal reaches the batch, which stops its rows) and dies with the batch
/// (PR_SET_PDEATHSIG), so that no row outlives the batch that started it.
#include "BatchManifest.h"
#include "BatchRecord.h"

#include <sys/types.h>

#include <chrono>
#include <string>

namespace tissuemosaic::cli {

struct RunningRow {
  const BatchRow* row = nullptr;
  pid_t pid = -1;
  int slot = 0;  ///< which of the --jobs slots it holds (picks its GPU where there are several)
  std::chrono::steady_clock::time_point start;
};

/// The path of the running executable (/proc/self/exe), which each row runs.
std::string thisExecutable();

/// Prepares the row's folder (created; temporary files of an interrupted run removed) and starts the row. `cudaDevice`,
/// when not empty, becomes the child's CUDA_VISIBLE_DEVICES. Throws Error when the folder cannot be made or fork fails.
RunningRow startRow(const BatchRow& row, const std::string& workingFolder, int slot, const std::string& cudaDevice);

/// The record of a row whose process ended with `waitStatus` (waitpid's): done, with the figures of its outputs,
/// when it exited 0 and they are whole; else failed with the reason (the command's error line from the log, or
/// the signal that ended it).
RowRecord finishedRowRecord(const RunningRow& running, int waitStatus);

/// Stops a running row at once (SIGKILL to its process group), waits for it and removes its temporary files: the
/// row is left without a record, to run again in full.
void stopRow(const RunningRow& running);

}  // namespace tissuemosaic::cli
