// tissuemosaic synth pair: writes one synthetic stereo pair with its calibration and ground truth.
#include "CommonOptions.h"
#include "Commands.h"
#include "SyntheticStereoScene.h"

#include "Core/Error.h"

#include <iostream>
#include <memory>

namespace tissuemosaic::cli {

namespace {
const char* const details = R"(Renders a synthetic stereo-endoscope pair of liver-like tissue with exact ground truth and writes
  DIR/left.png DIR/right.png           rectified pair
  DIR/left_raw.png DIR/right_raw.png   unrectified pair (lens distortion, rotated eyes)
  DIR/rig.yml                          calibration of the unrectified pair (K1 D1 K2 D2 R T imageSize)
  DIR/disparity.pfm DIR/depth_mm.pfm   rectified left view ground truth, NaN where not seen by both eyes
  DIR/groundtruth/highlight_mask_left.png
                                       rectified left view: 255 where a specular highlight raises the grey level
                                       by 10 or more, 0 elsewhere
--lighting realistic: the light at the scope tip with inverse-square fall-off, exposed so that near pale tissue is
bright and partly saturated; wet tissue whose highlights break into glints on different surface points in each eye;
sensor clipping at 255. standard (the default): small white highlights on darker tissue.
The scene options default to the preset's values (default | wide).)";

struct SynthPairOptions {
  std::string out, preset = "default", lighting = "standard";
  std::optional<int> seed, width, height, supersampling, rightRowsBelowPx;
  std::optional<double> workingDistanceMm, tiltDeg, reliefMm, baselineMm, focalPx, noiseStdGrey, distortion,
      eyeRotationDeg;
};

template <class T>
void override(T& value, const std::optional<T>& given) {
  if (given) value = *given;
}

void runSynthPair(const SynthPairOptions& given) {
  require(given.preset == "default" || given.preset == "wide",
          "--preset must be 'default' or 'wide', got '" + given.preset + "'");
  const synthetic::SyntheticStereoOptions defaults;
  synthetic::SyntheticStereoOptions options =
      given.preset == "wide" ? synthetic::SyntheticStereoOptions::wideDisparity(given.width.value_or(defaults.width),
                                                                                given.height.value_or(defaults.height))
                             : defaults;
  if (given.seed) {
    require(*given.seed >= 0, "--seed must be a non-negative integer");
    options.seed = static_cast<uint32_t>(*given.seed);
  }
  override(options.width, given.width);
  override(options.height, given.height);
  override(options.workingDistanceMm, given.workingDistanceMm);
  override(options.tiltDeg, given.tiltDeg);
  override(options.reliefMm, given.reliefMm);
  override(options.baselineMm, given.baselineMm);
  override(options.focalPx, given.focalPx);
  override(options.noiseStdGrey, given.noiseStdGrey);
  override(options.distortion, given.distortion);
  override(options.eyeRotationDeg, given.eyeRotationDeg);
  override(options.supersampling, given.supersampling);
  override(options.rightRowsBelowPx, given.rightRowsBelowPx);
  options.lighting = synthetic::parseSyntheticLighting(given.lighting);

  const synthetic::SyntheticStereoPair pair = synthetic::renderSyntheticStereoPair(options);
  const std::vector<std::string> written = synthetic::writeSyntheticStereoPair(pair, given.out);
  double low = 0, high = 0;
  cv::minMaxLoc(pair.disparityPx, &low, &high, nullptr, nullptr, pair.disparityPx == pair.disparityPx);
  std::cout << "synthetic pair " << options.width << "x" << options.height << ", seed " << options.seed
            << ": disparity " << low << " .. " << high << " px, focal " << pair.geometry.focalPx << " px, baseline "
            << pair.geometry.baselineMm << " mm\n";
  for (const std::string& path : written) std::cout << "wrote " << path << "\n";
  std::cout << "rectified geometry of left.png and right.png: " << geometryOptionsText(pair.geometry) << "\n";
}

}  // namespace

void setupSynthPair(CLI::App& synth) {
  auto options = std::make_shared<SynthPairOptions>();
  CLI::App* command = addCommand(synth, "pair", "a synthetic stereo pair with calibration and ground truth", details);
  command->add_option("--out", options->out, "output folder (created)")->required()->type_name("DIR")
      ->group(heading::output);
  const auto add = [&](const std::string& name, auto& value, const std::string& description) {
    command->add_option(name, value, description)->group(heading::options);
  };
  add("--preset", options->preset, "wide: a close, oblique view with about 100 px of disparity span (default: default)");
  command->get_option("--preset")->type_name("default|wide");
  add("--seed", options->seed, "random scene (default 1); the same seed gives identical files");
  add("--width", options->width, "image width in pixels (default 960)");
  add("--height", options->height, "image height in pixels (default 540)");
  add("--working-distance", options->workingDistanceMm, "distance in mm from the left eye to the tissue (default 85, "
                                                        "wide 45)");
  add("--tilt", options->tiltDeg, "angle in degrees between the scope axis and the tissue normal (default 15, wide 38)");
  add("--relief", options->reliefMm, "height in mm of the random bumps (default 4, wide 2.5)");
  add("--baseline", options->baselineMm, "distance in mm between the eyes (default 5)");
  add("--focal", options->focalPx, "focal length in pixels (default 1000 at 960 wide)");
  add("--noise", options->noiseStdGrey, "sensor read noise in grey levels (default 1.5)");
  add("--distortion", options->distortion, "scale of the lens distortion (default 1, 0 = none)");
  add("--eye-rotation", options->eyeRotationDeg, "rotation in degrees between the eyes (default 0.5)");
  add("--supersampling", options->supersampling, "N x N rays per pixel (default 2)");
  add("--lighting", options->lighting, "the light's look: standard (default) or realistic (see above)");
  command->get_option("--lighting")->type_name("standard|realistic");
  add("--right-rows-below", options->rightRowsBelowPx,
      "right.png's rows lie N px below the left's (negative: above): a pair out of rectification, as with a "
      "calibration off in the vertical; the ground truth is the rectified pair's (default 0)");
  command->callback([options] { runSynthPair(*options); });
}

}  // namespace tissuemosaic::cli
