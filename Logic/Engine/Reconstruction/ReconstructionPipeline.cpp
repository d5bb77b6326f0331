#include "Reconstruction/ReconstructionPipeline.h"

#include "Core/BackgroundWorker.h"
#include "Core/CudaRuntime.h"
#include "Core/Error.h"
#include "Core/PixelFormat.h"
#include "Core/Stopwatch.h"
#include "Core/SurfaceMeasurement.h"
#include "Deformation/ModelWarp.h"
#include "Fusion/PointFusion.h"
#include "Refinement/KeyFrameRefiner.h"
#include "Refinement/Relocaliser.h"
#include "Stereo/StereoMatcher.h"
#include "Tracking/FrameTracker.h"
#include "Tracking/SubPixelMatch.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <limits>
#include <optional>

namespace tissuemosaic {
namespace {

using Clock = std::chrono::steady_clock;

FrameTrackerOptions trackerOptions(const ReconstructionParameters& p, Device device,
                                   std::shared_ptr<SubPixelMatcher> subPixel) {
  FrameTrackerOptions options;
  options.tracking = p.tracking;
  options.features = p.features;
  options.extractor = p.extractor;
  options.featureDevice = p.extractor == FeatureExtractor::TissueMosaicOrb ? device : Device::Cpu;
  if (subPixel && subPixel->device() == options.featureDevice) options.subPixelMatcher = std::move(subPixel);
  return options;
}

/// One sub-pixel matcher for the tracker and the refiner: the tracker uploads every tracked frame, and keeping the
/// intermediate frames, the reference and the key frame spares the refiner uploading them again at each key frame.
std::shared_ptr<SubPixelMatcher> sharedSubPixelMatcher(const ReconstructionParameters& p, Device device) {
  auto matcher = std::make_shared<SubPixelMatcher>(device, p.features.maxRefinementShiftPx);
  matcher->setRetainedImages(p.refinement.maxIntermediateFrames + 3);
  return matcher;
}

}  // namespace

const char* frameStatusName(FrameStatus status) {
  switch (status) {
    case FrameStatus::Tracked: return "tracked";
    case FrameStatus::Relocalised: return "relocalised";
    default: return "lost";
  }
}

const char* sceneMotionName(SceneMotion motion) {
  switch (motion) {
    case SceneMotion::Still: return "still";
    case SceneMotion::Camera: return "camera";
    case SceneMotion::Tissue: return "tissue";
    case SceneMotion::Both: return "both";
    default: return "unknown";
  }
}

struct ReconstructionPipeline::Impl {
  RectifiedGeometry geometry;
  std::optional<StereoRectifier> rectifier;
  ReconstructionParameters parameters;
  Device device;
  StereoMatcher matcher;
  DisparityRangeFollower disparityRange;  ///< the matcher's range, frame by frame
  std::shared_ptr<SubPixelMatcher> subPixel;  ///< the tracker's and the refiner's
  FrameTracker tracker;
  KeyFrameRefiner refiner;
  Relocaliser relocaliser;
  PointFusion fusion;
  std::optional<DeformationTracker> deformation;  ///< fusion.deformation on
  std::optional<ModelWarp> modelWarp;             ///< the deformation's field as the fusion follows it
  std::vector<KeyFramePose> keyFrames;
  std::size_t peakDeviceBytes = 0;
  std::string lastRefinementMessage;
  bool frameDisparityKept = true;  ///< FrameResult::disparityPx filled
  // The workers come last, so that they stop before the members their tasks use are destroyed.
  BackgroundWorker worker;       ///< stereo beside tracking; the key frame's surface and ICP points beside matching
  BackgroundWorker modelWorker;  ///< samples the model beside the key frame's surface measurement
  BackgroundWorker rangeWorker;  ///< the automatic range's measurements, each beside several frames
  /// The measurement of an earlier frame (its sample and milliseconds), applied from frame rangeSampleDue on; last of
  /// all, so that it is waited for before anything its task uses goes.
  std::optional<PendingResult<std::pair<DisparitySample, double>>> rangeSample;
  int rangeSampleDue = 0;

