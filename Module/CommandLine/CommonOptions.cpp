#include "CommonOptions.h"

#include "Core/Error.h"
#include "IO/Calibration/CalibrationFile.h"
#include "Stereo/StereoParameterTable.h"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <optional>
#include <utility>

namespace tissuemosaic::cli {

CLI::Validator positiveNumber(const std::string& unit) {
  return CLI::Validator(
      [unit](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0') return "";  // not a number at all: the conversion says so
        if (value > 0 && std::isfinite(value)) return "";
        return "must be a positive number" + (unit.empty() ? std::string() : " " + unit) + ", got '" + text + "'";
      },
      "");
}

CLI::Validator numberWithin(double low, double high, const std::string& unit) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (end == text.c_str() || *end != '\0') return "";  // not a number at all: the conversion says so
        if (value >= low && value <= high) return "";
        return cv::format("must be a number of %s within [%g, %g], got '%s'", unit.c_str(), low, high, text.c_str());
      },
      "");
}

void addInputOptions(CLI::App& command, InputOptions& input) {
  CLI::Option* leftFrames = command.add_option("--left-frames", input.leftFrames,
                                               "left frames (PNG/JPEG/BMP/TIFF..., taken in file-name order)");
  CLI::Option* rightFrames = command.add_option("--right-frames", input.rightFrames,
                                                "right frames, as many as left ones, paired in file-name order");
  CLI::Option* leftVideo = command.add_option(
      "--left-video", input.leftVideo, "left video: a file, a V4L2 device (/dev/videoN) or a GStreamer pipeline ending "
                                       "in appsink (live: the newest frame first, docs/INPUT.md)");
  CLI::Option* rightVideo = command.add_option("--right-video", input.rightVideo,
                                               "right video, in lock step (files) or its newest frame (live)");
  CLI::Option* video = command.add_option("--video", input.video, "one 3D video with both eyes in each frame (a file, "
                                                                  "device or pipeline as above)");
  CLI::Option* layout =
      command.add_option("--video-layout", input.videoLayout,
                         "how --video or --igtl-sbs packs the eyes: side by side, squeezed side by side, top bottom, "
                         "squeezed top bottom, row-interlaced (even rows left)")
          ->check(CLI::IsMember({"sbs", "sbs-half", "tb", "tb-half", "rows"}))
          ->type_name("LAYOUT")
          ->capture_default_str();
  CLI::Option* igtlInput = command.add_option("--igtl-input", input.igtlInput,
                                              "IMAGE messages from an OpenIGTLink server such as PLUS "
                                              "(docs/OPENIGTLINK.md)");
  CLI::Option* igtlLeft = command.add_option("--igtl-left", input.igtlLeft, "... the left eye's IMAGE device name");
  CLI::Option* igtlRight = command.add_option("--igtl-right", input.igtlRight,
                                              "... the right eye's, paired with the left by time stamp");
  CLI::Option* igtlSbs = command.add_option("--igtl-sbs", input.igtlSbs,
                                            "... or one IMAGE stream with both eyes (--video-layout)");
  igtlInput->type_name("HOST:PORT");
  igtlLeft->type_name("NAME")->needs(igtlInput)->needs(igtlRight);
  igtlRight->type_name("NAME")->needs(igtlInput)->needs(igtlLeft);
  igtlSbs->type_name("NAME")->needs(igtlInput)->excludes(igtlLeft)->excludes(igtlRight);
  leftFrames->type_name("DIR")->needs(rightFrames);
  rightFrames->type_name("DIR")->needs(leftFrames);
  leftVideo->type_name("FILE")->needs(rightVideo);
  rightVideo->type_name("FILE")->needs(leftVideo);
  video->type_name("FILE");
  CLI::Option* scared = command.add_option(
      "--scared", input.scared,
      "a SCARED key-frame folder as it ships: data/rgb.mp4 (eyes top and bottom), endoscope_calibration.yaml, and "
      "where extracted data/frame_data/*.json (the first pose starts the model; track: the ground truth)");
  CLI::Option* hamlyn = command.add_option(
      "--hamlyn", input.hamlyn,
      "a rectified Hamlyn sequence: image01/ (left), image02/ (right), intrinsics.txt (f, cx, cy); the baseline "
      "with --baseline-mm unless intrinsics.txt is 3x4 with -f B");
  CLI::Option* stereomis = command.add_option(
      "--stereomis", input.stereomis,
      "a StereoMIS sequence: its side-by-side video (or the folder holding it) and StereoCalibration.ini beside it");
  scared->type_name("DIR");
  hamlyn->type_name("DIR");
  stereomis->type_name("DIR|VIDEO");
  for (CLI::Option* option : {scared, hamlyn, stereomis}) option->group(heading::input);
  command.add_option("--fps", input.fps, "frame rate of frame folders, for their time stamps (videos carry their own)")
      ->check(numberWithin(0.01, 10000, "frames per second"))
      ->capture_default_str();
  for (CLI::Option* option :
       {leftFrames, rightFrames, leftVideo, rightVideo, video, layout, igtlInput, igtlLeft, igtlRight, igtlSbs})
    option->group(heading::input);
  command.get_option("--fps")->group(heading::input);
}

