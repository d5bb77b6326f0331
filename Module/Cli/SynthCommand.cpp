// tissuemosaic synth pair: writes one synthetic stereo pair with its calibration and ground truth.
#include "Arguments.h"
#include "Commands.h"
#include "SyntheticStereoScene.h"

#include "Core/Error.h"

#include <iostream>

namespace tissuemosaic::cli {

namespace {
const char* const help = R"(usage: tissuemosaic synth pair --out DIR [options]

Renders a synthetic stereo-endoscope pair of liver-like tissue with exact ground truth and writes
  DIR/left.png DIR/right.png           rectified pair
  DIR/left_raw.png DIR/right_raw.png   unrectified pair (lens distortion, rotated eyes)
  DIR/rig.yml                          calibration of the unrectified pair (K1 D1 K2 D2 R T imageSize)
  DIR/disparity.pfm DIR/depth_mm.pfm   rectified left view ground truth, NaN where not seen by both eyes
  DIR/groundtruth/highlight_mask_left.png
                                       rectified left view: 255 where a specular highlight raises the grey level
                                       by 10 or more, 0 elsewhere

options:
  --seed S                 random scene (default 1); the same seed gives identical files
  --width W --height H     image size (default 960 x 540)
  --preset default|wide    wide: a close, oblique view with about 100 px of disparity span
  --working-distance MM    distance from the left eye to the tissue (default 85, wide 45)
  --tilt DEG               angle between the scope axis and the tissue normal (default 15, wide 38)
  --relief MM              height of the random bumps (default 4, wide 2.5)
  --baseline MM            distance between the eyes (default 5)
  --focal PX               focal length (default 1000 px at 960 wide)
  --noise GREY             sensor read noise in grey levels (default 1.5)
  --distortion SCALE       scale of the lens distortion (default 1, 0 = none)
  --eye-rotation DEG       rotation between the eyes (default 0.5)
  --supersampling N        N x N rays per pixel (default 2)
  --lighting standard|realistic
                           the light's look (default standard: small white highlights on darker tissue).
                           realistic: the light at the scope tip with inverse-square fall-off exposed so that
                           near pale tissue is bright and partly saturated, wet tissue whose highlights break
                           into glints that sit on different surface points in each eye, sensor clipping at 255
)";
}  // namespace

int runSynthPair(const Words& words) {
  if (helpRequested(words)) {
    std::cout << help;
    return 0;
  }
  const Arguments arguments(words);
  arguments.allowOnly({"out", "seed", "width", "height", "preset", "working-distance", "tilt", "relief", "baseline",
                       "focal", "noise", "distortion", "eye-rotation", "supersampling", "lighting"});
  const std::string out = arguments.required("out");
  const std::string preset = arguments.text("preset", "default");
  require(preset == "default" || preset == "wide", "--preset must be 'default' or 'wide', got '" + preset + "'");
  synthetic::SyntheticStereoOptions options =
      preset == "wide" ? synthetic::SyntheticStereoOptions::wideDisparity() : synthetic::SyntheticStereoOptions();
  const int seed = arguments.integer("seed", static_cast<int>(options.seed));
  require(seed >= 0, "--seed must be a non-negative integer");
  options.seed = static_cast<uint32_t>(seed);
  options.width = arguments.integer("width", options.width);
  options.height = arguments.integer("height", options.height);
  options.workingDistanceMm = arguments.number("working-distance", options.workingDistanceMm);
  options.tiltDeg = arguments.number("tilt", options.tiltDeg);
  options.reliefMm = arguments.number("relief", options.reliefMm);
  options.baselineMm = arguments.number("baseline", options.baselineMm);
  options.focalPx = arguments.number("focal", options.focalPx);
  options.noiseStdGrey = arguments.number("noise", options.noiseStdGrey);
  options.distortion = arguments.number("distortion", options.distortion);
  options.eyeRotationDeg = arguments.number("eye-rotation", options.eyeRotationDeg);
  options.supersampling = arguments.integer("supersampling", options.supersampling);
  options.lighting = synthetic::parseSyntheticLighting(arguments.text("lighting", "standard"));

  const synthetic::SyntheticStereoPair pair = synthetic::renderSyntheticStereoPair(options);
  const std::vector<std::string> written = synthetic::writeSyntheticStereoPair(pair, out);
  double low = 0, high = 0;
  cv::minMaxLoc(pair.disparityPx, &low, &high, nullptr, nullptr, pair.disparityPx == pair.disparityPx);
  std::cout << "synthetic pair " << options.width << "x" << options.height << ", seed " << options.seed
            << ": disparity " << low << " .. " << high << " px, focal " << pair.geometry.focalPx << " px, baseline "
            << pair.geometry.baselineMm << " mm\n";
  for (const std::string& path : written) std::cout << "wrote " << path << "\n";
  return 0;
}

}  // namespace tissuemosaic::cli
