#pragma once
/// @file SyntheticInVivo.h
/// @brief The in-vivo mode of the synthetic scans (`tissuemosaic synth scan --in-vivo`): what real in-vivo video shows
/// and the other synthetic scans do not, with ground truth for every frame. Beyond the hard mode
/// (SyntheticHardMode.h): the breathing also slides the tissue sideways, a small patch pulses with the heartbeat
/// (SyntheticPulse.h), instruments press into the tissue (SyntheticPush.h), the tissue is darker, blood-red and less
/// textured (TissueLook::InVivo), the exposure blurs motion and the frames may be interlaced (SyntheticCapture.h).
/// All off by default (the scans are then bit for bit those of before); each deterministic from the seed.
///
/// Ground truth (SyntheticScan.h): the truth of a frame (pose, depth, disparity, masks, the deformed surface) is for
/// its time t = index / fps, which is the middle of the exposure of the even field; an interlaced frame's odd rows
/// show the scene half a frame period later.
#include "TissueTexture.h"

namespace tissuemosaic::synthetic {

struct SyntheticHardModeOptions;
struct SyntheticScanOptions;

struct SyntheticInVivoOptions {
  /// The breathing's sideways part: at the breath's peak the breathing tissue has slid this far (mm) along a seeded
  /// direction of the tissue plane, with the same shape as the swell. Needs breathing. 0: none.
  double breathingLateralMm = 0;
  /// Pulsation: a patch of pulseRadiusMm at a seeded place in view rises toward the scope by up to pulseAmplitudeMm
  /// once per pulsePeriodS (a heartbeat). 0: none.
  double pulseAmplitudeMm = 0;
  double pulsePeriodS = 0.85;   ///< about 70 beats a minute
  double pulseRadiusMm = 8.0;
  /// Each instrument presses its closed jaws this far (mm) into the tissue in the middle of its span. Needs
  /// instruments. 0: none.
  double pushMm = 0;
  /// The instruments work near the view's border (their tips at about 60 % of the way from the centre to the edge,
  /// the shafts coming in from that side) instead of around its centre.
  bool instrumentsAtBorder = false;
  TissueLook tissueLook = TissueLook::Standard;
  /// Exposure time (ms): each field is the average of the scene over this span centred on its time. 0: none.
  double motionBlurMs = 0;
  /// Even rows at the frame's time, odd rows half a frame period later.
  bool interlaced = false;

  bool pulse() const { return pulseAmplitudeMm > 0; }
  bool push() const { return pushMm > 0; }
  bool motionBlur() const { return motionBlurMs > 0; }
  /// True when the exposure is more than one instant (blur or fields).
  bool timedCapture() const { return motionBlur() || interlaced; }
  /// Throws Error naming the first option out of range or missing what it needs.
  void validate(double fps, const SyntheticHardModeOptions& hardMode) const;
};

/// `tissuemosaic synth scan --in-vivo`: a still scope 80 mm over a whole view that breathes (3 mm toward the scope
/// and 1.5 mm sideways every 4.3 s, 14 breaths a minute), a pulsing patch (0.5 mm, 0.85 s, 8 mm), two instruments
/// working near the view's border that press 2 mm into the tissue, the in-vivo tissue look under the realistic light
/// (wet highlights), an 8 ms exposure and interlaced fields. Sets only these options; the caller's others stay.
void applyInVivoPreset(SyntheticScanOptions& options);

}  // namespace tissuemosaic::synthetic
