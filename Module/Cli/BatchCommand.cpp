// tissuemosaic batch: many recorded studies, one `reconstruct` each, from a manifest; on this machine N at a time,
// or as a Slurm job array (docs/BATCH.md).
#include "BatchManifest.h"
#include "BatchRecord.h"
#include "BatchRowOptions.h"
#include "BatchRunner.h"
#include "BatchSummary.h"
#include "CommonOptions.h"
#include "Commands.h"
#include "SlurmSubmission.h"

#include "Core/Error.h"
#include "IO/AtomicFile.h"

#include <filesystem>
#include <iostream>

namespace tissuemosaic::cli {
namespace {

const char* const details = R"(Runs `tissuemosaic reconstruct` once per manifest row, each in its own process with its own log (ROW_OUT/reconstruct.log),
in the manifest's folder. The manifest is CSV with the header name,out,args (optional columns params, device) or
YAML (docs/BATCH.md); every row's options are checked before any row runs. A row's outputs (ROW_OUT/model.ply,
quality.json, timing.json) are written atomically, then its done record ROW_OUT/done.json: a row with a done record
is skipped, so a stopped batch, run again, does only what was left. A failing row is recorded (ROW_OUT/failed.json,
with the reason) and the others go on; it runs again next time. Ctrl-C or SIGTERM stops the batch and its rows at
once. At the end: the summary (NAME-summary.csv and .json beside the manifest: frames, tracked, lost, key frames,
points, agreement, time, exit status). Exit status 0 when every row is done, 1 when one failed or did not run.
Slurm: --slurm submits one job array of the rows not done (task i runs --row i); --summary collects the results.)";

struct BatchOptions {
  std::string manifest;
  std::optional<int> jobs, row;
  bool summaryOnly = false, slurm = false;
  std::optional<std::string> slurmScriptOnly, summaryCsv, summaryJson;
  SlurmOptions slurmOptions;
};

std::vector<int> rowsNotDone(const BatchManifest& manifest) {
  std::vector<int> numbers;
  for (const BatchRow& row : manifest.rows) {
    if (!rowIsDone(row)) numbers.push_back(row.number);
  }
  return numbers;
}

/// Writes the summary files and prints the table; Error when a row is not done (exit status 1).
void summarise(const BatchManifest& manifest, const BatchOptions& options) {
  const BatchSummary summary = collectSummary(manifest);
  const std::string csv = options.summaryCsv.value_or(defaultSummaryPath(manifest, ".csv"));
  const std::string json = options.summaryJson.value_or(defaultSummaryPath(manifest, ".json"));
  writeSummaryFiles(manifest, summary, csv, json);
  std::cout << summaryTable(manifest, summary) << "summary files: " << csv << ", " << json << "\n";
  if (summary.done != static_cast<int>(manifest.rows.size())) {
    throw Error("not every row is done: " + std::to_string(summary.failed) + " failed, " +
                std::to_string(summary.notRun) + " not run (the reasons are in the summary)");
  }
}

void submitToSlurm(const BatchManifest& manifest, const BatchOptions& options) {
  const std::vector<int> pending = rowsNotDone(manifest);
  if (pending.empty()) {
    std::cout << "every row of " << manifest.path << " is done: nothing to submit\n";
    return;
  }
  const std::filesystem::path path(manifest.path);
  const std::string slurmFolder = (path.parent_path() / (path.stem().string() + "-slurm")).string();
  std::error_code error;
  std::filesystem::create_directories(slurmFolder, error);
  require(std::filesystem::is_directory(slurmFolder), "cannot make the folder '" + slurmFolder + "' for the task logs");
  const std::string script = slurmScript(manifest, pending, options.slurmOptions, slurmFolder);
  const std::string scriptPath = options.slurmScriptOnly.value_or(slurmFolder + "/array.sbatch");
  requireWritableOutput(scriptPath, "sbatch script");
  writeStreamAtomically(scriptPath, "sbatch script", [&](std::ostream& out) { out << script; });
  if (options.slurmScriptOnly) {
    std::cout << "wrote " << scriptPath << ": a job array of " << pending.size() << " tasks (rows "
              << slurmArrayIndices(pending) << "); submit it with: sbatch " << scriptPath << "\n";
    return;
  }
  const std::string job = submitSlurmScript(scriptPath);
  std::cout << "submitted job array " << job << ": " << pending.size() << " tasks (rows " << slurmArrayIndices(pending)
            << "), script " << scriptPath << ", task logs " << slurmFolder << "/slurm-" << job << "_N.out\n"
            << "watch it with: squeue -j " << job << "; collect the results with: tissuemosaic batch "
            << manifest.path << " --summary\n";
}

void runBatch(const BatchOptions& options) {
  const BatchManifest manifest = readBatchManifest(options.manifest);
  if (options.summaryOnly) return summarise(manifest, options);
  for (const BatchRow& row : manifest.rows) checkRowOptions(row);
  if (options.slurm || options.slurmScriptOnly) return submitToSlurm(manifest, options);
  if (options.row) {
    const BatchRunResult result = runBatchRows(manifest, {*options.row}, 1);
    const RowRecord record = readRowRecord(manifest.row(*options.row));
    if (result.signal) throw Error("stopped by a signal: the row was not finished");
    if (record.status != "done") throw Error("row " + std::to_string(*options.row) + " failed: " + record.reason);
    return;
  }
  const int jobs = options.jobs.value_or(defaultBatchJobs());
  std::cerr << "batch: " << manifest.rows.size() << " rows from " << manifest.path << ", " << jobs << " at a time\n";
  const BatchRunResult result = runBatchRows(manifest, {}, jobs);
  if (result.signal) throw Error("stopped by a signal: run the batch again to finish the rows not done");
  summarise(manifest, options);
}

}  // namespace

