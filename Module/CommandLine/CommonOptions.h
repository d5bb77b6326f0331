#pragma once
/// @file CommonOptions.h
/// @brief The option groups that several commands (and the desktop application) share, defined once: input video, stereo geometry, device,
/// parameters file, disparity range, image size and --quiet. Each group is a struct the command's options hold,
/// an add* function that declares its options on the command (under the same help heading everywhere), and the
/// function that turns what was given into engine objects, checking what CLI11 cannot (exactly one input, one
/// geometry) with a UsageError.
#include "Core/Device.h"
#include "Core/StereoRig.h"
#include "IO/StereoGeometry.h"
#include "IO/TrajectoryTum.h"

#include <CLI/CLI.hpp>

#include <memory>
#include <optional>
#include <string>

namespace tissuemosaic {
class StereoFrameSource;
struct StereoParameters;
}  // namespace tissuemosaic

namespace tissuemosaic::cli {

/// Help headings, in this order in every command's --help.
namespace heading {
inline const std::string input = "Input";
inline const std::string geometry = "Geometry";
inline const std::string output = "Output";
inline const std::string options = "Options";
inline const std::string disparityRange = "Disparity range";
inline const std::string common = "Common options";
}  // namespace heading

/// A command line that does not make sense (a wrong combination of options): reported like CLI11's own parse
/// errors, with exit status 2.
class UsageError : public CLI::ParseError {
public:
  explicit UsageError(const std::string& message) : CLI::ParseError("UsageError", message, 2) {}
};

/// The stereo video: two folders of frames, two videos, one 3D video in a layout, or IMAGE messages from an
/// OpenIGTLink server (exactly one of them). Videos may be files, V4L2 devices or GStreamer pipelines (live).
struct InputOptions {
  std::string leftFrames, rightFrames, leftVideo, rightVideo, video;
  std::string videoLayout = "sbs";  ///< how --video (and --igtl-sbs) pack the eyes (IO/StereoVideoLayout.h)
  std::string igtlInput, igtlLeft, igtlRight, igtlSbs;  ///< HOST:PORT and the IMAGE device names
  std::string scared, hamlyn, stereomis;  ///< a public data set's own layout (applyDatasetLayout)
  double fps = 30;  ///< time stamps of frame folders (videos carry their own)
};
void addInputOptions(CLI::App& command, InputOptions& input);
/// True when any input option was given.
bool inputGiven(const InputOptions& input);
/// UsageError unless exactly one input was given (and --video-layout only with an input that packs both eyes).
void requireOneInput(const InputOptions& input);
/// Opens the one input given (UsageError when none or several are). Implemented in InputSource.cpp, apart from
/// the rest: it needs the video and image codecs, which tissuemosaic-bench must not link.
std::unique_ptr<StereoFrameSource> openInput(const InputOptions& input);

/// What a data set's own layout gave beyond the input and the geometry.
struct DatasetInput {
  std::string description;  ///< e.g. "SCARED key frame DIR", empty when no data-set option was given
  Trajectory poses;         ///< the data set's per-frame poses (SCARED), T_world_camera; empty when none
  std::string note;         ///< where the poses came from, or why there are none
};
struct GeometryOptions;
/// Turns --scared, --hamlyn or --stereomis into the plain input and geometry options they stand for (a video with
/// its layout or two frame folders; a calibration file, or the focal length and principal point). UsageError when
/// one is combined with another input, or with geometry it gives itself; Error for a missing or unreadable part.
/// Implemented in DatasetInput.cpp (it reads videos, which tissuemosaic-bench must not link).
DatasetInput applyDatasetLayout(InputOptions& input, GeometryOptions& geometry);

/// The stereo geometry: the rig's calibration (raw frames are rectified from it; --rectified: they already are),
/// or, for rectified frames, the focal length and baseline with the optional principal point and disparity offset.
struct GeometryOptions {
  std::string calib;
  std::string calibExtrinsics, calibRight;  ///< the second file of layouts that come in two (docs/CALIBRATION.md)
  bool rectified = false;
  std::optional<double> focalPx, baselineMm, cxPx, cyPx, doffsPx;
  /// True when any geometry option was given.
  bool given() const;
};
void addGeometryOptions(CLI::App& command, GeometryOptions& geometry);

/// UsageError unless the options describe one geometry (a calibration, or a focal length with a baseline).
void requireGeometry(const GeometryOptions& geometry);
/// Checks the options (requireGeometry) and resolves them through the engine (IO/StereoGeometry.h):
/// a calibration must be for frames of `frameSize` (Error naming `framesDescription`), a file without image size
/// takes it.
StereoGeometry resolveGeometry(const GeometryOptions& geometry, const cv::Size& frameSize,
                               const std::string& framesDescription);

/// The geometry options that describe `geometry` exactly (17 significant digits): "--focal-px F --baseline-mm B
/// --cx-px X --cy-px Y --doffs-px D", e.g. for a synthetic scan's rectified frames without rig.yml.
std::string geometryOptionsText(const RectifiedGeometry& geometry);

/// --device cpu|cuda|auto (default auto).
struct DeviceOption {
  std::string name = "auto";
  /// The device; throws Error for cuda where CUDA cannot be used (never a silent fallback).
  Device resolve() const { return parseDevice(name); }
};
void addDeviceOption(CLI::App& command, DeviceOption& device, const std::string& description = "where the engine runs");

/// --params p.yml: OpenCV YAML/XML parameters; `nodes` says which nodes this command reads.
void addParamsOption(CLI::App& command, std::optional<std::string>& path, const std::string& nodes);

/// The stereo disparity range, overriding the parameters file's (whose default is the automatic range).
struct DisparityRangeOptions {
  std::optional<int> minPx, maxPx;
  std::optional<std::string> range;     ///< --disparity-range auto | MIN:MAX
  std::optional<std::string> depthMm;   ///< --depth-range-mm NEAR:FAR
  /// Sets the range of `parameters` from the options given (the one place that does): --min/--max-disparity fix it
  /// (over everything else; the other end from the file or the default), else --depth-range-mm sets a working
  /// distance, else --disparity-range auto or MIN:MAX.
  void applyTo(StereoParameters& parameters) const;
};
void addDisparityRangeOptions(CLI::App& command, DisparityRangeOptions& range);

/// --stereo-search exhaustive|guided: which cells the paper's matcher scores (StereoParameters::search), over the
/// parameters file's.
struct StereoSearchOption {
  std::optional<std::string> search;
  void applyTo(StereoParameters& parameters) const;
};
void addStereoSearchOption(CLI::App& command, StereoSearchOption& option);

/// UsageError when the parameters ask for a working distance and there is no geometry to turn it into disparities.
void requireGeometryForWorkingDistance(const StereoParameters& parameters, bool haveGeometry);
/// The automatic range's failure (too few feature matches), said with the options that avoid it.
[[noreturn]] void rethrowWithRangeOptions(const std::exception& error);

/// --quiet: no progress output.
void addQuietFlag(CLI::App& command, bool& quiet, const std::string& description = "no progress output");

/// --width W --height H of rendered synthetic images.
void addImageSizeOptions(CLI::App& command, int& width, int& height);

/// --disparities N of the bench commands that render a synthetic scan (`bench track`, `bench reconstruct`).
void addBenchDisparitiesOption(CLI::App& command, std::optional<int>& disparities);
/// The disparity range those benches search. The synthetic scan keeps its field of view and working distance at
/// every size, so its disparities grow with the width: without a parameters file the paper's range (-20..80 px at
/// 960 px wide) is scaled by widthPx / 960 (-40..160 at 1920); `disparities` keeps the range's start and sets the
/// count (the parameters file's start when one was read).
void applyBenchDisparityRange(StereoParameters& parameters, int widthPx, const std::optional<int>& disparities,
                              bool fromParametersFile);

/// A validator for positive finite numbers; its message reads after the option's name, which CLI11 puts first:
/// "--focal-px: must be a positive number of pixels, got '-3'".
CLI::Validator positiveNumber(const std::string& unit);
/// The same for a number within [low, high]: "--fps: must be a number of frames per second within [0.01, 10000]".
CLI::Validator numberWithin(double low, double high, const std::string& unit);

}  // namespace tissuemosaic::cli
