#pragma once
/// @file BatchManifest.h
/// @brief The manifest of `tissuemosaic batch`: one row per study, read from CSV (the header names the columns;
/// `name,out,args` is always accepted) or YAML (a list `studies:` of maps with the same keys). Columns: `name` (the
/// study's name in the summary), `out` (its folder: model.ply, the log and the done record go there), `args` (that
/// study's `reconstruct` options as one string, quoted as a shell would), and the optional `params` (a parameters
/// file) and `device` (cpu|cuda|auto). Relative paths are relative to the manifest's folder, where the rows run.
/// docs/BATCH.md.
#include <string>
#include <vector>

namespace tissuemosaic::cli {

struct BatchRow {
  int number = 0;        ///< 1 for the first study: the Slurm array index and `--row N`
  std::string name;
  std::string out;       ///< absolute folder
  std::string args;      ///< as written
  std::string params;    ///< optional column, empty when absent
  std::string device;    ///< optional column, empty when absent
  /// The row's `reconstruct` options: args split as a shell would (quotes group words), then --params and
  /// --device from their columns.
  std::vector<std::string> options() const;
  /// True when the row asks for a GPU (--device cuda), for Slurm's --gres.
  bool wantsGpu() const;
};

struct BatchManifest {
  std::string path;    ///< absolute
  std::string folder;  ///< where the rows run and relative paths start
  std::vector<BatchRow> rows;
  /// The row numbered `number` (1-based); throws UsageError when there is none.
  const BatchRow& row(int number) const;
};

/// Reads and checks a manifest: a missing column, an unknown one, a malformed line (an unclosed quote, a wrong
/// number of fields), an empty name or out, two rows with one name or one out folder are each an Error naming
/// the file and line. The rows' options are checked separately (checkRowOptions, BatchRowOptions.h).
BatchManifest readBatchManifest(const std::string& path);

}  // namespace tissuemosaic::cli