void setupBatch(CLI::App& tool) {
  auto options = std::make_shared<BatchOptions>();
  CLI::App* command = addCommand(tool, "batch", "many recorded studies from a manifest: on this machine N at a time, or "
                                               "as a Slurm job array", details);
  command->add_option("manifest", options->manifest, "the studies: CSV (name,out,args) or YAML (docs/BATCH.md)")
      ->required()
      ->type_name("MANIFEST");
  CLI::Option* jobs = command->add_option("--jobs", options->jobs, "rows at a time on this machine (default: one per "
                                                                   "GPU, or one on the CPU)")
                          ->check(CLI::PositiveNumber)
                          ->group(heading::options);
  CLI::Option* row = command->add_option("--row", options->row, "run this row alone (1 = the first study; what each "
                                                                "Slurm task runs with $SLURM_ARRAY_TASK_ID)")
                         ->check(CLI::PositiveNumber)
                         ->group(heading::options);
  CLI::Option* summary = command->add_flag("--summary", options->summaryOnly,
                                           "run nothing: collect the rows' records into the summary (after a Slurm "
                                           "array)")
                             ->group(heading::options);
  command->add_option("--summary-csv", options->summaryCsv, "the summary's CSV (default NAME-summary.csv beside the "
                                                            "manifest)")
      ->type_name("FILE")
      ->group(heading::output);
  command->add_option("--summary-json", options->summaryJson, "the summary's JSON (default NAME-summary.json)")
      ->type_name("FILE")
      ->group(heading::output);
  const std::string slurmHeading = "Slurm";
  CLI::Option* slurm = command->add_flag("--slurm", options->slurm,
                                         "submit one job array with sbatch: a task per row not done yet")
                           ->group(slurmHeading);
  CLI::Option* scriptOnly = command->add_option("--slurm-script-only", options->slurmScriptOnly,
                                                "write that job array's sbatch script here, submit nothing")
                                ->type_name("FILE")
                                ->group(slurmHeading);
  SlurmOptions& s = options->slurmOptions;
  std::vector<CLI::Option*> slurmOnly = {
      command->add_option("--partition", s.partition, "sbatch --partition")->type_name("NAME"),
      command->add_option("--time", s.time, "sbatch --time: each task's limit (e.g. 2:00:00)")->type_name("TIME"),
      command->add_option("--mem", s.memory, "sbatch --mem: each task's memory (e.g. 16G)")->type_name("SIZE"),
      command->add_option("--cpus-per-task", s.cpusPerTask, "sbatch --cpus-per-task")->check(CLI::PositiveNumber),
      command->add_option("--account", s.account, "sbatch --account")->type_name("NAME"),
      command->add_option("--max-running", s.maxRunning, "at most N tasks at once (the array's %N)")
          ->check(CLI::PositiveNumber)};
  for (CLI::Option* option : slurmOnly) option->group(slurmHeading);
  slurm->excludes(scriptOnly);
  for (CLI::Option* option : {jobs, summary, slurm, scriptOnly}) row->excludes(option);
  for (CLI::Option* option : {jobs, slurm, scriptOnly}) summary->excludes(option);
  jobs->excludes(slurm)->excludes(scriptOnly);
  command->callback([options, slurmOnly] {
    if (!options->slurm && !options->slurmScriptOnly) {
      for (CLI::Option* option : slurmOnly) {
        if (option->count() > 0) throw UsageError(option->get_name() + " applies to --slurm and --slurm-script-only");
      }
    }
    runBatch(*options);
  });
}

}  // namespace tissuemosaic::cli
