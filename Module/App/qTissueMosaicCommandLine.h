#pragma once
/// @class qTissueMosaicCommandLine
/// @brief The command line of tissuemosaic-app (QCommandLineParser). Input and geometry are given exactly as to
/// `tissuemosaic reconstruct`, with the same names, meanings and messages: --left-frames/--right-frames,
/// --left-video/--right-video or --video, then --calib [--rectified] or --focal-px/--baseline-mm [--cx-px --cy-px
/// --doffs-px], and --fps for frame folders; --start begins the scan at once. The application's own options
/// (demo, offscreen, snapshot, exports, stall report) follow. With --offscreen --report-stalls --quit-when-done
/// any input's scan is measured headless, as `reconstruct` would run it.
#include <QString>
#include <QStringList>

#include <limits>

class qTissueMosaicReconstructionWidget;

class qTissueMosaicCommandLine {
public:
  // Input and geometry, as `tissuemosaic reconstruct`.
  QString leftFrames, rightFrames, leftVideo, rightVideo, video, calibration;
  bool rectified = false;
  double focalPx = 0, baselineMm = 0;
  double cxPx = std::numeric_limits<double>::quiet_NaN(), cyPx = std::numeric_limits<double>::quiet_NaN();
  double doffsPx = 0, fps = 30;
  bool start = false;
  // The application's own.
  bool demo = false, offscreen = false, quitWhenDone = false, reportStalls = false, help = false;
  int demoFrames = 60, demoWidth = 480, demoHeight = 270, snapshotFrame = -1, slowEventMs = 0;
  QString device = "auto", params, snapshot, exportModel, exportTrajectory;

  /// Parses the arguments (argv[0] first). False with `error` in plain words for a usage error.
  bool parse(const QStringList& arguments, QString& error);
  /// The --help text: every option with what it means.
  static QString helpText();

  bool hasInput() const;
  bool hasPinholeGeometry() const { return this->focalPx > 0 || this->baselineMm > 0; }
  /// Opens the input and its geometry in the panel (as the panel's buttons would). False with the reason.
  bool openInput(qTissueMosaicReconstructionWidget* panel, QString& error) const;
};