bool inputGiven(const InputOptions& input) {
  return !input.leftFrames.empty() || !input.leftVideo.empty() || !input.video.empty() || !input.igtlInput.empty();
}

void requireOneInput(const InputOptions& input) {
  const bool folders = !input.leftFrames.empty();
  const bool videos = !input.leftVideo.empty();
  const bool packed = !input.video.empty();
  const bool igtl = !input.igtlInput.empty();
  if (folders + videos + packed + igtl != 1) {
    throw UsageError("give exactly one input: --left-frames DIR --right-frames DIR, --left-video L --right-video R, "
                     "--video V, or --igtl-input HOST:PORT");
  }
  if (input.videoLayout != "sbs" && !packed && input.igtlSbs.empty()) {
    throw UsageError("--video-layout applies to --video and --igtl-sbs");
  }
}

bool GeometryOptions::given() const { return !calib.empty() || focalPx || baselineMm; }

void addGeometryOptions(CLI::App& command, GeometryOptions& geometry) {
  CLI::Option* calib = command.add_option(
      "--calib", geometry.calib,
      "calibration of the unrectified rig, recognised by its keys (docs/CALIBRATION.md: OpenCV, stereo_calib / SCARED "
      "/ SurgT, ROS camera_info, Kalibr, MATLAB): frames are rectified with it; without an image size the frames give "
      "it");
  CLI::Option* extrinsics = command.add_option(
      "--calib-extrinsics", geometry.calibExtrinsics,
      "with --calib intrinsics.yml: the stereo_calib sample's extrinsics.yml (R T)");
  CLI::Option* right = command.add_option("--calib-right", geometry.calibRight,
                                          "ROS camera_info: --calib is the left eye's file, this the right eye's");
  extrinsics->type_name("FILE")->needs(calib)->excludes(right);
  right->type_name("FILE")->needs(calib);
  CLI::Option* rectified = command.add_flag(
      "--rectified", geometry.rectified,
      "with --calib: the frames are already rectified as StereoRectifier makes them from it (e.g. synth scan's)");
  CLI::Option* focal = command.add_option("--focal-px", geometry.focalPx,
                                          "rectified frames without a calibration: focal length in pixels");
  CLI::Option* baseline = command.add_option("--baseline-mm", geometry.baselineMm, "... and baseline in mm");
  CLI::Option* cx = command.add_option("--cx-px", geometry.cxPx, "... left principal point x (default: image centre)");
  CLI::Option* cy = command.add_option("--cy-px", geometry.cyPx, "... principal point y (default: image centre)");
  CLI::Option* doffs = command.add_option("--doffs-px", geometry.doffsPx,
                                          "... cx_right - cx_left (default 0): depth = f B / (d + doffs)");
  calib->type_name("FILE");
  rectified->needs(calib);
  focal->check(positiveNumber("of pixels"))->needs(baseline);
  baseline->check(positiveNumber("of mm"));  // alone with --hamlyn, whose intrinsics.txt gives the focal length
  for (CLI::Option* option : {cx, cy, doffs}) option->needs(focal);
  calib->excludes(focal)->excludes(baseline);
  for (CLI::Option* option : {calib, extrinsics, right, rectified, focal, baseline, cx, cy, doffs})
    option->group(heading::geometry);
}

void requireGeometry(const GeometryOptions& options) {
  if (!options.calib.empty()) return;
  if (options.baselineMm && !options.focalPx) {
    throw UsageError("--baseline-mm needs --focal-px (or --hamlyn, whose intrinsics.txt gives it)");
  }
  if (!options.focalPx) {
    throw UsageError("give the geometry: --calib rig.yml, or --focal-px and --baseline-mm for rectified frames");
  }
}

