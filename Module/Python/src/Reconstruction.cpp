#include "Reconstruction.h"

#include "ModelOutput.h"  // Module/Cli: the model file as `reconstruct --out` writes it

#include "Core/Error.h"
#include "Core/Stopwatch.h"

#include <chrono>

namespace tissuemosaic::python {

Reconstruction::Reconstruction(std::shared_ptr<Rig> rig, ReconstructionParameters parameters, Device device,
                               const Eigen::Matrix4d& T_world_startCamera, bool keepDisparity)
    : rig_(std::move(rig)), parameters_(std::move(parameters)), device_(device),
      T_world_startCamera_(T_world_startCamera), keepDisparity_(keepDisparity) {
  require(rig_ != nullptr, "Reconstruction needs a rig (Rig.from_file or Rig.rectified)");
  parameters_.validate();
  requireUsableDevice(device_, "Reconstruction");
}

FrameResult Reconstruction::process(const cv::Mat& left, const cv::Mat& right, double timeS, double* engineMs) {
  const std::lock_guard<std::mutex> lock(mutex_);
  require(left.size() == right.size(), cv::format("the left frame is %dx%d but the right one %dx%d", left.cols,
                                                  left.rows, right.cols, right.rows));
  if (!pipeline_) {
    // As the command line: a calibration whose frames are raw makes the pipeline rectify them itself.
    const std::shared_ptr<const StereoGeometry> geometry = rig_->resolve(left.size(), "the frames given to process()");
    pipeline_ = geometry->rectifier
                    ? std::make_unique<ReconstructionPipeline>(*geometry->calibration, parameters_, device_,
                                                               T_world_startCamera_)
                    : std::make_unique<ReconstructionPipeline>(geometry->rectified, parameters_, device_,
                                                               T_world_startCamera_);
    pipeline_->setFrameDisparityKept(keepDisparity_);
  }
  const auto start = std::chrono::steady_clock::now();
  FrameResult result = pipeline_->process(left, right, timeS);
  *engineMs = millisecondsSince(start);
  timing_.add(result);
  if (result.tracked) {
    TimedPose pose;
    pose.timeS = timeS;
    pose.T_world_camera = result.T_world_camera;
    framePoses_.push_back(pose);
  }
  return result;
}

const ReconstructionPipeline& Reconstruction::pipeline() const {
  require(pipeline_ != nullptr, "no frame has been processed yet");
  return *pipeline_;
}

int Reconstruction::frameCount() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return pipeline_ ? pipeline_->frameCount() : 0;
}

ModelPoints Reconstruction::model() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return pipeline_ ? pipeline_->modelSnapshot() : ModelPoints{};
}

Trajectory Reconstruction::keyFrameTrajectory() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  Trajectory keyFrames;
  if (!pipeline_) return keyFrames;
  for (const KeyFramePose& k : pipeline_->keyFrames()) {
    TimedPose pose;
    pose.timeS = k.timeS;
    pose.T_world_camera = k.T_world_camera;
    keyFrames.push_back(pose);
  }
  return keyFrames;
}

Trajectory Reconstruction::frameTrajectory() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return framePoses_;
}

TimingTable Reconstruction::timing() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return timing_;
}

std::string Reconstruction::disparityRangeDescription() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return pipeline().disparityRangeDescription();
}

void Reconstruction::save(const std::string& modelPath, const std::string& trajectoryPath) const {
  cli::checkModelOutputPath(modelPath);
  const ModelPoints points = model();
  require(points.size() > 0, "the reconstruction has no model points yet (tracking never started?)");
  cli::writeModelFile(modelPath, points.cloud, cli::kReconstructedModelComment);
  if (!trajectoryPath.empty()) writeTumTrajectory(trajectoryPath, keyFrameTrajectory(), cli::kKeyFrameTrajectoryHeader);
}

}  // namespace tissuemosaic::python
