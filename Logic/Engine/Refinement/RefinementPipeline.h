#pragma once
/// @file RefinementPipeline.h
/// @brief The device-resident working set of one key-frame refinement and the backend entry points that run the
/// per-residual and per-point steps on it. The steps are one template (RefinementPipeline.inl) instantiated for
/// the CPU (RefinementBackendCpu.cpp) and for CUDA (RefinementBackendCuda.cu); RefinementBackendCudaAbsent.cpp
/// stands in without CUDA. The LM's pose iterations run there too (PoseLmKernels.h); RefinementSolver.cpp drives them.
#include "Core/Buffer.h"
#include "Core/Image.h"
#include "PoseLmKernels.h"
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
  double initialLambda = 1e-3;       ///< of the pose LM
  Buffer<Pose> poses;                ///< frameCount; frame 0 is the key frame
  Buffer<double> pointsWorldMm;      ///< 3 per point
  Buffer<uint8_t> pointFixed;        ///< 1 per point
  Buffer<uint8_t> frameFixedOnly;    ///< 1 per frame: in a fixedPointsOnly run its pose step sees only fixed points
  Buffer<Observation> observations;
  Buffer<int> freePoints, pointObservationBegin, pointObservationIndex;
  Buffer<double> pointLambdas;       ///< freeCount
  Buffer<Float3> modelPointsWorldMm; ///< icpCount
  Image<Float3> measuredPointsCopy, measuredNormalsCopy;  ///< the maps, when they had to be copied to this device
  ImageView<const Float3> measuredPointsCameraMm, measuredNormalsCamera;  ///< what the ICP term reads
  Buffer<int> chunkBegin;            ///< chunkCount + 1
  Buffer<double> partials;           ///< chunkCount x kTerms
  Buffer<int> frameChunkBegin;       ///< frameCount + 1: frame f's chunks are frameChunks[begin[f] .. begin[f + 1])
  Buffer<int> frameChunks;           ///< chunkCount
  // The pose LM's state (PoseLmKernels.h).
  Buffer<Pose> candidatePoses;       ///< frameCount
  Buffer<uint8_t> stepped;           ///< frameCount
  Buffer<double> poseLambdas;        ///< frameCount
  Buffer<double> currentTerms;       ///< frameCount x kTerms, at poses
  Buffer<double> trialTerms;         ///< frameCount x kTerms, at candidatePoses
  Buffer<double> gains;              ///< frameCount: relative cost decrease of the last iteration
  Buffer<PoseLmControl> control;     ///< 1
};

/// How a run of pose iterations starts.
struct PoseRun {
  int iterations = 0;            ///< 0: only evaluate currentTerms at the poses
  bool fixedPointsOnly = false;  ///< frames flagged in frameFixedOnly count only their fixed points' observations
  bool resetLambdas = false;     ///< every frame starts from initialLambda (else only those whose steps kept failing)
};

/// Queues run.iterations LM iterations on every pose at once (points fixed), after evaluating currentTerms at the
/// poses. Nothing is waited for: read currentTerms, poses or control afterwards (their download waits).
void runPoseStepsCpu(RefinementWorkspace& workspace, const PoseRun& run);
void runPoseStepsCuda(RefinementWorkspace& workspace, const PoseRun& run);
/// Runs UpdatePoints on every free point (poses fixed).
void updatePointsCpu(RefinementWorkspace& workspace);
void updatePointsCuda(RefinementWorkspace& workspace);

}  // namespace tissuemosaic::refinement
