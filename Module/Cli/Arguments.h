#pragma once
/// @file Arguments.h
/// @brief Command-line arguments of the form `--name value` and `--flag`, with typed, checked access.
#include <map>
#include <set>
#include <string>
#include <vector>

namespace tissuemosaic::cli {

/// True when the words ask for a command's help (--help or -h anywhere), before any other checking.
bool helpRequested(const std::vector<std::string>& words);

class Arguments {
public:
  /// words: everything after the command (and sub-command) names. `--name value` pairs and bare `--flag`s
  /// (a flag is a --name followed by another --name or nothing). Positional words are kept in order.
  explicit Arguments(const std::vector<std::string>& words);

  bool has(const std::string& name) const;
  /// The value of --name; throws Error "missing required option --name" when absent.
  std::string required(const std::string& name) const;
  std::string text(const std::string& name, const std::string& fallback) const;
  int integer(const std::string& name, int fallback) const;
  double number(const std::string& name, double fallback) const;
  /// Throws Error naming the first option not in `known` (catches typos such as --min-disparty), or the first
  /// positional word (no command takes any: a stray word is a mistyped option value).
  void allowOnly(const std::set<std::string>& known) const;

private:
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_;
};

}  // namespace tissuemosaic::cli
