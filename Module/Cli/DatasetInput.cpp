// applyDatasetLayout (CommonOptions.h): the public data sets' own layouts as the plain input and geometry options.
#include "CommonOptions.h"

#include "IO/Datasets/HamlynRectified.h"
#include "IO/Datasets/ScaredKeyframe.h"
#include "IO/Datasets/StereoMisSequence.h"

namespace tissuemosaic::cli {

DatasetInput applyDatasetLayout(InputOptions& input, GeometryOptions& geometry) {
  const int datasets = !input.scared.empty() + !input.hamlyn.empty() + !input.stereomis.empty();
  if (datasets == 0) return {};
  const bool otherInput = !input.leftFrames.empty() || !input.leftVideo.empty() || !input.video.empty() ||
                          !input.igtlInput.empty();
  if (datasets > 1 || otherInput) {
    throw UsageError("give exactly one input: --scared, --hamlyn and --stereomis are inputs themselves");
  }
  const std::string option = !input.scared.empty() ? "--scared" : !input.hamlyn.empty() ? "--hamlyn" : "--stereomis";
  const bool calibration = !geometry.calib.empty();
  if (calibration || geometry.focalPx || geometry.cxPx || geometry.cyPx || geometry.doffsPx ||
      (geometry.baselineMm && option != "--hamlyn")) {
    throw UsageError(option + " gives the geometry from the data set's own files: leave out --calib and --focal-px" +
                     std::string(option == "--hamlyn" ? " (--baseline-mm is the one geometry option it takes)" : ""));
  }
  DatasetInput dataset;
  if (!input.scared.empty()) {
    const ScaredKeyframe keyframe = readScaredKeyframe(input.scared);
    input.video = keyframe.video;
    input.videoLayout = "tb";
    geometry.calib = keyframe.calibration;
    dataset.description = "SCARED key frame " + input.scared;
    dataset.poses = keyframe.poses;
    dataset.note = keyframe.posesNote;
  } else if (!input.hamlyn.empty()) {
    const HamlynRectified sequence = readHamlynRectified(input.hamlyn);
    input.leftFrames = sequence.leftFolder;
    input.rightFrames = sequence.rightFolder;
    geometry.focalPx = sequence.focalPx;
    geometry.cxPx = sequence.cxPx;
    geometry.cyPx = sequence.cyPx;
    if (!geometry.baselineMm) geometry.baselineMm = sequence.baselineMm;
    if (!geometry.baselineMm) {
      throw UsageError("--hamlyn '" + input.hamlyn + "': its intrinsics.txt holds no baseline: give --baseline-mm");
    }
    dataset.description = "Hamlyn rectified sequence " + input.hamlyn;
  } else {
    const StereoMisSequence sequence = findStereoMisSequence(input.stereomis);
    input.video = sequence.video;
    input.videoLayout = "sbs";
    geometry.calib = sequence.calibration;
    dataset.description = "StereoMIS sequence " + sequence.video;
  }
  input.scared.clear();
  input.hamlyn.clear();
  input.stereomis.clear();
  return dataset;
}

}  // namespace tissuemosaic::cli