  Impl(const RectifiedGeometry& g, std::optional<StereoRectifier> r, const ReconstructionParameters& p, Device d,
       const Eigen::Matrix4d& T_world_start)
      : geometry(g), rectifier(std::move(r)), parameters(p), device(d), matcher(d, p.stereo),
        disparityRange(p.stereo, g, d), subPixel(sharedSubPixelMatcher(p, d)),
        tracker(g, trackerOptions(p, d, subPixel), T_world_start),
        refiner(g, p.refinement, p.tracking, p.features, d, subPixel), relocaliser(g, p.tracking, p.features, d),
        fusion(g, p.fusion, d) {
    if (p.fusion.deformation) {
      deformation.emplace(g);
      // The field follows the tissue to within the samples' agreement distance ("within" for its live share).
      modelWarp.emplace(deformation->graph(), deformation->parameters().agreementMm);
    }
  }

  void samplePeakDeviceMemory() {
    if (device == Device::Cuda) peakDeviceBytes = std::max(peakDeviceBytes, cuda::deviceBytesInUse());
  }
};

namespace {

RectifiedGeometry checkedGeometry(const RectifiedGeometry& geometry) {
  require(geometry.imageSize.width > 0 && geometry.imageSize.height > 0 && geometry.focalPx > 0 &&
              geometry.baselineMm > 0,
          "reconstruction: the rectified geometry needs an image size, a focal length and a baseline");
  return geometry;
}

const ReconstructionParameters& validated(const ReconstructionParameters& parameters) {
  parameters.validate();
  return parameters;
}

}  // namespace

ReconstructionPipeline::ReconstructionPipeline(const RectifiedGeometry& geometry,
                                               const ReconstructionParameters& parameters, Device device,
                                               const Eigen::Matrix4d& T_world_startCamera)
    : impl_(std::make_unique<Impl>(checkedGeometry(geometry), std::nullopt, validated(parameters), device,
                                   T_world_startCamera)) {}

ReconstructionPipeline::ReconstructionPipeline(const StereoCalibration& calibration,
                                               const ReconstructionParameters& parameters, Device device,
                                               const Eigen::Matrix4d& T_world_startCamera) {
  StereoRectifier rectifier(calibration);
  const RectifiedGeometry geometry = checkedGeometry(rectifier.geometry());
  impl_ = std::make_unique<Impl>(geometry, std::move(rectifier), validated(parameters), device, T_world_startCamera);
}

ReconstructionPipeline::~ReconstructionPipeline() = default;

namespace {

/// The grey image a grey-working stage (range, stereo, tracking) takes of a frame: the frame itself in BGR (the stage
/// converts it, as before), converted here in RGB; large frames in bands on the thread pool, as StereoMatcher does.
cv::Mat stageImage(const cv::Mat& frame, ChannelOrder order, const char* what) {
  if (order == ChannelOrder::Bgr) return frame;
  cv::Mat grey;
  convertToGrey8(frame, grey, what, frame.total() >= 1'000'000 ? 8 : 1, ChannelOrder::Rgb);
  return grey;
}

}  // namespace

FrameResult ReconstructionPipeline::process(const cv::Mat& left, const cv::Mat& right, double timeS,
                                            ChannelOrder order) {
  Impl& s = *impl_;
  const cv::Size size = s.geometry.imageSize;
  require(!left.empty() && !right.empty(), "reconstruction: empty frame");
  require(left.size() == size && right.size() == size,
          "reconstruction: frame sizes " + std::to_string(left.cols) + "x" + std::to_string(left.rows) + " and " +
              std::to_string(right.cols) + "x" + std::to_string(right.rows) + " differ from the rig's " +
              std::to_string(size.width) + "x" + std::to_string(size.height));
  FrameResult result;
  result.frameIndex = s.tracker.frameCount();
  const auto start = Clock::now();

  // 3 channels in the frames' order (grey and 4-channel frames become 3 channels; rectification keeps the order).
  cv::Mat leftColour = toBgr8(left, "reconstruction: frames"), rightColour = toBgr8(right, "reconstruction: frames");
  if (s.rectifier) {
    s.rectifier->rectify(leftColour, rightColour, result.leftRectified, result.rightRectified);
  } else {
    result.leftRectified = leftColour;
    result.rightRectified = rightColour;
  }
  result.channelOrder = order;
  result.timesMs.videoReading = millisecondsSince(start);

  // The frame's disparity range is set before its dense matching starts and stays for the whole frame. The automatic
  // range measures the first frame now. Later, every N-th frame (sampleEveryFrames) is measured on a thread of its
  // own beside the N frames after it, and decides the range from frame k + N on: no frame waits for a measurement,
  // which costs more than a whole frame on the GPU, and the ranges depend on the frames alone, not on timing.
  const int sampleEvery = s.disparityRange.sampleEveryFrames();
  if (s.rangeSample && result.frameIndex >= s.rangeSampleDue) {
    const auto waitStart = Clock::now();
    const auto [sample, measuredMs] = s.rangeSample->get();
    result.disparityRangeWaitMs = millisecondsSince(waitStart);
    s.rangeSample.reset();
    result.disparityRangeMs = measuredMs;
    // The sample serves frames N..2N-1 after its own: predicted that far, as the tissue moved since the last one.
    s.disparityRange.afterFrame(sample, (2.0 * sampleEvery - 1.0) / sampleEvery);
  }
  const bool firstRange = !s.disparityRange.history().current;
  const auto rangeStart = Clock::now();
  // The images are read only where the first frame's range is measured.
  result.disparityRange =
      firstRange ? s.disparityRange.beforeFrame(stageImage(result.leftRectified, order, "disparity range: the left image"),
                                                stageImage(result.rightRectified, order, "disparity range: the right image"))
                 : s.disparityRange.beforeFrame(result.leftRectified, result.rightRectified);
  // A pair whose rows the first frame found apart is matched with its right view moved onto the left's rows.
  result.rightRectified = s.disparityRange.alignedRight(result.rightRectified);
  s.matcher.setDisparityRange(result.disparityRange);
  if (s.disparityRange.automatic() && firstRange) result.disparityRangeMs = millisecondsSince(rangeStart);
  if (s.disparityRange.automatic() && !firstRange && !s.rangeSample && result.frameIndex % sampleEvery == 0) {
    // Copies: the caller may write its next frame into the same images while this frame is measured.
    // (RGB frames: their grey images, new memory too.)
    const auto copyOf = [order](const cv::Mat& image, const char* what) {
      return order == ChannelOrder::Bgr ? image.clone() : stageImage(image, order, what);
    };
    s.rangeSample.emplace(s.rangeWorker.run([&s, left = copyOf(result.leftRectified, "disparity range: the left image"),
                                              right = copyOf(result.rightRectified, "disparity range: the right image")] {
      const auto measureStart = Clock::now();
      DisparitySample sample = s.disparityRange.measure(left, right);
      return std::make_pair(std::move(sample), millisecondsSince(measureStart));
    }));
    s.rangeSampleDue = result.frameIndex + sampleEvery;
  }

  // Stereo runs beside the tracking: matching and the pose need only the reference frame's depth, and the tracker
  // asks for this frame's disparity at its end, to lift the features for the frames after it.
  // The tracker and fusion take the disparity without the pixels near a highlight (a highlight slides over the
  // tissue as the camera moves: features and points on it would mislead both); the frame's result keeps all of it.
  struct TimedDisparity {
    cv::Mat disparityPx;
    double milliseconds = 0;
    StereoTimingsMs parts;
    RangeEndCounts rangeEnds;
  };
  PendingResult<TimedDisparity> stereo = s.worker.run([&] {
    const auto stereoStart = Clock::now();
    TimedDisparity computed;
    s.matcher.match(stageImage(result.leftRectified, order, "the left image"),
                    stageImage(result.rightRectified, order, "the right image"), &computed.parts);
    computed.rangeEnds = s.matcher.lastRangeEndCounts();
    if (s.frameDisparityKept) {
      const auto downloadStart = Clock::now();
      computed.disparityPx = s.matcher.downloadLastDisparity();
      computed.parts.download = millisecondsSince(downloadStart);
    }
    synchronize(s.device);  // nothing of this thread's left in flight when another thread takes over
    computed.milliseconds = millisecondsSince(stereoStart);
    return computed;
  });
  const auto waitForStereo = [&] {
    if (!stereo.pending()) return;
    TimedDisparity computed = stereo.get();
    result.disparityPx = computed.disparityPx;
    result.timesMs.stereo = computed.milliseconds;
    result.stereoPartsMs = computed.parts;
    result.disparityRangeEnds = computed.rangeEnds;
  };
  // The tracker lifts its features with the disparity at their keypoints, sampled where the map lies.
  double samplingMs = 0;
  const auto sampleTrackingDisparity = [&](const std::vector<cv::Point2f>& pointsPx) {
    waitForStereo();
    const auto samplingStart = Clock::now();
    std::vector<float> disparitiesPx = s.matcher.sampleLastDisparityAwayFromHighlights(pointsPx);
    samplingMs = millisecondsSince(samplingStart);
    return disparitiesPx;
  };
  // The model agreement at every pose the tracker solves (the frame's stereo, where it was computed, against the
  // model seen from the pose): the check that refuses a pose the model contradicts wholesale, and the quality signal.
  ModelAgreement agreement;
  Eigen::Matrix4d T_world_agreement = Eigen::Matrix4d::Identity();
  const auto measureAgreement = [&](const Eigen::Matrix4d& T_world_camera) {
    const auto agreementStart = Clock::now();
    agreement = s.fusion.pointCount() > 0
                    ? s.fusion.measureAgreement(s.matcher.lastDisparity(), T_world_camera,
                                                s.parameters.agreement.sampleStridePx)
                    : ModelAgreement{};
    T_world_agreement = T_world_camera;
    result.timesMs.agreement += millisecondsSince(agreementStart);
    return agreement;
  };
  const FrameTracker::PoseCheck check = [&](const Eigen::Matrix4d& T_world_camera) -> std::string {
    const ModelAgreement a = measureAgreement(T_world_camera);
    if (!s.parameters.agreement.collapsed(a)) return {};
    // A pose that continues the scope's smooth motion is kept: the tissue moved (breathing, pushed), not the camera.
    if (s.tracker.continuesMotion(T_world_camera)) {
      result.tissueMoved = true;
      return {};
    }
    return cv::format("the model disagrees with the frame's depth at this pose (%.0f%% within 1 mm, median %.1f mm)",
                      100 * a.shareWithin1mm, a.medianDepthDifferenceMm);
  };
  TrackResult track = s.tracker.track(stageImage(result.leftRectified, order, "tracking: the left image"),
                                      FrameTracker::DisparitySource(sampleTrackingDisparity), check);
  waitForStereo();  // the tracker has waited on every path that returns; this only guards that contract
  if (!track.tracked) {
    // Frames since the last key frame are from before the loss: not the next key frame's bundle.
    s.refiner.clearIntermediateFrames();
    if (s.refiner.keyFrameCount() > 0) {
      const RelocalisationResult found =
          s.relocaliser.relocalise(s.tracker.lastFeatures(), s.refiner, s.tracker.lastTrackedPose());
      if (found.success) {
        const ModelAgreement a = measureAgreement(found.T_world_camera);
        const AgreementParameters& limits = s.parameters.agreement;
        if (a.measured && a.overlap() >= limits.minOverlap && a.shareWithin1mm >= limits.relocalisationMinShare) {
          const std::string lostReason = track.failureReason;
          const TrackResult lostTrack = track;
          track = s.tracker.acceptRelocalisation(found.T_world_camera, found.inliers);
          track.timesMs = lostTrack.timesMs;  // the time went into the failed attempt
          result.trackingMessage = "relocalised against key frame " + std::to_string(found.keyFrame) + " (" +
                                   std::to_string(found.inliers) + " inliers) after: " + lostReason;
        } else {
          track.failureReason += cv::format("; relocalisation against key frame %d refused: %.0f%% of its depths within "
                                            "1 mm of the model", found.keyFrame, a.measured ? 100 * a.shareWithin1mm : 0.0);
        }
      }
    }
  }
  result.timesMs.orbVoting = track.timesMs.orbVoting + samplingMs;  // sampling is part of lifting the features
  result.timesMs.pnp = track.timesMs.pnp;
  result.trackingPartsMs = {track.timesMs.extract + samplingMs, track.timesMs.match, track.timesMs.subPixel,
                            track.timesMs.vote};
  result.tracked = track.tracked;
  result.status = !track.tracked ? FrameStatus::Lost : (track.relocalised ? FrameStatus::Relocalised : FrameStatus::Tracked);
  result.keyFrame = track.tracked && track.keyFrame;
  if (!track.tracked) result.trackingMessage = track.failureReason;
  result.inliers = track.inliers;
  result.movingMatches = track.movingMatches;
  if (track.tracked && !track.initial && !track.relocalised) {
    const bool cameraMoved =
        track.stepMmPerFrame > kCameraStillMmPerFrame || track.stepDegPerFrame > kCameraStillDegPerFrame;
    const int matched = track.inliers + track.movingMatches;
    const bool tissueMoved = result.tissueMoved || (matched > 0 && track.movingMatches >= kTissueMovingShare * matched);
    result.sceneMotion = cameraMoved ? (tissueMoved ? SceneMotion::Both : SceneMotion::Camera)
                                     : (tissueMoved ? SceneMotion::Tissue : SceneMotion::Still);
  }
  result.T_world_camera = track.T_world_camera;
  if (track.tracked && s.deformation) {
    // The tissue's motion beyond the camera's, at the tracked pose, before the frame meets the model: the fused
    // model then follows it (its agreement, motion evidence, ICP samples and fusion see the tissue where it is now).
    const auto deformationStart = Clock::now();
    const cv::Mat disparity = result.disparityPx.empty() ? s.matcher.downloadLastDisparity() : result.disparityPx;
    result.deformation = s.deformation->update(disparity, result.T_world_camera);
    if (!result.deformation.cameraCorrection.isIdentity()) {
      // The camera takes the field's rigid part (DeformationTrackerParameters::cameraTakesRigidPart).
      result.T_world_camera = result.deformation.cameraCorrection * result.T_world_camera;
      s.tracker.correctLastPose(result.T_world_camera);
    }
    s.fusion.followDeformation(*s.modelWarp);
    T_world_agreement = Eigen::Matrix4d::Constant(std::numeric_limits<double>::quiet_NaN());  // the model moved
    result.timesMs.deformation = millisecondsSince(deformationStart);
  }
  if (track.tracked) {
    if (!(T_world_agreement == result.T_world_camera)) measureAgreement(result.T_world_camera);
    result.agreement = agreement;
    result.agreementLevel = s.parameters.agreement.level(agreement);
    // Motion evidence: model points this frame contradicts lose weight (before a key frame fuses).
    const auto motionStart = Clock::now();
    result.pointsRemoved = s.fusion.updateMotion(s.matcher.lastDisparity(), result.T_world_camera, agreement);
    result.timesMs.agreement += millisecondsSince(motionStart);
  }

  if (result.tracked && !result.keyFrame) {
    s.refiner.addIntermediateFrame(result.frameIndex, s.tracker.lastFeatures(), result.T_world_camera);
  }
  if (result.keyFrame) {
    auto stageStart = Clock::now();
    // The surface (refinement's ICP term and fusion) and the ICP term's model points, seen from the tracked pose,
    // need no matches: they are prepared on two other threads (the sample beside the surface) while the refiner
    // matches the key frame's features; the surface's thread then chooses the ICP points from the sample.
    PendingResult<std::vector<Eigen::Vector3f>> modelSample = s.modelWorker.run([&] {
      const auto sampleStart = Clock::now();
      std::vector<Eigen::Vector3f> modelPointsWorldMm, modelNormalsWorld;
      if (s.fusion.pointCount() > 0) {
        s.fusion.sampleVisible(result.T_world_camera, s.parameters.refinement.icpSamples, modelPointsWorldMm,
                               modelNormalsWorld);
      }
      synchronize(s.device);  // nothing of this thread's left in flight for the next key frame's fusion
      result.refinementPartsMs.modelSample = millisecondsSince(sampleStart);
      return modelPointsWorldMm;
    });
    struct SurfaceAndIcp {
      SurfaceMeasurement measurement;
      IcpModelPoints icp;
    };
    PendingResult<SurfaceAndIcp> surfaceAndIcp = s.worker.run([&] {
      SurfaceAndIcp prepared;
      const auto surfaceStart = Clock::now();
      prepared.measurement =
          measureSurface(s.matcher.lastDisparityAwayFromHighlightsView(), result.leftRectified, s.geometry, s.device,
                         s.parameters.fusion.normalRadiusPx, s.parameters.fusion.maxDepthJumpMm,
                         SurfaceMapResidence::DeviceOnly,  // refinement and fusion run on the same device
                         workingDisparityRange(s.geometry, s.parameters.fusion), order);
      synchronize(s.device);  // the maps stay on the device for the refiner and fusion on the calling thread
      result.refinementPartsMs.surface = millisecondsSince(surfaceStart);
      const std::vector<Eigen::Vector3f> modelPointsWorldMm = modelSample.get();
      const auto selectionStart = Clock::now();
      prepared.icp = s.refiner.selectIcpModelPoints(prepared.measurement, modelPointsWorldMm, result.T_world_camera);
      result.refinementPartsMs.icpSelection = millisecondsSince(selectionStart);
      return prepared;
    });
    auto partStart = Clock::now();
    KeyFrameMatches matches = s.refiner.matchKeyFrame(result.frameIndex, s.tracker.lastFeatures(), result.T_world_camera);
    result.refinementPartsMs.matchingCall = millisecondsSince(partStart);
    partStart = Clock::now();
    const SurfaceAndIcp prepared = surfaceAndIcp.get();
    result.refinementPartsMs.surfaceWait = millisecondsSince(partStart);
    const SurfaceMeasurement& measurement = prepared.measurement;
    partStart = Clock::now();
    const RefinementResult refinement = s.refiner.refineMatchedKeyFrame(std::move(matches), measurement, prepared.icp);
    result.refinementPartsMs.solveCall = millisecondsSince(partStart);
    s.lastRefinementMessage = refinement.message;
    result.refinementPartsMs.keyFrameMatching = refinement.keyFrameMatchingMs;
    result.refinementPartsMs.intermediateMatching = refinement.intermediateMatchingMs;
    result.refinementPartsMs.solve = refinement.solveMs;
    result.refined = refinement.refined;
    result.matchedKeyFrames = refinement.matchedKeyFrames;
    result.guidedKeyFrames = refinement.guidedKeyFrames;
    result.intermediateFrames = refinement.intermediateFrames;
    result.guidedIntermediateFrames = refinement.guidedFrames;
    if (refinement.refined) {
      result.T_world_camera = refinement.T_world_camera;
      s.tracker.correctLastPose(result.T_world_camera);
    }
    result.timesMs.refinement = millisecondsSince(stageStart);

    stageStart = Clock::now();
    const FusionStats fused = s.fusion.integrate(measurement, result.T_world_camera);
    result.fusedMerged = fused.merged;
    result.fusedAdded = fused.added;
    result.timesMs.tsdf = millisecondsSince(stageStart);

    KeyFramePose pose;
    pose.frameIndex = result.frameIndex;
    pose.timeS = timeS;
    pose.T_world_camera = result.T_world_camera;
    s.keyFrames.push_back(pose);
  }
  result.modelPoints = s.fusion.pointCount();
  result.pointBudgetReached = s.fusion.budgetReached();
  result.timesMs.total = millisecondsSince(start);
  s.samplePeakDeviceMemory();
  return result;
}

const RectifiedGeometry& ReconstructionPipeline::geometry() const { return impl_->geometry; }
const ReconstructionParameters& ReconstructionPipeline::parameters() const { return impl_->parameters; }
Device ReconstructionPipeline::device() const { return impl_->device; }
int ReconstructionPipeline::frameCount() const { return impl_->tracker.frameCount(); }
const std::vector<KeyFramePose>& ReconstructionPipeline::keyFrames() const { return impl_->keyFrames; }
ModelPoints ReconstructionPipeline::modelSnapshot() const { return impl_->fusion.download(); }
ModelPoints ReconstructionPipeline::liveModelSnapshot() const { return impl_->fusion.downloadLive(); }
std::size_t ReconstructionPipeline::modelPointCount() const { return impl_->fusion.pointCount(); }
std::size_t ReconstructionPipeline::peakDeviceBytes() const { return impl_->peakDeviceBytes; }
void ReconstructionPipeline::setFrameDisparityKept(bool kept) { impl_->frameDisparityKept = kept; }
cv::Mat ReconstructionPipeline::downloadLastDisparity() const { return impl_->matcher.downloadLastDisparity(); }
const DeformationGraph* ReconstructionPipeline::deformationGraph() const {
  return impl_->deformation ? &impl_->deformation->graph() : nullptr;
}
const DeformationTracker* ReconstructionPipeline::deformation() const {
  return impl_->deformation ? &*impl_->deformation : nullptr;
}
const std::string& ReconstructionPipeline::lastRefinementMessage() const { return impl_->lastRefinementMessage; }
const DisparityRangeHistory& ReconstructionPipeline::disparityRangeHistory() const {
  return impl_->disparityRange.history();
}
std::string ReconstructionPipeline::disparityRangeDescription() const { return impl_->disparityRange.description(); }

}  // namespace tissuemosaic
