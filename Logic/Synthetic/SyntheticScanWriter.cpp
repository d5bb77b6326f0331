// Writing a synthetic scan to files: kept apart from the renderer so that programs which only render do not link
// OpenCV's image codecs.
#include "SyntheticScan.h"

#include "SyntheticBreathing.h"
#include "SyntheticInstruments.h"
#include "SyntheticPulse.h"
#include "SyntheticPush.h"

#include "Core/Error.h"
#include "IO/DisparityPfm.h"
#include "IO/Calibration/CalibrationFile.h"
#include "IO/MeshPly.h"
#include "IO/TrajectoryTum.h"

#include <opencv2/core/persistence.hpp>
#include <opencv2/imgcodecs.hpp>

#include <filesystem>

namespace tissuemosaic::synthetic {

namespace {

/// static_surface.ply, instruments.ply and scene.yml of the hard-mode options (SyntheticHardMode.h) that are on.
int writeHardModeGroundTruth(const SyntheticScan& scan, const std::filesystem::path& folder) {
  const SyntheticHardModeOptions& hard = scan.options().hardMode;
  const SyntheticInVivoOptions& inVivo = scan.options().inVivo;
  const bool anyInVivo = inVivo.breathingLateralMm > 0 || inVivo.pulse() || inVivo.push() ||
                         inVivo.instrumentsAtBorder || inVivo.tissueLook != TissueLook::Standard ||
                         inVivo.timedCapture();
  if (!hard.breathing() && hard.instruments == 0 && !hard.cameraOut() && !hard.smoke && !anyInVivo) return 0;
  int written = 0;
  const std::string frame = "frame: world (tissue Z = h(X, Y), +Z into the tissue), millimetres";
  bool staticWritten = false;
  if (scan.tissueDeforms()) {
    // A view that moves as a whole (whole-view breathing) has no still part: no file then (scene.yml says so).
    const TriangleMesh still = scan.staticSurfaceMesh(0.5, 1, true);
    if (!still.triangles.empty()) {
      writeMeshPly((folder / "static_surface.ply").string(), still,
                   "TissueMosaic synthetic scan: the part of surface.ply that never moves (breathing moves it at most " +
                       std::to_string(SyntheticBreathing::kStaticToleranceMm) + " mm)\n" + frame);
      ++written;
      staticWritten = true;
    }
  }
  if (hard.instruments > 0) {
    writeMeshPly((folder / "instruments.ply").string(), scan.instrumentSurfaceMesh(),
                 "TissueMosaic synthetic scan: the instruments' surfaces at every frame with tissue, one mesh (shafts "
                 "meshed " + std::to_string(static_cast<int>(SyntheticInstruments::kMeshedShaftLengthMm)) +
                     " mm from the tip)\n" + frame);
    ++written;
  }
  const std::string path = (folder / "scene.yml").string();
  cv::FileStorage scene(path, cv::FileStorage::WRITE);
  require(scene.isOpened(), "cannot write '" + path + "'");
  scene.writeComment("TissueMosaic synthetic scan: what moves besides the camera (world frame, mm, s, frames)");
  if (hard.breathing()) {
    const SurfaceSwell& shape = scan.breathing().shape();
    scene << "breathing" << "{" << "amplitudeMm" << hard.breathingAmplitudeMm << "periodS" << hard.breathingPeriodS
          << "centreXMm" << shape.centreXMm << "centreYMm" << shape.centreYMm << "innerRadiusMm" << shape.innerRadiusMm
          << "outerRadiusMm" << shape.outerRadiusMm << "staticToleranceMm" << SyntheticBreathing::kStaticToleranceMm;
    if (hard.breathHold()) scene << "holdStartS" << hard.breathHoldStartS << "holdEndS" << hard.breathHoldEndS;
    if (inVivo.breathingLateralMm > 0) {
      const cv::Vec2d& direction = scan.breathing().lateralDirection();
      scene << "lateralMm" << inVivo.breathingLateralMm << "lateralDirectionX" << direction[0]
            << "lateralDirectionY" << direction[1];
    }
    scene << "}";
  }
  if (scan.tissueDeforms() && !staticWritten) scene << "staticSurface" << "none: every seen triangle moves";
  if (anyInVivo) {
    scene << "inVivo" << "{";
    if (inVivo.pulse()) {
      const SurfaceSwell& shape = scan.pulse().shape();
      scene << "pulse" << "{" << "amplitudeMm" << inVivo.pulseAmplitudeMm << "periodS" << inVivo.pulsePeriodS
            << "centreXMm" << shape.centreXMm << "centreYMm" << shape.centreYMm << "innerRadiusMm"
            << shape.innerRadiusMm << "outerRadiusMm" << shape.outerRadiusMm << "}";
    }
    if (inVivo.push()) {
      scene << "push" << "{" << "depthMm" << inVivo.pushMm << "dentInnerRadiusMm" << kPushInnerRadiusMm
            << "dentOuterRadiusMm" << pushDentOuterRadiusMm(inVivo.pushMm) << "}";
    }
    scene << "instrumentsAtBorder" << static_cast<int>(inVivo.instrumentsAtBorder)
          << "tissueLook" << tissueLookName(inVivo.tissueLook) << "motionBlurMs" << inVivo.motionBlurMs
          << "interlaced" << static_cast<int>(inVivo.interlaced)
          << "truthTime" << "each frame's time t = index / fps: the even field's mid-exposure (odd rows: t + 0.5 / fps)"
          << "}";
  }
  if (hard.instruments > 0) {
    scene << "instruments" << "[";
    for (int i = 0; i < scan.instruments().count(); ++i) {
      const auto [enter, leave] = scan.instruments().span(i);
      scene << "{" << "firstFrame" << enter << "lastFrame" << leave << "}";
    }
    scene << "]";
  }
  if (hard.cameraOut()) {
    scene << "cameraOut" << "{" << "firstFrame" << hard.cameraOutStart << "endFrame" << hard.cameraOutEnd << "}";
  }
  scene << "smoke" << static_cast<int>(hard.smoke);
  scene.release();
  return written + 1;
}

}  // namespace

int writeSyntheticScan(const SyntheticScan& scan, const std::string& directory, void (*progress)(int, int)) {
  const std::filesystem::path root(directory);
  for (const char* sub : {"left", "right", "groundtruth"}) {
    std::error_code error;
    std::filesystem::create_directories(root / sub, error);
    require(std::filesystem::is_directory(root / sub), "cannot create output folder '" + (root / sub).string() + "'");
  }
  int written = 0;
  const auto image = [&](const std::filesystem::path& path, const cv::Mat& pixels) {
    bool ok = false;
    try {
      ok = cv::imwrite(path.string(), pixels);
    } catch (const cv::Exception&) {
    }
    require(ok, "cannot write image '" + path.string() + "'");
    ++written;
  };
  writeStereoCalibration(scan.calibration(), (root / "rig.yml").string());
  ++written;

  Trajectory trajectory;
  for (int index = 0; index < scan.frameCount(); ++index) {
    const SyntheticScanFrame frame = scan.renderFrame(index);
    const std::string name = cv::format("%06d", index);
    image(root / "left" / (name + ".png"), frame.leftRectified);
    image(root / "right" / (name + ".png"), frame.rightRectified);
    writePfm((root / "groundtruth" / ("depth_" + name + ".pfm")).string(), frame.depthMm);
    ++written;
    if (!frame.instrumentMask.empty()) image(root / "groundtruth" / ("instrument_mask_" + name + ".png"), frame.instrumentMask);
    image(root / "groundtruth" / ("highlight_mask_left_" + name + ".png"), frame.highlightMaskLeft);
    if (frame.tissueInView) {  // else the scope is out: no ground-truth pose
      TimedPose pose;
      pose.timeS = frame.timeS;
      pose.T_world_camera = frame.T_world_camera;
      trajectory.push_back(pose);
    }
    if (progress) progress(index + 1, scan.frameCount());
  }
  writeTumTrajectory((root / "groundtruth" / "trajectory.txt").string(), trajectory,
                     "TissueMosaic synthetic scan ground truth: T_world_camera of the LEFT RECTIFIED camera\n"
                     "world: tissue Z = h(X, Y), +Z into the tissue; millimetres, seconds\n"
                     "t tx ty tz qx qy qz qw");
  ++written;
  const TriangleMesh seen = scan.seenSurfaceMesh(0.5);
  writeMeshPly((root / "groundtruth" / "surface.ply").string(), seen,
               "TissueMosaic synthetic scan: true tissue surface seen by both eyes in at least one frame\n"
               "frame: world (tissue Z = h(X, Y), +Z into the tissue), millimetres");
  ++written;
  if (scan.tissueDeforms()) {
    // The tissue at rest over what the scan saw, and where each of its points is at each frame's time.
    const std::string frameText = "frame: world (tissue Z = h(X, Y), +Z into the tissue), millimetres";
    writeMeshPly((root / "groundtruth" / "rest_surface.ply").string(), seen,
                 "TissueMosaic synthetic scan: the tissue at rest (no breathing, pulse or push) over what the scan saw\n" +
                     frameText);
    ++written;
    for (int index = 0; index < scan.frameCount(); ++index) {
      writeMeshPly((root / "groundtruth" / ("surface_" + cv::format("%06d", index) + ".ply")).string(),
                   scan.frameSurfaceMesh(seen, index),
                   "TissueMosaic synthetic scan: the true tissue at frame " + std::to_string(index) + " (t = " +
                       cv::format("%.6f", scan.timeS(index)) + " s, the even field's mid-exposure); vertex i is "
                       "rest_surface.ply's vertex i moved with the tissue\n" + frameText);
      ++written;
    }
  }
  written += writeHardModeGroundTruth(scan, root / "groundtruth");
  return written;
}

}  // namespace tissuemosaic::synthetic
