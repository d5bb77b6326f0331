// The CUDA instantiation of measureSurface's kernels (SurfaceKernels.h).
#include "SurfaceKernels.h"

namespace tissuemosaic::surface {

void measureSurfaceCuda(ImageView<const float> disparityPx, ImageView<Float3> pointsMm, ImageView<Float3> normals,
                        ImageView<uint8_t> valid, const Reprojection& reprojection, int normalRadiusPx,
                        float maxDepthJumpMm, float keptLowestPx, float keptHighestPx) {
  measureSurfaceOn<CudaBackend>(disparityPx, pointsMm, normals, valid, reprojection, normalRadiusPx, maxDepthJumpMm,
                                keptLowestPx, keptHighestPx);
}

}  // namespace tissuemosaic::surface
