#pragma once
/// @file BatchSummary.h
/// @brief The batch's summary: every row's record (done, failed, not run) with its figures, as CSV and JSON files
/// and as a table on stdout. Built from the records in the rows' folders alone, so that it reads the same after a
/// local batch and after a Slurm array whose tasks ran on other machines.
#include "BatchManifest.h"
#include "BatchRecord.h"

#include <string>
#include <vector>

namespace tissuemosaic::cli {

struct BatchSummary {
  std::vector<RowRecord> records;  ///< one per manifest row, in its order
  int done = 0, failed = 0, notRun = 0;
};

BatchSummary collectSummary(const BatchManifest& manifest);

/// Default paths beside the manifest: NAME-summary.csv and NAME-summary.json for NAME.csv.
std::string defaultSummaryPath(const BatchManifest& manifest, const std::string& extension);

/// CSV columns: row,name,status,exit_status,frames,tracked,lost,key_frames,points,agreement,time_s,reason,out
/// (empty where a figure is unknown); JSON: {"rows": [...], "done": D, "failed": F, "not_run": N}. Atomic writes.
void writeSummaryFiles(const BatchManifest& manifest, const BatchSummary& summary, const std::string& csvPath,
                       const std::string& jsonPath);

/// The table printed at the end: a line per row and the counts.
std::string summaryTable(const BatchManifest& manifest, const BatchSummary& summary);

}  // namespace tissuemosaic::cli