StereoGeometry resolveGeometry(const GeometryOptions& options, const cv::Size& frameSize,
                               const std::string& framesDescription) {
  requireGeometry(options);
  StereoGeometrySpec spec;
  if (!options.calib.empty()) {
    spec.calibration =
        readCalibrationFiles(CalibrationFiles{options.calib, options.calibExtrinsics, options.calibRight});
    spec.framesRectified = options.rectified;
  } else {
    spec.focalPx = *options.focalPx;
    spec.baselineMm = *options.baselineMm;
    spec.cxPx = options.cxPx;
    spec.cyPx = options.cyPx;
    spec.doffsPx = options.doffsPx.value_or(0.0);
  }
  return resolveStereoGeometry(spec, frameSize, framesDescription);
}

std::string geometryOptionsText(const RectifiedGeometry& geometry) {
  return cv::format("--focal-px %.17g --baseline-mm %.17g --cx-px %.17g --cy-px %.17g --doffs-px %.17g",
                    geometry.focalPx, geometry.baselineMm, geometry.cxLeftPx, geometry.cyPx, geometry.doffsPx);
}

void addDeviceOption(CLI::App& command, DeviceOption& device, const std::string& description) {
  command.add_option("--device", device.name, description + " (default auto: CUDA when usable, else the CPU)")
      ->type_name("cpu|cuda|auto")
      ->group(heading::common);
}

void addParamsOption(CLI::App& command, std::optional<std::string>& path, const std::string& nodes) {
  command
      .add_option("--params", path,
                  "parameters file (OpenCV YAML/XML; nodes " + nodes +
                      "; missing keys keep the paper's defaults; `tissuemosaic params` lists every key)")
      ->type_name("p.yml")
      ->group(heading::common);
}

namespace {

/// "A:B" as two finite numbers; nullopt for anything else.
std::optional<std::pair<double, double>> numberPair(const std::string& text) {
  const std::size_t colon = text.find(':');
  if (colon == std::string::npos) return std::nullopt;
  const std::string first = text.substr(0, colon), second = text.substr(colon + 1);
  char *end1 = nullptr, *end2 = nullptr;
  const double a = std::strtod(first.c_str(), &end1), b = std::strtod(second.c_str(), &end2);
  if (first.empty() || second.empty() || *end1 != '\0' || *end2 != '\0' || !std::isfinite(a) || !std::isfinite(b)) {
    return std::nullopt;
  }
  return std::make_pair(a, b);
}

/// --disparity-range: "auto", or MIN:MAX whole pixels with MIN < MAX.
std::string checkDisparityRange(const std::string& text) {
  if (text == "auto") return "";
  const auto pair = numberPair(text);
  if (pair && pair->first == std::floor(pair->first) && pair->second == std::floor(pair->second) &&
      pair->first < pair->second) {
    return "";
  }
  return "expects auto or MIN:MAX in whole pixels with MIN < MAX (e.g. 0:120), got '" + text + "'";
}

/// --depth-range-mm: NEAR:FAR with 0 < NEAR < FAR.
std::string checkDepthRange(const std::string& text) {
  const auto pair = numberPair(text);
  if (pair && pair->first > 0 && pair->second > pair->first) return "";
  return "expects NEAR:FAR in mm with 0 < NEAR < FAR (e.g. 30:150), got '" + text + "'";
}

}  // namespace

void DisparityRangeOptions::applyTo(StereoParameters& parameters) const {
  if (depthMm) {
    const auto nearFar = *numberPair(*depthMm);  // checked when parsed
    parameters.disparityRangeMode = DisparityRangeMode::WorkingDistance;
    parameters.workingDistanceNearMm = static_cast<float>(nearFar.first);
    parameters.workingDistanceFarMm = static_cast<float>(nearFar.second);
  } else if (range && *range == "auto") {
    parameters.disparityRangeMode = DisparityRangeMode::Automatic;
  } else if (range) {
    const auto minMax = *numberPair(*range);
    parameters.setFixedDisparityRange(static_cast<int>(minMax.first), static_cast<int>(minMax.second));
  }
  if (minPx || maxPx) {
    parameters.setFixedDisparityRange(minPx.value_or(parameters.minDisparityPx),
                                      maxPx.value_or(parameters.maxDisparityPx));
  }
}

