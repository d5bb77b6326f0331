// Built only without the CUDA backend: the CUDA entry point says so instead of running.
#include "Error.h"
#include "SurfaceKernels.h"

namespace tissuemosaic::surface {

void measureSurfaceCuda(ImageView<const float>, ImageView<Float3>, ImageView<Float3>, ImageView<uint8_t>,
                        const Reprojection&, int, float, float, float) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

}  // namespace tissuemosaic::surface
