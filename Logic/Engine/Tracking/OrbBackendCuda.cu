// The CUDA instantiation of the ORB extractor and the Hamming matcher.
#include "OrbPipeline.inl"

namespace tissuemosaic::orb {

void runOrbPipelineCuda(OrbLevelWorkspace* levels, int levelCount, const OrbSettings& settings, const int8_t* pattern) {
  runOrbPipeline<CudaBackend>(levels, levelCount, settings, pattern);
}

void hammingKnnCuda(const uint64_t* a, int rowsA, const uint64_t* b, int rowsB, int k, int* indices, int* distances) {
  hammingKnn<CudaBackend>(a, rowsA, b, rowsB, k, indices, distances);
}

}  // namespace tissuemosaic::orb
