#pragma once
/// @class qTissueMosaicCommandLine
/// @brief The command line of tissuemosaic-app, parsed by CLI11 with the option groups of `tissuemosaic reconstruct`
/// (Module/CommandLine/CommonOptions.h): the same input and geometry options, help text, checks and messages
/// (--left-frames/--right-frames, --left-video/--right-video or --video, then --calib [--rectified] or
/// --focal-px/--baseline-mm [--cx-px --cy-px --doffs-px], --fps, --device, --params). The application's own options
/// (start, demo, offscreen, snapshot, exports, stall report) follow. With --offscreen --report-stalls
/// --quit-when-done any input's scan is measured headless, as `reconstruct` would run it.
#include "CommonOptions.h"

#include <QString>
#include <QStringList>

#include <optional>
#include <string>

class qTissueMosaicReconstructionWidget;

class qTissueMosaicCommandLine {
public:
  // As `tissuemosaic reconstruct`.
  tissuemosaic::cli::InputOptions input;
  tissuemosaic::cli::GeometryOptions geometry;
  tissuemosaic::cli::DeviceOption device;
  std::optional<std::string> params;
  bool start = false;
  // The application's own.
  bool demo = false, offscreen = false, quitWhenDone = false, reportStalls = false, help = false;
  int demoFrames = 60, demoWidth = 480, demoHeight = 270, snapshotFrame = -1, slowEventMs = 0;
  std::string snapshot, exportModel, exportTrajectory;

  /// Parses the arguments (argv[0] first). False with `error` in plain words for a usage error.
  bool parse(const QStringList& arguments, QString& error);
  /// The --help text: every option with what it means.
  static QString helpText();

  bool hasInput() const { return tissuemosaic::cli::inputGiven(this->input); }
  bool hasPinholeGeometry() const { return this->geometry.focalPx || this->geometry.baselineMm; }
  /// Opens the input and its geometry in the panel (as the panel's buttons would). False with the reason.
  bool openInput(qTissueMosaicReconstructionWidget* panel, QString& error) const;
};
