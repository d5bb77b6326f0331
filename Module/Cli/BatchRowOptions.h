#pragma once
/// @file BatchRowOptions.h
/// @brief What one manifest row runs: `tissuemosaic reconstruct` with the row's options and the outputs the batch
/// sets in the row's folder, and the check of those options by the reconstruct command's own CLI11 parser before
/// any row runs (so a typo in row 40 is found before rows 1-39 have taken hours).
#include "BatchManifest.h"

#include <string>
#include <vector>

namespace tissuemosaic::cli {

/// The files of one row's folder.
struct RowFiles {
  std::string model, quality, timing, log, doneRecord, failedRecord;
};
RowFiles rowFiles(const BatchRow& row);

/// The row's `reconstruct` command line after the program name: "reconstruct", the row's options, then --out,
/// --quality-json and --timing-json in its folder.
std::vector<std::string> reconstructArguments(const BatchRow& row);

/// Parses the row's command line with the reconstruct command's options (nothing runs). Throws UsageError
/// "manifest row N (NAME): MESSAGE" for an unknown option, a missing value, a wrong combination, or an output option
/// the batch sets itself.
void checkRowOptions(const BatchRow& row);

}  // namespace tissuemosaic::cli
