// Built only without the CUDA backend: the CUDA entry points say so instead of running.
#include "Core/Error.h"
#include "DisparitySampling.h"
#include "StereoPipeline.h"

namespace tissuemosaic::stereo {

void computeZnccVolumeCuda(const ZnccVolumeInputs&) { throw Error("this build of TissueMosaic has no CUDA backend"); }

void computeScanlinePathsCuda(const ScanlineInputs&) { throw Error("this build of TissueMosaic has no CUDA backend"); }

void detectHighlightSeedsCuda(const DetectHighlightSeeds&) { throw Error("this build of TissueMosaic has no CUDA backend"); }

void runStereoPipelineCuda(StereoWorkspace&, const StereoParameters&, StereoTimingsMs&, StereoExplanation*) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

}  // namespace tissuemosaic::stereo

namespace tissuemosaic {

void sampleDisparitiesCuda(ImageView<const float>, const float*, float*, int) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

}  // namespace tissuemosaic
