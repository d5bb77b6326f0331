#include "SyntheticHardMode.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <string>

namespace tissuemosaic::synthetic {

void SyntheticHardModeOptions::validate(int frames) const {
  constexpr parameters::Group kSyntheticScan{"synthetic scan"};
  kSyntheticScan.requireRange("breathing amplitude (mm)", breathingAmplitudeMm, 0.0, 10.0);
  kSyntheticScan.requireRange("breathing period (s)", breathingPeriodS, 0.5, 60.0);
  kSyntheticScan.requireRange("breathing radius (mm)", breathingRadiusMm, 5.0, 500.0);
  kSyntheticScan.requireRange("instruments", instruments, 0, 4);
  if (breathHold()) {
    require(breathing(), "synthetic scan: a breath hold needs breathing (--breathing-mm)");
    require(breathHoldEndS > breathHoldStartS,
            "synthetic scan: the breath hold S:E needs 0 <= S < E (s), got " + std::to_string(breathHoldStartS) + ":" +
                std::to_string(breathHoldEndS));
  }
  if (cameraOut()) {
    require(cameraOutStart >= 1 && cameraOutEnd > cameraOutStart && cameraOutEnd < frames,
            "synthetic scan: the camera-out frames S:E need 1 <= S < E < frames (" + std::to_string(frames) +
                "): tissue before and after them");
  }
}

}  // namespace tissuemosaic::synthetic