void addDisparityRangeOptions(CLI::App& command, DisparityRangeOptions& range) {
  const StereoParameters defaults;
  CLI::Option* automatic =
      command
          .add_option("--disparity-range", range.range,
                      "auto (the default, unless the parameters file fixes a range): chosen from sparse feature "
                      "matches of the first frame and following the tissue; or MIN:MAX in px")
          ->type_name("auto|MIN:MAX")
          ->check(CLI::Validator(checkDisparityRange, ""));
  CLI::Option* depth =
      command
          .add_option("--depth-range-mm", range.depthMm,
                      "the working distance: tissue from NEAR to FAR mm in front of the scope, turned into the "
                      "disparity range through the geometry (d = f B / Z - doffs)")
          ->type_name("NEAR:FAR")
          ->check(CLI::Validator(checkDepthRange, ""));
  depth->excludes(automatic);
  command.add_option("--min-disparity", range.minPx,
                     "fixes the range: its smallest candidate disparity in px (over the other options; the other "
                     "end from --max-disparity, else the parameters file, else " +
                         std::to_string(defaults.minDisparityPx) + ".." + std::to_string(defaults.maxDisparityPx) +
                         ")");
  const parameters::Field<StereoParameters>& minimum = stereoParameterTable().field("minDisparityPx");
  command.add_option("--max-disparity", range.maxPx,
                     "fixes the range: its largest candidate disparity in px, inclusive (both ends within [" +
                         std::to_string(static_cast<int>(minimum.minimum)) + ", " +
                         std::to_string(static_cast<int>(minimum.maximum)) + "], at most " +
                         std::to_string(kMaxDisparityCount) + " candidates)");
  for (const char* name : {"--disparity-range", "--depth-range-mm", "--min-disparity", "--max-disparity"}) {
    command.get_option(name)->group(heading::disparityRange);
  }
}

void requireGeometryForWorkingDistance(const StereoParameters& parameters, bool haveGeometry) {
  if (parameters.disparityRangeMode == DisparityRangeMode::WorkingDistance && !haveGeometry) {
    throw UsageError("a working distance (--depth-range-mm, or the parameters file's) needs the geometry to become "
                     "disparities: --calib rig.yml, or --focal-px and --baseline-mm");
  }
}

void rethrowWithRangeOptions(const std::exception& error) {
  throw Error(std::string(error.what()) +
              " (--disparity-range MIN:MAX, --min-disparity/--max-disparity or --depth-range-mm NEAR:FAR)");
}

void addQuietFlag(CLI::App& command, bool& quiet, const std::string& description) {
  command.add_flag("--quiet", quiet, description)->group(heading::common);
}

void addImageSizeOptions(CLI::App& command, int& width, int& height) {
  command.add_option("--width", width, "image width in pixels")->capture_default_str()->group(heading::options);
  command.add_option("--height", height, "image height in pixels")->capture_default_str()->group(heading::options);
}

void addBenchDisparitiesOption(CLI::App& command, std::optional<int>& disparities) {
  command.add_option("--disparities", disparities,
                     "disparities searched (default: the paper's 101, -20..80 px, scaled by width / 960)")
      ->check(CLI::Range(2, kMaxDisparityCount))
      ->group(heading::options);
}

void StereoSearchOption::applyTo(StereoParameters& parameters) const {
  if (search) parameters.search = parseStereoSearch(*search);
}

void addStereoSearchOption(CLI::App& command, StereoSearchOption& option) {
  command
      .add_option("--stereo-search", option.search,
                  "candidates the paper's matcher scores: every one of the range (exhaustive, the paper's), or "
                  "windows from a half-resolution pass (guided; docs/STEREO.md) (default: the parameters')")
      ->type_name("exhaustive|guided")
      ->check(CLI::IsMember({"exhaustive", "guided"}))
      ->group(heading::options);
}

void applyBenchDisparityRange(StereoParameters& parameters, int widthPx, const std::optional<int>& disparities,
                              bool fromParametersFile) {
  if (fromParametersFile && !disparities) return;
  const double scale = widthPx / 960.0;  // the synthetic scene's focal length grows with the width
  const StereoParameters paper;
  int minPx = parameters.minDisparityPx, maxPx = parameters.maxDisparityPx;
  if (!fromParametersFile) {
    minPx = static_cast<int>(std::lround(paper.minDisparityPx * scale));
    maxPx = static_cast<int>(std::lround(paper.maxDisparityPx * scale));
  }
  if (disparities) maxPx = minPx + *disparities - 1;
  parameters.setFixedDisparityRange(minPx, maxPx);
}

}  // namespace tissuemosaic::cli
