// The CPU instantiation of the ORB extractor and the Hamming matcher.
#include "OrbPipeline.inl"

namespace tissuemosaic::orb {

void runOrbPipelineCpu(OrbLevelWorkspace* levels, int levelCount, const OrbSettings& settings, const int8_t* pattern) {
  runOrbPipeline<CpuBackend>(levels, levelCount, settings, pattern);
}

void hammingKnnCpu(const HammingKnn& knn, int rowsA) { parallelFor<CpuBackend>(rowsA, knn, 16); }

void refineSubPixelCpu(const subpixel::LucasKanadeRefine& refine, int count) {
  parallelFor<CpuBackend>(count, refine, 16);
}

}  // namespace tissuemosaic::orb
