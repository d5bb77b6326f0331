#pragma once
/// @file RefinementPipeline.h
/// @brief The device-resident working set of one key-frame refinement and the backend entry points that run the
/// per-residual and per-point steps on it. The steps are one template (RefinementPipeline.inl) instantiated for
/// the CPU (RefinementBackendCpu.cpp) and for CUDA (RefinementBackendCuda.cu); RefinementBackendCudaAbsent.cpp
/// stands in without CUDA. The LM bookkeeping around them (RefinementSolver.cpp) is the same for both.
#include "Core/Buffer.h"
#include "Core/Image.h"
#include "RefinementKernels.h"

namespace tissuemosaic::refinement {

/// Sizes and device buffers of one problem. Residuals: the observations (sorted by frame) first, then the model
/// points (the key frame's ICP term); each chunk of residuals belongs to one frame.
struct RefinementWorkspace {
  Device device = Device::Cpu;
  Camera camera{};
  RobustConstants robust{};
  int frameCount = 0, observationCount = 0, icpCount = 0, freeCount = 0, chunkCount = 0;
  int pointIterations = 1;           ///< LM iterations of each point update
  Buffer<Pose> poses;                ///< frameCount; frame 0 is the key frame
  Buffer<double> pointsWorldMm;      ///< 3 per point
  Buffer<uint8_t> pointFixed;        ///< 1 per point
  Buffer<uint8_t> frameFixedOnly;    ///< 1 per frame: its pose step sees only fixed points (BaPoseTerms)
  Buffer<Observation> observations;
  Buffer<int> freePoints, pointObservationBegin, pointObservationIndex;
  Buffer<double> pointLambdas;       ///< freeCount
  Buffer<Float3> modelPointsWorldMm; ///< icpCount
  Image<Float3> measuredPointsCopy, measuredNormalsCopy;  ///< the maps, when they had to be copied to this device
  ImageView<const Float3> measuredPointsCameraMm, measuredNormalsCamera;  ///< what the ICP term reads
  Buffer<double> terms;              ///< kTerms x (observationCount + icpCount), structure of arrays
  Buffer<int> chunkBegin;            ///< chunkCount + 1
  Buffer<double> partials;           ///< chunkCount x kTerms
  Pose keyFramePose{};               ///< host copy of poses[0] for the ICP functor
};

/// Writes every residual's terms at the poses in workspace.poses and sums them per chunk into workspace.partials.
void evaluatePoseTermsCpu(RefinementWorkspace& workspace);
void evaluatePoseTermsCuda(RefinementWorkspace& workspace);
/// Runs UpdatePoints on every free point (poses fixed).
void updatePointsCpu(RefinementWorkspace& workspace);
void updatePointsCuda(RefinementWorkspace& workspace);

}  // namespace tissuemosaic::refinement
