#include "Reconstruction.h"

#include "ModelFile.h"  // Logic/ModelFile: the model file as `reconstruct --out` writes it

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
  // Built now when the rig knows the frames' size (the usual case), else at the first frame.
  if (const std::optional<cv::Size> size = rig_->imageSize()) build(*size);
}

void Reconstruction::build(const cv::Size& frameSize) {
  // As the command line: a calibration whose frames are raw makes the pipeline rectify them itself.
  const std::shared_ptr<const StereoGeometry> geometry = rig_->resolve(frameSize, "the frames given to process()");
  requireDisparityRangeMeetsImage(parameters_.stereo, frameSize.width);
  pipeline_ = geometry->rectifier
                  ? std::make_unique<ReconstructionPipeline>(*geometry->calibration, parameters_, device_,
                                                             T_world_startCamera_)
                  : std::make_unique<ReconstructionPipeline>(geometry->rectified, parameters_, device_,
                                                             T_world_startCamera_);
  pipeline_->setFrameDisparityKept(keepDisparity_);
}

FrameResult Reconstruction::process(const cv::Mat& leftGiven, const cv::Mat& rightGiven, bool rgb, double timeS,
                                    double* engineMs) {
  const std::lock_guard<std::mutex> lock(mutex_);
  require(leftGiven.size() == rightGiven.size(),
          cv::format("the left frame is %dx%d but the right one %dx%d", leftGiven.cols, leftGiven.rows,
                     rightGiven.cols, rightGiven.rows));
  if (!pipeline_) {
    build(leftGiven.size());
  } else if (leftGiven.size() != pipeline_->geometry().imageSize) {
    rig_->resolve(leftGiven.size(), "the frames given to process()");  // the CLI's message: "the calibration is for"
  }
  // RGB frames go to the engine as they are (no conversion, no copy): it reads them in that order.
  const auto start = std::chrono::steady_clock::now();
  FrameResult result =
      pipeline_->process(leftGiven, rightGiven, timeS, rgb ? ChannelOrder::Rgb : ChannelOrder::Bgr);
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

ModelPoints Reconstruction::liveModel() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return pipeline_ ? pipeline_->liveModelSnapshot() : ModelPoints{};
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
  checkModelOutputPath(modelPath);
  const ModelPoints points = model();
  require(points.size() > 0, "the reconstruction has no model points yet (tracking never started?)");
  writeModelFile(modelPath, points.cloud, kReconstructedModelComment);
  if (!trajectoryPath.empty()) writeTumTrajectory(trajectoryPath, keyFrameTrajectory(), kKeyFrameTrajectoryHeader);
}

}  // namespace tissuemosaic::python
