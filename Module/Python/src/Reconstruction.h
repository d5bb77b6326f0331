#pragma once
/// @file Reconstruction.h
/// @brief The Python module's Reconstruction: the engine's ReconstructionPipeline fed frame by frame, built at the
/// first frame (whose size resolves the rig, as the command line resolves it with its input's), with the key-frame
/// and per-frame trajectories and the runtime table that `tissuemosaic reconstruct` keeps.
#include "Rig.h"

#include "IO/TrajectoryTum.h"
#include "Reconstruction/ReconstructionPipeline.h"
#include "Reconstruction/TimingTable.h"

#include <memory>
#include <mutex>
#include <string>

namespace tissuemosaic::python {

class Reconstruction {
public:
  /// Checks the parameters and the device at once (Error); the pipeline waits for the first frame.
  Reconstruction(std::shared_ptr<Rig> rig, ReconstructionParameters parameters, Device device,
                 const Eigen::Matrix4d& T_world_startCamera, bool keepDisparity);

  /// One frame: 8-bit BGR or grey images, or RGB ones (rgb: the pipeline reads them in that order, without a
  /// conversion or a copy). Thread-safe: calls on one object run one at a time. engineMs: the milliseconds of
  /// ReconstructionPipeline::process alone.
  FrameResult process(const cv::Mat& left, const cv::Mat& right, bool rgb, double timeS, double* engineMs);

  int frameCount() const;
  ModelPoints model() const;
  /// The model where the tissue is now (fusion.deformation on); model() itself otherwise.
  ModelPoints liveModel() const;
  Trajectory keyFrameTrajectory() const;
  Trajectory frameTrajectory() const;  ///< every tracked frame
  TimingTable timing() const;
  /// The model as `reconstruct --out` writes it (.ply; .vtp in builds with VTK), and optionally the key-frame
  /// trajectory as `--trajectory` writes it.
  void save(const std::string& modelPath, const std::string& trajectoryPath) const;
  std::string disparityRangeDescription() const;
  Device device() const { return device_; }

private:
  const ReconstructionPipeline& pipeline() const;  ///< Error before the first frame
  void build(const cv::Size& frameSize);            ///< the pipeline for frames of this size (under the lock)

  std::shared_ptr<Rig> rig_;
  ReconstructionParameters parameters_;
  Device device_;
  Eigen::Matrix4d T_world_startCamera_;
  bool keepDisparity_;
  mutable std::mutex mutex_;
  std::unique_ptr<ReconstructionPipeline> pipeline_;
  TimingTable timing_;
  Trajectory framePoses_;
};

}  // namespace tissuemosaic::python
