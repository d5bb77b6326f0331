#pragma once
/// @file SyntheticScan.h
/// @brief A synthetic scanning video with exact ground truth, deterministic from a seed: the stereo scope of
/// SyntheticStereoScene sweeps the liver-like surface along a smooth lawn-mower path (a Lissajous raster: slow along
/// X, back and forth along Y), 60-120 mm from the tissue, at a speed that varies smoothly within a band, with gentle
/// tilt and roll. The texture's smooth patches give low-texture stretches. Frames are rendered on demand with the
/// rectified cameras (as StereoRectifier would produce them from rig calibration()), so the ground truth is exact.
///
/// World frame: the tissue is Z = h(X, Y), +Z into the tissue (TissueSurface.h), millimetres. Poses are
/// T_world_camera of the LEFT RECTIFIED camera (x right, y down, z forward).
#include "Core/StereoRig.h"
#include "IO/MeshPly.h"
#include "SurfaceSwell.h"
#include "SyntheticHardMode.h"
#include "SyntheticInVivo.h"
#include "SyntheticLighting.h"

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace tissuemosaic::synthetic {

class TissueSurface;
class SyntheticBreathing;
class SyntheticInstruments;
class SyntheticPulse;

/// How the scope's working distance changes over a scan.
enum class WorkingDistanceProfile {
  Oscillating,  ///< slowly up and down between the minimum and the maximum
  Approaching,  ///< steadily from the maximum down to the minimum over the whole scan (the scope moves in)
};

struct SyntheticScanOptions {
  int width = 960, height = 540;     ///< image size in pixels
  uint32_t seed = 1;                 ///< same seed and options: identical frames, bit for bit
  int frames = 120;
  double fps = 30.0;
  double minWorkingDistanceMm = 70.0, maxWorkingDistanceMm = 100.0;  ///< height of the scope tip above the tissue
  double minSpeedMmPerS = 6.0, maxSpeedMmPerS = 20.0;  ///< speed along the path (height changes add a little)
  double rasterWidthMm = 50.0, rasterHeightMm = 30.0;  ///< the path's extent on the tissue (X x Y)
  int rasterSweeps = 5;              ///< back-and-forth sweeps along Y per pass along X
  double maxTiltDeg = 10.0;          ///< largest angle between the optical axis and world +Z
  double maxRollDeg = 6.0;           ///< largest rotation about the optical axis
  double reliefMm = 4.0;             ///< amplitude of the surface's random bumps
  double baselineMm = 5.0;
  double focalPx = 0;                ///< 0: 1000 px scaled by width / 960
  WorkingDistanceProfile distanceProfile = WorkingDistanceProfile::Oscillating;
  /// The exposure follows the working distance (as a scope's automatic exposure does), instead of being set for the
  /// middle of the working range: a scope that moves from 110 to 50 mm would otherwise see 5x more light at the end.
  bool autoExposure = false;
  /// doffs of the rectified pair: the right view's principal point lies this far right of the left's (as
  /// RectificationMode::KeepPrincipalPoints leaves it), so every disparity is f B / Z - doffs (negative ones too).
  /// rig.yml's own rectification has none: frames rendered with an offset need its value (reconstruct --doffs-px).
  double rectifiedDisparityOffsetPx = 0;
  double noiseStdGrey = 1.5;
  int supersampling = 2;
  SyntheticHardModeOptions hardMode;  ///< breathing, instruments, camera-out, smoke (all off by default)
  SyntheticLighting lighting = SyntheticLighting::Standard;  ///< the look (SyntheticLighting.h)
  /// Lateral breathing, pulsation, push, the in-vivo tissue look, motion blur, interlacing (all off by default;
  /// SyntheticInVivo.h, applyInVivoPreset).
  SyntheticInVivoOptions inVivo;

  /// Throws Error naming the first option out of range.
  void validate() const;
};

struct SyntheticScanFrame {
  int index = 0;
  double timeS = 0;
  cv::Mat leftRectified, rightRectified;  ///< CV_8UC3 BGR
  cv::Mat disparityPx;                    ///< CV_32F left-view ground truth, NaN where not seen by both eyes
  cv::Mat depthMm;                        ///< CV_32F along the left rectified optical axis, NaN as above
  cv::Mat highlightMaskLeft;              ///< CV_8U, left rectified view: 255 on specular highlights
  Eigen::Matrix4d T_world_camera = Eigen::Matrix4d::Identity();  ///< left rectified camera
  /// False for a camera-out frame (SyntheticCameraOut.h): no tissue, NaN truth, and T_world_camera is not ground
  /// truth (the withdrawn scope).
  bool tissueInView = true;
  /// With instruments: CV_8U, 255 where an instrument covers the left pixel's centre (depthMm and disparityPx are
  /// the tissue's, behind it). Empty without instruments.
  cv::Mat instrumentMask;
};

class SyntheticScan {
public:
  /// Builds the rig, the path, the surface and its texture (a second or so at 960x540). Throws Error for invalid
  /// options or a path that sees the surface too obliquely (self-occlusion, which the ground truth does not model).
  explicit SyntheticScan(const SyntheticScanOptions& options);
  ~SyntheticScan();
  SyntheticScan(const SyntheticScan&) = delete;
  SyntheticScan& operator=(const SyntheticScan&) = delete;

  const SyntheticScanOptions& options() const;
  int frameCount() const;
  /// Raw rig (what rig.yml holds) and the rectified geometry the frames are rendered with.
  const StereoCalibration& calibration() const;
  const RectifiedGeometry& geometry() const;
  /// Ground-truth pose of the left rectified camera at frame index (0 <= index < frameCount()).
  Eigen::Matrix4d T_world_camera(int index) const;
  double timeS(int index) const;
  /// Renders frame index: both rectified views and ground-truth disparity and depth. With motion blur or
  /// interlacing (options().inVivo) the views are composed over the exposure and the fields (SyntheticCapture.h);
  /// the truth (depth, disparity, masks, pose) is for the frame's time timeS(index), the even field's mid-exposure.
  SyntheticScanFrame renderFrame(int index) const;
  /// Frame index's scene as one instantaneous exposure offsetS seconds after its time (no blur, no fields), truth
  /// included, all at that instant: renderFrame's parts, for tests. Same noise as renderFrame(index).
  SyntheticScanFrame renderFrameAt(int index, double offsetS) const;
  /// False for the camera-out frames (options().hardMode), whose pose is not ground truth.
  bool tissueInView(int index) const;
  /// The frames that show tissue, in order.
  std::vector<int> tissueFrames() const;
  /// The breathing and the instruments (inactive / none without the hard-mode options).
  const SyntheticBreathing& breathing() const;
  const SyntheticInstruments& instruments() const;
  /// The pulsation (inactive without options().inVivo.pulseAmplitudeMm).
  const SyntheticPulse& pulse() const;

  /// True when the tissue moves (breathing, pulsation or push): the writer then adds rest_surface.ply and
  /// surface_NNNNNN.ply.
  bool tissueDeforms() const;
  /// The true tissue at frame index, offsetS seconds after its time (world frame, mm): surface() deformed by the
  /// breathing (and its lateral part), the pulsation and the instruments' dents. Frame index's ground truth is
  /// surfaceAt(index, 0). A copy: take it once per frame, then ask it heights (TissueSurface::heightMm).
  TissueSurface surfaceAt(int index, double offsetS = 0) const;
  /// The true surface's height at world (x, y) in frame index: surfaceAt(index).heightMm(x, y) (builds it on each call).
  double surfaceHeightMm(double xMm, double yMm, int index) const;
  /// How far the tissue point resting at world XY (restXMm, restYMm) (on surface()) has moved at frame index (mm,
  /// world frame; lateral breathing moves it in X and Y too).
  cv::Vec3d displacementMm(double restXMm, double restYMm, int index) const;
  /// restMesh (vertices on surface(), such as seenSurfaceMesh()) with every vertex moved to where its tissue point
  /// is at frame index: the same triangles, the frame's true surface (world frame, mm).
  TriangleMesh frameSurfaceMesh(const TriangleMesh& restMesh, int index) const;
  /// The instruments' dents at frame index + offsetS (SyntheticPush.h): those with amplitude > 0 (empty without push).
  std::vector<SurfaceSwell> pushDentsAt(int index, double offsetS = 0) const;

  const TissueSurface& surface() const;
  /// World XY rectangle seen by some frame (with a margin): where the texture and the surface mesh are defined.
  cv::Rect2d scannedDomainMm() const;
  /// The true surface over scannedDomainMm() as a grid of triangles (vertices exactly on h, world frame, mm).
  TriangleMesh surfaceMesh(double spacingMm = 0.5) const;
  /// Pixels this close to an image edge do not count as seen (stereo windows do not reach there either).
  static constexpr double kSeenBorderPx = 5.0;
  /// What the scan saw with both eyes: the triangles of surfaceMesh(spacingMm) for which, in at least one frame,
  /// every vertex lies in front of the left rectified camera and projects inside both rectified images shrunk by
  /// kSeenBorderPx (pixel centres are integers: kSeenBorderPx <= u <= width - 1 - kSeenBorderPx, same for v).
  /// Vertices no kept triangle uses are dropped. Self-occlusion is not tested: the constructor rejects paths where
  /// it could occur. Tests every frameStep-th frame and the last one (1: all); runs in parallel, about 0.1 s per
  /// 100 frames at 960x540. Throws Error when no triangle is seen.
  TriangleMesh seenSurfaceMesh(double spacingMm = 0.5, int frameStep = 1) const;
  /// seenSurfaceMesh without the triangles that breathing moves (SyntheticBreathing::isStatic at every vertex), nor
  /// those the pulsation or a push reaches: the part of the surface that never moves, the reference of a scan with
  /// breathing. Throws Error when every triangle moves, unless allowEmpty (then an empty mesh).
  TriangleMesh staticSurfaceMesh(double spacingMm = 0.5, int frameStep = 1, bool allowEmpty = false) const;
  /// The instruments' surfaces over every frame with tissue (SyntheticInstruments::surfaceMesh); empty without.
  TriangleMesh instrumentSurfaceMesh() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Writes DIR/left/000000.png.., DIR/right/.. (rectified), DIR/rig.yml (raw rig calibration), and
/// DIR/groundtruth/trajectory.txt (TUM, T_world_camera of the left rectified camera, mm; no line for a camera-out
/// frame), surface.ply (world frame triangle mesh: seenSurfaceMesh(0.5), the surface the scan saw with both eyes, so
/// that a reconstruction's coverage of it is a fair score), depth_000000.pfm.. (mm, left rectified view, the tissue
/// at that frame) and highlight_mask_left_000000.png.. (255 on specular highlights, left rectified view). With the
/// hard-mode options also: static_surface.ply (breathing: staticSurfaceMesh(0.5)), instrument_mask_000000.png.. and
/// instruments.ply (instruments: instrumentSurfaceMesh()), and scene.yml (what breathes, when each instrument is in,
/// the camera-out span; the in-vivo options). When the tissue deforms (tissueDeforms()): rest_surface.ply (the tissue
/// at rest over what the scan saw, seenSurfaceMesh(0.5), whole) and surface_000000.ply.. (frameSurfaceMesh of it:
/// the true surface at each frame's time, the same triangles). static_surface.ply is left out when nothing stays
/// still. progress (optional) is called after each frame.
/// Returns the number of files written. Throws Error when a file cannot be written.
int writeSyntheticScan(const SyntheticScan& scan, const std::string& directory,
                       void (*progress)(int frame, int frames) = nullptr);

}  // namespace tissuemosaic::synthetic
