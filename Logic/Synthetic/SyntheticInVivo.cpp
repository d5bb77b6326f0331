#include "SyntheticInVivo.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"
#include "SyntheticBreathing.h"
#include "SyntheticHardMode.h"
#include "SyntheticScan.h"

namespace tissuemosaic::synthetic {

namespace {
/// The breathing's sideways slide stays one to one with a wide margin: its largest strain (lateral x the shape's
/// steepest weight slope) at most this.
constexpr double kMaxLateralStrain = 0.3;
}  // namespace

void SyntheticInVivoOptions::validate(double fps, const SyntheticHardModeOptions& hard) const {
  constexpr parameters::Group kSyntheticScan{"synthetic scan"};
  kSyntheticScan.requireRange("lateral breathing (mm)", breathingLateralMm, 0.0, 10.0);
  kSyntheticScan.requireRange("pulse amplitude (mm)", pulseAmplitudeMm, 0.0, 3.0);
  kSyntheticScan.requireRange("pulse period (s)", pulsePeriodS, 0.2, 5.0);
  kSyntheticScan.requireRange("pulse radius (mm)", pulseRadiusMm, 2.0, 30.0);
  kSyntheticScan.requireRange("push (mm)", pushMm, 0.0, 5.0);
  kSyntheticScan.requireRange("motion blur (ms)", motionBlurMs, 0.0, 1000.0);
  if (breathingLateralMm > 0) {
    require(hard.breathing(), "synthetic scan: lateral breathing needs breathing (--breathing-mm)");
    SurfaceSwell shape;
    shape.innerRadiusMm = SyntheticBreathing::kInnerShare * hard.breathingRadiusMm;
    shape.outerRadiusMm = hard.breathingRadiusMm;
    require(breathingLateralMm * shape.maxWeightSlopePerMm() <= kMaxLateralStrain,
            "synthetic scan: lateral breathing of " + std::to_string(breathingLateralMm) +
                " mm tears a breathing disc of radius " + std::to_string(hard.breathingRadiusMm) +
                " mm apart; lower --breathing-lateral-mm or widen --breathing-radius-mm");
  }
  if (pushMm > 0) require(hard.instruments > 0, "synthetic scan: a push needs instruments (--instruments)");
  if (instrumentsAtBorder) {
    require(hard.instruments > 0, "synthetic scan: instruments at the border need instruments (--instruments)");
  }
  // Each field's exposure ends before the next field starts.
  const double fieldMs = 1000.0 / fps / (interlaced ? 2.0 : 1.0);
  require(motionBlurMs <= fieldMs, "synthetic scan: a motion blur of " + std::to_string(motionBlurMs) +
                                       " ms is longer than a " + (interlaced ? std::string("field") : "frame") +
                                       " (" + std::to_string(fieldMs) + " ms at this frame rate)");
}

void applyInVivoPreset(SyntheticScanOptions& options) {
  // A still scope, held 80 mm from the tissue and looking straight at it.
  options.minSpeedMmPerS = options.maxSpeedMmPerS = 0;
  options.maxTiltDeg = options.maxRollDeg = 0;
  options.minWorkingDistanceMm = options.maxWorkingDistanceMm = 80.0;
  // A ventilated patient (12-16 breaths a minute): the whole view rises and slides a few mm with each breath.
  SyntheticHardModeOptions& hard = options.hardMode;
  hard.breathingAmplitudeMm = 3.0;
  hard.breathingPeriodS = 4.3;
  hard.breathingRadiusMm = 100.0;
  hard.instruments = 2;
  SyntheticInVivoOptions& inVivo = options.inVivo;
  inVivo.breathingLateralMm = 1.5;
  inVivo.pulseAmplitudeMm = 0.5;
  inVivo.pulsePeriodS = 0.85;
  inVivo.pulseRadiusMm = 8.0;
  inVivo.pushMm = 2.0;
  inVivo.instrumentsAtBorder = true;
  inVivo.tissueLook = TissueLook::InVivo;
  inVivo.motionBlurMs = 8.0;
  inVivo.interlaced = true;
  options.lighting = SyntheticLighting::Realistic;
}

}  // namespace tissuemosaic::synthetic
