#pragma once
/// @file UsageMessage.h
/// @brief CLI11's parse errors said the house's way (the option or word at fault first, a near miss suggested), for
/// main() and for anything else that parses a command line with the tool's commands (the batch checks each
/// manifest row's `reconstruct` options this way before running any).
#include <CLI/CLI.hpp>

#include <string>

namespace tissuemosaic::cli {

/// "stereo", "bench stereo", or "" for the tool itself: the deepest command named on the parsed command line.
std::string commandPath(const CLI::App& tool);

/// The message for `error`, raised while `tool` parsed: e.g. "unknown option --min-disparty (did you mean
/// --min-disparity?)", "missing required option --out", "option --fps expects a number, got 'x'".
std::string usageMessage(const CLI::ParseError& error, const CLI::App& tool);

}  // namespace tissuemosaic::cli
