// tissuemosaic synth scan: writes a synthetic scanning video with its calibration and ground truth.
#include "CommonOptions.h"
#include "Commands.h"
#include "SyntheticScan.h"

#include "Core/Error.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>
#include <memory>
#include <string>

namespace tissuemosaic::cli {

namespace {
const char* const details = R"(Renders a synthetic stereo-endoscope video that scans liver-like tissue along a smooth lawn-mower path
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
  DIR/groundtruth/highlight_mask_left_000000.png ...
                                       left rectified view: 255 where a specular highlight raises the grey level
                                       by 10 or more, 0 elsewhere
--lighting realistic: the light's look of `synth pair --lighting realistic` (bright, partly saturated tissue, wet
glints, clipping); standard is the default.
The world frame has the tissue at Z = h(X, Y), +Z into the tissue. --path approach moves the scope in from
--max-distance to --min-distance over the scan instead of up and down between them (add --auto-exposure, or the
nearest frames get several times the light of the farthest); --focal-px, --baseline-mm and --doffs-px choose the
scope and so the disparities (f B / Z - doffs). With --doffs-px the frames are not what rig.yml's rectification
gives: use the printed geometry options instead of --calib rig.yml --rectified.
Hard mode (real surgery, each with its ground truth; deterministic from the seed): --breathing-mm makes part of the
tissue (a disc of --breathing-radius-mm, 18 mm by default, flat over its inner 10/18) rise toward the scope and fall
back once per breath (depth_NNNNNN.pfm follows it; groundtruth/static_surface.ply is the part of surface.ply that
never moves); --breath-hold-s S:E pauses the breath from S to E seconds (a ventilator hold: the tissue rests where
it was at S, then breathes on from there); --instruments adds rigid instruments (groundtruth/instrument_mask_NNNNNN.png: 255 where one covers the left pixel;
groundtruth/instruments.ply: their surfaces at every frame, for `tissuemosaic eval --reference ... --coverage-radius-mm
0`, whose share_within_1mm is the share of a model's points within 1 mm of an instrument); --camera-out S:E shows no
tissue in frames S to E-1 (no line in trajectory.txt), and the camera is back at frame E about 10 mm and 10 degrees
from where it left. groundtruth/scene.yml says what breathes, when each instrument is in and the camera-out span.
In-vivo mode (what real in-vivo video shows, with ground truth for every frame): --in-vivo sets a still scope 80 mm
over a whole view that breathes (3 mm toward the scope and --breathing-lateral-mm 1.5 sideways every 4.3 s), a
pulsing patch (--pulse-mm 0.5, --pulse-period-s 0.85, --pulse-radius-mm 8), two instruments near the view's border
(--instruments-at-border) that press --push-mm 2 into the tissue, --tissue-look invivo (darker, blood-red, less
texture) under --lighting realistic, --motion-blur-ms 8 and --interlaced fields (even rows at t, odd rows at t + half
a frame period). Options given with it, before or after, override it (--no-interlaced, --min-speed 5 ...; with
--instruments 0 or --breathing-mm 0 its push, border and lateral parts go too). Whenever the tissue deforms
(breathing, pulse or push) the ground truth adds
  DIR/groundtruth/rest_surface.ply     the tissue at rest (no breathing, pulse or push) over what the scan saw, whole
  DIR/groundtruth/surface_000000.ply ... the true surface at each frame (rest_surface.ply's vertices moved with the
                                       tissue), world frame, mm
Each frame's truth (depth, pose, masks, surface_NNNNNN.ply) is for its time t = index / fps: the middle of the even
field's exposure. static_surface.ply is left out where nothing stays still (whole-view breathing).)";

struct SynthScanOptions {
  std::string out;
  synthetic::SyntheticScanOptions scan;
  int seed = static_cast<int>(synthetic::SyntheticScanOptions{}.seed);
  std::string cameraOut;  ///< "S:E", empty: none
  std::string breathHold;  ///< "S:E" in seconds, empty: none
  std::string lighting = "standard";
  std::string tissueLook = "standard";
  bool inVivo = false;  ///< --in-vivo given
  /// The in-vivo options that need another one (breathing, instruments), given explicitly: without it they are an
  /// error; set only by the preset they give way (--in-vivo --instruments 0 is a scan without instruments).
  const CLI::Option* lateralGiven = nullptr;
  const CLI::Option* pushGiven = nullptr;
  const CLI::Option* atBorderGiven = nullptr;
};

void printProgress(int frame, int frames) {
  std::cerr << "\rrendered frame " << frame << " / " << frames << std::flush;
  if (frame == frames) std::cerr << "\n";
}

void runSynthScan(const SynthScanOptions& given) {
  require(given.seed >= 0, "--seed must be a non-negative integer");
  synthetic::SyntheticScanOptions options = given.scan;
  options.seed = static_cast<uint32_t>(given.seed);
  if (!given.cameraOut.empty()) {
    int first = -1, back = -1;
    char colon = 0, extra = 0;
    require(std::sscanf(given.cameraOut.c_str(), "%d%c%d%c", &first, &colon, &back, &extra) == 3 && colon == ':',
            "--camera-out must be S:E (first frame without tissue, first frame back), got '" + given.cameraOut + "'");
    require(first >= 1, "--camera-out S:E needs S >= 1, got '" + given.cameraOut + "'");
    options.hardMode.cameraOutStart = first;
    options.hardMode.cameraOutEnd = back;
  }
  if (!given.breathHold.empty()) {
    double first = -1, last = -1;
    char colon = 0, extra = 0;
    require(std::sscanf(given.breathHold.c_str(), "%lf%c%lf%c", &first, &colon, &last, &extra) == 3 && colon == ':' &&
                first >= 0 && last > first,
            "--breath-hold-s must be S:E with 0 <= S < E (seconds), got '" + given.breathHold + "'");
    options.hardMode.breathHoldStartS = first;
    options.hardMode.breathHoldEndS = last;
  }
  options.lighting = synthetic::parseSyntheticLighting(given.lighting);
  options.inVivo.tissueLook = synthetic::parseTissueLook(given.tissueLook);
  if (given.inVivo) {
    if (!options.hardMode.breathing() && given.lateralGiven->count() == 0) options.inVivo.breathingLateralMm = 0;
    if (options.hardMode.instruments == 0 && given.pushGiven->count() == 0) options.inVivo.pushMm = 0;
    if (options.hardMode.instruments == 0 && given.atBorderGiven->count() == 0) options.inVivo.instrumentsAtBorder = false;
  }
  const std::string& out = given.out;
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
            << "  rig.yml             unrectified rig calibration; the frames' rectified geometry is\n"
            << "                      " << geometryOptionsText(scan.geometry())
            << (options.rectifiedDisparityOffsetPx != 0 ? " (not rig.yml's: --doffs-px)" : "") << "\n"
            << "  groundtruth/        trajectory.txt (TUM, T_world_camera of the left rectified camera, mm),\n"
            << "                      surface.ply (world frame mesh, mm), depth_NNNNNN.pfm (mm)"
            << (scan.tissueDeforms() ? ",\n                      rest_surface.ply, surface_NNNNNN.ply (the true surface per frame)" : "")
            << "\n";
}

}  // namespace

void setupSynthScan(CLI::App& synth) {
  auto options = std::make_shared<SynthScanOptions>();
  CLI::App* command = addCommand(synth, "scan", "a synthetic scanning video (rectified frames) with trajectory, "
                                               "surface and depth ground truth", details);
  synthetic::SyntheticScanOptions& scan = options->scan;
  command->add_option("--out", options->out, "output folder (created)")->required()->type_name("DIR")
      ->group(heading::output);
  const auto add = [&](const std::string& name, auto& value, const std::string& description) {
    command->add_option(name, value, description)->capture_default_str()->group(heading::options);
  };
  add("--frames", scan.frames, "number of frames");
  add("--seed", options->seed, "random scene and path; the same seed gives identical files");
  addImageSizeOptions(*command, scan.width, scan.height);
  add("--fps", scan.fps, "frame rate");
  add("--min-distance", scan.minWorkingDistanceMm, "nearest working distance along the optical axis, mm");
  add("--max-distance", scan.maxWorkingDistanceMm, "farthest working distance, mm");
  add("--min-speed", scan.minSpeedMmPerS, "slowest scope speed, mm/s");
  add("--max-speed", scan.maxSpeedMmPerS, "fastest scope speed, mm/s");
  add("--noise", scan.noiseStdGrey, "sensor read noise in grey levels");
  add("--supersampling", scan.supersampling, "N x N rays per pixel");
  add("--focal-px", scan.focalPx, "focal length of the rectified views in px (0: 1000 px x width / 960)");
  add("--baseline-mm", scan.baselineMm, "stereo baseline, mm");
  add("--doffs-px", scan.rectifiedDisparityOffsetPx,
      "the right rectified principal point this far right of the left's: disparities f B / Z - doffs");
  const std::map<std::string, synthetic::WorkingDistanceProfile> paths = {
      {"oscillate", synthetic::WorkingDistanceProfile::Oscillating},
      {"approach", synthetic::WorkingDistanceProfile::Approaching}};
  command->add_option("--path", scan.distanceProfile,
                      "oscillate: the working distance goes up and down between the two; approach: from the "
                      "maximum down to the minimum over the scan")
      ->transform(CLI::CheckedTransformer(paths))
      ->type_name("oscillate|approach")
      ->default_str("oscillate")
      ->group(heading::options);
  command->add_flag("--auto-exposure", scan.autoExposure,
                    "the exposure follows the working distance (as a scope's automatic exposure)")
      ->group(heading::options);
  const std::string hardMode = "Hard mode (real surgery, with ground truth)";
  synthetic::SyntheticHardModeOptions& hard = scan.hardMode;
  command->add_option("--breathing-mm", hard.breathingAmplitudeMm,
                      "part of the tissue rises toward the scope by up to this and falls back once per breath (0: none)")
      ->capture_default_str()->type_name("MM")->group(hardMode);
  command->add_option("--breathing-period-s", hard.breathingPeriodS, "one breath, s")
      ->capture_default_str()->type_name("S")->group(hardMode);
  command->add_option("--breathing-radius-mm", hard.breathingRadiusMm,
                      "radius of the breathing part on the tissue (flat over its inner 10/18); 60 or more: the whole view")
      ->capture_default_str()->type_name("MM")->group(hardMode);
  command->add_option("--breath-hold-s", options->breathHold,
                      "the ventilator pauses from S to E seconds: the breathing tissue rests where it was at S, then "
                      "breathes on")
      ->type_name("S:E")->group(hardMode);
  command->add_option("--instruments", hard.instruments,
                      "rigid instruments (steel shaft, serrated jaws) that enter, move over the tissue and leave")
      ->capture_default_str()->type_name("N")->group(hardMode);
  command->add_option("--camera-out", options->cameraOut,
                      "frames S to E-1 show no tissue (the scope withdrawn); at E it is back about 10 mm and 10 degrees "
                      "from where it left")
      ->type_name("S:E")->group(hardMode);
  command->add_flag("--smoke", hard.smoke, "a drifting haze over the tissue in every frame")->group(hardMode);
  add("--lighting", options->lighting, "the light's look: standard or realistic");
  command->get_option("--lighting")->type_name("standard|realistic");

  const std::string inVivoMode = "In-vivo mode (real in-vivo video, with the true surface of every frame)";
  synthetic::SyntheticInVivoOptions& inVivo = scan.inVivo;
  // The preset is applied as soon as --in-vivo is parsed; every other option's value is stored after parsing, so
  // options given with it override it wherever they stand.
  command->add_flag_callback("--in-vivo", [options] {
        options->inVivo = true;
        synthetic::applyInVivoPreset(options->scan);
        options->lighting = synthetic::syntheticLightingName(options->scan.lighting);
        options->tissueLook = synthetic::tissueLookName(options->scan.inVivo.tissueLook);
      }, "a still scope over breathing, pulsing, pushed, blood-red tissue, realistic light, 8 ms blur, interlaced "
         "(values in the description above); other options override it")
      ->trigger_on_parse()->group(inVivoMode);
  options->lateralGiven = command->add_option("--breathing-lateral-mm", inVivo.breathingLateralMm,
                      "with the breath the tissue also slides this far sideways (seeded direction; needs --breathing-mm)")
      ->capture_default_str()->type_name("MM")->group(inVivoMode);
  command->add_option("--pulse-mm", inVivo.pulseAmplitudeMm,
                      "a patch at a seeded place in view rises by up to this once per heartbeat (0: none)")
      ->capture_default_str()->type_name("MM")->group(inVivoMode);
  command->add_option("--pulse-period-s", inVivo.pulsePeriodS, "one heartbeat, s")
      ->capture_default_str()->type_name("S")->group(inVivoMode);
  command->add_option("--pulse-radius-mm", inVivo.pulseRadiusMm, "radius of the pulsing patch on the tissue")
      ->capture_default_str()->type_name("MM")->group(inVivoMode);
  options->pushGiven = command->add_option("--push-mm", inVivo.pushMm,
                      "each instrument presses its closed jaws this far into the tissue in the middle of its span, "
                      "denting it (needs --instruments; 0: none)")
      ->capture_default_str()->type_name("MM")->group(inVivoMode);
  options->atBorderGiven = command->add_flag("--instruments-at-border,!--instruments-at-centre", inVivo.instrumentsAtBorder,
                    "the instruments work near the view's border (default: around its centre)")
      ->group(inVivoMode);
  command->add_option("--tissue-look", options->tissueLook,
                      "standard, or invivo: darker, blood-red tissue with less fine texture")
      ->capture_default_str()->type_name("standard|invivo")->group(inVivoMode);
  command->add_option("--motion-blur-ms", inVivo.motionBlurMs,
                      "exposure time: each field averages the scene over it, centred on its time (0: none)")
      ->capture_default_str()->type_name("MS")->group(inVivoMode);
  command->add_flag("--interlaced,!--no-interlaced", inVivo.interlaced,
                    "even rows at the frame's time, odd rows half a frame period later")
      ->group(inVivoMode);
  command->callback([options] { runSynthScan(*options); });
}

}  // namespace tissuemosaic::cli
