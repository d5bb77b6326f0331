#include "SlurmSubmission.h"

#include "RowProcess.h"

#include "Core/Error.h"

#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <sstream>

namespace tissuemosaic::cli {
namespace {

/// A word for the shell in single quotes.
std::string shellQuoted(const std::string& word) {
  std::string quoted = "'";
  for (const char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

std::string slurmArrayIndices(const std::vector<int>& rowNumbers) {
  std::string text;
  for (std::size_t i = 0; i < rowNumbers.size();) {
    std::size_t j = i;
    while (j + 1 < rowNumbers.size() && rowNumbers[j + 1] == rowNumbers[j] + 1) ++j;
    text += (text.empty() ? "" : ",") + std::to_string(rowNumbers[i]);
    if (j > i) text += "-" + std::to_string(rowNumbers[j]);
    i = j + 1;
  }
  return text;
}

std::string slurmScript(const BatchManifest& manifest, const std::vector<int>& rowNumbers, const SlurmOptions& options,
                        const std::string& logFolder) {
  require(!rowNumbers.empty(), "no row to submit");
  bool gpu = false;
  for (int number : rowNumbers) gpu = gpu || manifest.row(number).wantsGpu();
  std::ostringstream script;
  script << "#!/bin/bash\n"
         << "# tissuemosaic batch: one task per manifest row (the array index is the row number); written by\n"
         << "# tissuemosaic batch " << manifest.path << " --slurm. Collect the results with --summary.\n"
         << "#SBATCH --job-name=tissuemosaic-" << std::filesystem::path(manifest.path).stem().string() << "\n"
         << "#SBATCH --array=" << slurmArrayIndices(rowNumbers)
         << (options.maxRunning ? "%" + std::to_string(*options.maxRunning) : "") << "\n"
         << "#SBATCH --output=" << logFolder << "/slurm-%A_%a.out\n"
         << "#SBATCH --chdir=" << manifest.folder << "\n"
         << "#SBATCH --ntasks=1\n";
  if (options.partition) script << "#SBATCH --partition=" << *options.partition << "\n";
  if (options.account) script << "#SBATCH --account=" << *options.account << "\n";
  if (options.time) script << "#SBATCH --time=" << *options.time << "\n";
  if (options.memory) script << "#SBATCH --mem=" << *options.memory << "\n";
  if (options.cpusPerTask) script << "#SBATCH --cpus-per-task=" << *options.cpusPerTask << "\n";
  if (gpu) script << "#SBATCH --gres=gpu:1\n";
  script << "exec " << shellQuoted(thisExecutable()) << " batch " << shellQuoted(manifest.path)
         << " --row \"$SLURM_ARRAY_TASK_ID\"\n";
  return script.str();
}

std::string submitSlurmScript(const std::string& scriptPath) {
  const std::string command = "sbatch --parsable " + shellQuoted(scriptPath) + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  require(pipe != nullptr, "cannot run sbatch");
  std::string output;
  char buffer[512];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  while (!output.empty() && (output.back() == '\n' || output.back() == ' ')) output.pop_back();
  if (status != 0) {
    const bool missing = WIFEXITED(status) && WEXITSTATUS(status) == 127;
    throw Error(missing ? "sbatch is not on PATH: --slurm needs a machine with Slurm's client commands (or write the "
                          "script with --slurm-script-only and submit it where Slurm is)"
                        : "sbatch refused the job array: " + output);
  }
  // --parsable prints "JOBID" or "JOBID;CLUSTER" on its last line (warnings may come before it).
  const std::size_t lineStart = output.find_last_of('\n');
  const std::string last = output.substr(lineStart == std::string::npos ? 0 : lineStart + 1);
  return last.substr(0, last.find(';'));
}

}  // namespace tissuemosaic::cli
