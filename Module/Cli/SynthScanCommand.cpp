// tissuemosaic synth scan: writes a synthetic scanning video with its calibration and ground truth.
#include "Arguments.h"
#include "Commands.h"
#include "SyntheticScan.h"

#include "Core/Error.h"

#include <chrono>
#include <cstdio>
#include <iostream>

namespace tissuemosaic::cli {

namespace {
const char* const help = R"(usage: tissuemosaic synth scan --out DIR [options]

Renders a synthetic stereo-endoscope video that scans liver-like tissue along a smooth lawn-mower path
(60-120 mm from the tissue, 3-30 mm/s at 30 fps, gentle tilt and roll, low-texture stretches) and writes
  DIR/left/000000.png ...              RECTIFIED left frames (track them with --rectified)
  DIR/right/000000.png ...             RECTIFIED right frames
  DIR/rig.yml                          calibration of the unrectified rig (K1 D1 K2 D2 R T imageSize); the frames are
                                       what StereoRectifier makes of it
  DIR/groundtruth/trajectory.txt       TUM (t tx ty tz qx qy qz qw): T_world_camera of the LEFT RECTIFIED camera, mm
  DIR/groundtruth/surface.ply          the true surface that the scan saw with both eyes (triangles inside both
                                       rectified views, 5 px border, in some frame), triangle mesh, world frame, mm:
                                       the reference of `tissuemosaic eval`
  DIR/groundtruth/depth_000000.pfm ... depth (mm) along the left rectified optical axis, NaN = not seen by both eyes
The world frame has the tissue at Z = h(X, Y), +Z into the tissue.

options:
  --frames N               number of frames (default 120)
  --seed S                 random scene and path (default 1); the same seed gives identical files
  --width W --height H     image size (default 960 x 540)
  --fps F                  frame rate (default 30)
  --min-distance MM        nearest working distance along the optical axis (default 70)
  --max-distance MM        farthest working distance (default 100)
  --min-speed MM_S         slowest scope speed (default 6)
  --max-speed MM_S         fastest scope speed (default 20)
  --noise GREY             sensor read noise in grey levels (default 1.5)
  --supersampling N        N x N rays per pixel (default 2)

hard mode (real surgery, each with its ground truth; deterministic from the seed):
  --breathing-mm A         part of the tissue (a disc of 18 mm radius, flat over its inner 10 mm) rises toward the
                           scope by up to A mm and falls back once per breath; depth_NNNNNN.pfm is the tissue at
                           that frame, groundtruth/static_surface.ply the part of surface.ply that never moves
  --breathing-period-s T   one breath (default 4)
  --instruments N          N rigid instruments (steel shaft, serrated jaws) enter, move over the tissue and leave;
                           groundtruth/instrument_mask_NNNNNN.png (255: an instrument covers the left pixel; the
                           depth is the tissue's behind it) and groundtruth/instruments.ply (their surfaces at every
                           frame, one mesh: `tissuemosaic eval --reference` on it gives share_within_1mm, the share
                           of a model's points within 1 mm of an instrument)
  --camera-out S:E         frames S to E-1 show no tissue (the scope withdrawn: smoke, dark, a smeared lens) and have
                           no line in trajectory.txt; at frame E the camera is back about 10 mm and 10 degrees from
                           where it left
  --smoke                  a drifting haze over the tissue in every frame
groundtruth/scene.yml then says what breathes, when each instrument is in and the camera-out span.
)";

void printProgress(int frame, int frames) {
  std::cerr << "\rrendered frame " << frame << " / " << frames << std::flush;
  if (frame == frames) std::cerr << "\n";
}
}  // namespace

int runSynthScan(const Words& words) {
  if (helpRequested(words)) {
    std::cout << help;
    return 0;
  }
  const Arguments arguments(words);
  arguments.allowOnly({"out", "frames", "seed", "width", "height", "fps", "min-distance", "max-distance", "min-speed",
                       "max-speed", "noise", "supersampling", "breathing-mm", "breathing-period-s", "instruments",
                       "camera-out", "smoke"});
  const std::string out = arguments.required("out");
  synthetic::SyntheticScanOptions options;
  const int seed = arguments.integer("seed", static_cast<int>(options.seed));
  require(seed >= 0, "--seed must be a non-negative integer");
  options.seed = static_cast<uint32_t>(seed);
  options.frames = arguments.integer("frames", options.frames);
  options.width = arguments.integer("width", options.width);
  options.height = arguments.integer("height", options.height);
  options.fps = arguments.number("fps", options.fps);
  options.minWorkingDistanceMm = arguments.number("min-distance", options.minWorkingDistanceMm);
  options.maxWorkingDistanceMm = arguments.number("max-distance", options.maxWorkingDistanceMm);
  options.minSpeedMmPerS = arguments.number("min-speed", options.minSpeedMmPerS);
  options.maxSpeedMmPerS = arguments.number("max-speed", options.maxSpeedMmPerS);
  options.noiseStdGrey = arguments.number("noise", options.noiseStdGrey);
  options.supersampling = arguments.integer("supersampling", options.supersampling);
  synthetic::SyntheticHardModeOptions& hard = options.hardMode;
  hard.breathingAmplitudeMm = arguments.number("breathing-mm", hard.breathingAmplitudeMm);
  hard.breathingPeriodS = arguments.number("breathing-period-s", hard.breathingPeriodS);
  hard.instruments = arguments.integer("instruments", hard.instruments);
  if (arguments.has("camera-out")) {
    const std::string span = arguments.required("camera-out");
    int start = -1, end = -1;
    char colon = 0, extra = 0;
    require(std::sscanf(span.c_str(), "%d%c%d%c", &start, &colon, &end, &extra) == 3 && colon == ':',
            "--camera-out must be S:E (first frame without tissue, first frame back), got '" + span + "'");
    require(start >= 0, "--camera-out S:E needs S >= 1, got '" + span + "'");
    hard.cameraOutStart = start;
    hard.cameraOutEnd = end;
  }
  hard.smoke = arguments.has("smoke");

  const auto start = std::chrono::steady_clock::now();
  const synthetic::SyntheticScan scan(options);
  const int written = synthetic::writeSyntheticScan(scan, out, printProgress);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const cv::Rect2d domain = scan.scannedDomainMm();
  std::cout << "synthetic scan " << options.width << "x" << options.height << ", " << options.frames
            << " frames at " << options.fps << " fps, seed " << options.seed << ": focal " << scan.geometry().focalPx
            << " px, baseline " << scan.geometry().baselineMm << " mm, scanned area " << domain.width << " x "
            << domain.height << " mm\n"
            << "wrote " << written << " files under " << out << " in " << cv::format("%.1f", seconds) << " s\n"
            << "  left/, right/       RECTIFIED frames (use `tissuemosaic track --rectified`)\n"
            << "  rig.yml             unrectified rig calibration\n"
            << "  groundtruth/        trajectory.txt (TUM, T_world_camera of the left rectified camera, mm),\n"
            << "                      surface.ply (world frame mesh, mm), depth_NNNNNN.pfm (mm)\n";
  return 0;
}

}  // namespace tissuemosaic::cli
