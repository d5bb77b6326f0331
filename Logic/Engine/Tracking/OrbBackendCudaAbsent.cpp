// Built only without the CUDA backend: the CUDA entry points say so instead of running.
#include "Core/Error.h"
#include "OrbPipeline.h"

namespace tissuemosaic::orb {

void runOrbPipelineCuda(OrbLevelWorkspace*, int, const OrbSettings&, const int8_t*) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

void hammingKnnCuda(const HammingKnn&, int) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

void refineSubPixelCuda(const subpixel::LucasKanadeRefine&, int) {
  throw Error("this build of TissueMosaic has no CUDA backend");
}

}  // namespace tissuemosaic::orb
