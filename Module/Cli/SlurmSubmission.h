#pragma once
/// @file SlurmSubmission.h
/// @brief A manifest as one Slurm job array: one task per row that is not done yet, each task running `tissuemosaic
/// batch MANIFEST --row $SLURM_ARRAY_TASK_ID` (the array's indices are the manifest's row numbers), so that Slurm
/// does all the scheduling and a resubmission asks only for what is left. Nothing of our own runs across machines.
#include "BatchManifest.h"

#include <optional>
#include <string>
#include <vector>

namespace tissuemosaic::cli {

struct SlurmOptions {
  std::optional<std::string> partition, time, memory, account;
  std::optional<int> cpusPerTask;
  std::optional<int> maxRunning;  ///< at most this many tasks at once (the array's %N)
};

/// "1-3,5,7-8" for Slurm's --array.
std::string slurmArrayIndices(const std::vector<int>& rowNumbers);

/// The sbatch script for the rows `rowNumbers` (non-empty): #SBATCH lines (job name, array, task log
/// LOGDIR/slurm-%A_%a.out, partition, time, memory, CPUs, and --gres=gpu:1 when any of the rows asks for
/// --device cuda), then the task's command with this executable's absolute path.
std::string slurmScript(const BatchManifest& manifest, const std::vector<int>& rowNumbers, const SlurmOptions& options,
                        const std::string& logFolder);

/// Runs `sbatch --parsable SCRIPT` and returns the job id it printed. Throws Error with sbatch's own message when
/// it fails (no sbatch on PATH, no controller, a bad partition...).
std::string submitSlurmScript(const std::string& scriptPath);

}  // namespace tissuemosaic::cli
