#include "SyntheticHardMode.h"

#include "Core/Error.h"
#include "Core/ParameterChecks.h"

#include <string>

namespace tissuemosaic::synthetic {

void SyntheticHardModeOptions::validate(int frames) const {
  const auto range = [](const char* name, double value, double low, double high) {
    parameters::requireRange("synthetic scan", name, value, low, high);
  };
  range("breathing amplitude (mm)", breathingAmplitudeMm, 0.0, 10.0);
  range("breathing period (s)", breathingPeriodS, 0.5, 60.0);
  range("breathing radius (mm)", breathingRadiusMm, 5.0, 500.0);
  range("instruments", instruments, 0, 4);
  if (cameraOut()) {
    require(cameraOutStart >= 1 && cameraOutEnd > cameraOutStart && cameraOutEnd < frames,
            "synthetic scan: the camera-out frames S:E need 1 <= S < E < frames (" + std::to_string(frames) +
                "): tissue before and after them");
  }
}

}  // namespace tissuemosaic::synthetic
