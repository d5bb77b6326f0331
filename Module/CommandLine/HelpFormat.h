#pragma once
/// @file HelpFormat.h
/// @brief The help layout of every TissueMosaic command line (the tool's commands and the desktop application): one
/// blank line between option groups, no Needs:/Excludes: lists (each group's descriptions say how its options go
/// together), -h/--help last under the common options, and an option given twice an error.
#include <CLI/CLI.hpp>

namespace tissuemosaic::cli {

/// Sets the layout above on `app` (its commands added later inherit it) and moves its --help last.
void useHouseHelpFormat(CLI::App& app);
/// -h/--help last, under the common options, in `app` and each of its commands (CLI11 adds it first).
void moveHelpLast(CLI::App& app);

}  // namespace tissuemosaic::cli
