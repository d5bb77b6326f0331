#pragma once
/// @file BatchRecord.h
/// @brief The record one row leaves in its folder: done.json once its outputs are complete (the batch skips the row
/// from then on), or failed.json with the reason. Either holds the row's figures for the summary, taken from the
/// files `reconstruct` wrote (--timing-json, --quality-json). Written atomically, so a record is whole or absent.
#include "BatchManifest.h"

#include <optional>
#include <string>

namespace tissuemosaic::cli {

struct RowRecord {
  std::string status;      ///< "done", "failed", or "not run" (no record yet)
  int exitStatus = -1;     ///< of the row's reconstruct process; -1: none ran
  std::string reason;      ///< why it failed (the command's error line, or the signal that ended it)
  double timeS = 0;        ///< wall time of the row's process
  // From the row's outputs, when it got that far:
  std::optional<int> frames, tracked, lost, keyFrames;
  std::optional<long long> points;
  /// Mean over the frames where it was measured of the share of the frame's depth within 1 mm of the model
  /// (--quality-json's share_within_1mm), 0..1.
  std::optional<double> agreement;
};

/// The figures of a finished run, read from the row's timing and quality JSON. Throws Error when they are missing
/// or malformed (a run that exits 0 writes both), or when the run was stopped by a signal (a partial model).
RowRecord measureRow(const BatchRow& row);

/// True when the row has a done record and its model: its work is complete.
bool rowIsDone(const BatchRow& row);

/// The row's record: done.json, else failed.json, else status "not run".
RowRecord readRowRecord(const BatchRow& row);

/// Writes done.json (status done; removes an old failed.json) or failed.json (any other status) atomically.
void writeRowRecord(const BatchRow& row, const RowRecord& record);

/// The record as one JSON object (the summary's element), with the row's number, name and out folder.
std::string rowRecordJson(const BatchRow& row, const RowRecord& record);

}  // namespace tissuemosaic::cli
