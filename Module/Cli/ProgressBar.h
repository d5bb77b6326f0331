#pragma once
/// @file ProgressBar.h
/// @brief Progress of long commands on stderr: a bar redrawn in place on a terminal; on a pipe or file, one line
/// per 10% so that logs stay short.
#include <string>

namespace tissuemosaic::cli {

class ProgressBar {
public:
  /// total: the expected count (-1 when unknown: a running count is shown). enabled = false shows nothing.
  ProgressBar(int total, bool enabled);
  /// Shows `done` of total with a short status text.
  void update(int done, const std::string& status);
  /// A message on its own line (the bar is redrawn below it on a terminal).
  void message(const std::string& text);
  /// Ends the bar's line.
  void finish();

private:
  int total_;
  bool enabled_;
  bool terminal_;
  int lastDecile_ = -1;
  bool drawn_ = false;
  std::string lastLine_;
};

}  // namespace tissuemosaic::cli
