#pragma once
/// @file SyntheticHardMode.h
/// @brief What makes a synthetic scan look like surgery rather than a still phantom (`tissuemosaic synth scan`
/// --breathing-mm, --instruments, --camera-out, --smoke): part of the tissue breathes (SyntheticBreathing.h),
/// instruments enter, work over the tissue and leave (SyntheticInstruments.h), the scope is withdrawn and put back
/// (SyntheticCameraOut.h), smoke drifts over the view (SyntheticHaze.h). All off by default; each deterministic
/// from the scan's seed, with its ground truth. The in-vivo mode (SyntheticInVivo.h) builds on these.
namespace tissuemosaic::synthetic {

struct SyntheticHardModeOptions {
  /// Largest displacement (mm, toward the scope) of the breathing part of the surface, at its centre; 0: none.
  double breathingAmplitudeMm = 0;
  double breathingPeriodS = 4.0;  ///< one breath
  /// Radius (mm, on the tissue) of the breathing part: it rises by the full amplitude over its inner 10/18 and
  /// tapers to zero at this radius. The default (18 mm) is a quarter to a third of a 960x540 view at 70-100 mm;
  /// 60 mm or more makes the whole view breathe, as a scope held still over the abdomen sees it.
  double breathingRadiusMm = 18.0;
  /// From breathHoldStartS to breathHoldEndS (s) the ventilator pauses: the breathing tissue rests where it was at
  /// the start, then breathes on from there. breathHoldStartS < 0: no hold.
  double breathHoldStartS = -1, breathHoldEndS = -1;
  int instruments = 0;            ///< rigid instruments (shaft and jaws) that enter, move over the tissue and leave
  /// Frames [cameraOutStart, cameraOutEnd) show no tissue (the scope withdrawn: smoke, dark, a smeared lens); at
  /// cameraOutEnd the camera is back about 10 mm and 10 degrees from where it left. cameraOutStart < 0: none.
  int cameraOutStart = -1, cameraOutEnd = -1;
  bool smoke = false;             ///< a drifting haze over the tissue in every frame

  bool breathing() const { return breathingAmplitudeMm > 0; }
  bool breathHold() const { return breathHoldStartS >= 0; }
  bool cameraOut() const { return cameraOutStart >= 0; }
  /// True when frame `index` shows no tissue (inside the camera-out span).
  bool outOfView(int index) const { return cameraOut() && index >= cameraOutStart && index < cameraOutEnd; }
  /// Throws Error naming the first option out of range (frames: the scan's frame count).
  void validate(int frames) const;
};

}  // namespace tissuemosaic::synthetic
