#include "PointFusion.h"

#include "Core/Error.h"
#include "Core/RigidTransform.h"
#include "Core/SurfaceKernels.h"
#include "Core/Stopwatch.h"
#include "FusionPipeline.h"

#include <Eigen/LU>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

namespace tissuemosaic {

namespace fusion {

FusionModel::FusionModel(Device device_, int width_, int height_)
    : device(device_), width(width_), height(height_), pointsMm(device_, width_, height_),
      normals(device_, width_, height_), colourBgr(device_, std::size_t(3) * width_ * height_),
      covered(device_, std::size_t(width_) * height_), flags(device_, std::size_t(width_) * height_),
      offsets(device_, std::size_t(width_) * height_), depthKeys(device_, std::size_t(width_) * height_),
      counters(device_, 1) {}

std::size_t FusionModel::bytes() const {
  return 3 * store.capacity() * sizeof(Float4) + 2 * pointsMm.buffer().size() * sizeof(Float3) + colourBgr.size() +
         covered.size() + (flags.size() + offsets.size() + counters.size()) * sizeof(int) +
         depthKeys.size() * sizeof(uint64_t) + scanScratch.size() +
         (samplePositions.size() + sampleNormals.size() + warpRows.size()) * sizeof(Float4);
}

}  // namespace fusion

namespace {

fusion::FramePose framePose(const Eigen::Matrix4d& T_world_camera) {
  require(T_world_camera.allFinite(), "PointFusion: the camera pose has non-finite entries");
  const Eigen::Matrix3d R = T_world_camera.topLeftCorner<3, 3>();
  const Eigen::Vector3d t = T_world_camera.topRightCorner<3, 1>();
  require(isRigidTransform(T_world_camera),
          "PointFusion: T_world_camera must be a rigid transform (rotation and translation)");
  const Eigen::Matrix3d Rt = R.transpose();
  const Eigen::Vector3d tInverse = -Rt * t;
  fusion::FramePose pose{};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      pose.cameraToWorld.r[3 * r + c] = static_cast<float>(R(r, c));
      pose.worldToCamera.r[3 * r + c] = static_cast<float>(Rt(r, c));
    }
    pose.cameraToWorld.t[r] = static_cast<float>(t(r));
    pose.worldToCamera.t[r] = static_cast<float>(tInverse(r));
  }
  pose.cameraCentreWorld = {static_cast<float>(t(0)), static_cast<float>(t(1)), static_cast<float>(t(2))};
  return pose;
}

fusion::FusionSettings fusionSettings(const RectifiedGeometry& geometry, const FusionParameters& p) {
  constexpr double kPi = 3.14159265358979323846;
  fusion::FusionSettings s{};
  s.camera = {static_cast<float>(geometry.focalPx), static_cast<float>(geometry.cxLeftPx),
              static_cast<float>(geometry.cyPx), geometry.imageSize.width, geometry.imageSize.height};
  s.truncationMm = static_cast<float>(p.truncationMm);
  s.maxWeight = static_cast<float>(p.maxWeight);
  s.minNormalCosine = static_cast<float>(std::cos(p.maxNormalAngleDeg * kPi / 180.0));
  s.coverageRadiusPx = p.coverageRadiusPx;
  s.newPointStepPx = p.newPointStepPx;
  s.colourFullWeightFraction = static_cast<float>(p.colourFullWeightFraction);
  s.colourMinWeight = static_cast<float>(p.colourMinWeight);
  s.conflictMinWeight = static_cast<float>(p.conflictMinWeight);
  // Part of the scene-motion handling (motionPenalty > 0): what passes in front of the model is not fused.
  s.occluderMarginMm = p.motionPenalty > 0 ? static_cast<float>(p.occlusionMarginMm) : 0.0f;
  s.movedTissueRadiusMm = p.motionPenalty > 0 ? static_cast<float>(p.movedTissueRadiusMm) : 0.0f;
  s.markerRestFrames = p.markerRestFrames;
  s.seenThroughEvidenceRate = p.motionPenalty > 0 ? fusion::seenThroughEvidenceRate(p.seenThroughFrames) : 0.0f;
  return s;
}

/// Copies elements first..first+count-1 of a device (or host) buffer to host memory.
template <class T>
void downloadRange(const Buffer<T>& buffer, std::size_t first, std::size_t count, T* host) {
  if (count == 0) return;
  if (buffer.device() == Device::Cuda) cuda::copyDeviceToHost(host, buffer.data() + first, count * sizeof(T));
  else std::copy_n(buffer.data() + first, count, host);
}

cv::Mat continuous(const cv::Mat& image) { return image.isContinuous() ? image : image.clone(); }

/// The agreement's figures from its counters: the median by interpolation within its histogram bin.
ModelAgreement agreementFromCounters(const std::vector<int>& counters) {
  using namespace fusion;
  ModelAgreement a;
  a.measuredSamples = counters[kMeasuredSamples];
  a.overlapSamples = counters[kOverlapSamples];
  if (a.overlapSamples == 0) return a;
  a.measured = true;
  const int withinBins = static_cast<int>(std::lround(ModelAgreement::kToleranceMm / kAgreementBinMm));
  long long within = 0, below = 0;
  for (int b = 0; b < withinBins; ++b) within += counters[kHistogramStart + b];
  a.shareWithin1mm = static_cast<double>(within) / a.overlapSamples;
  const double half = 0.5 * a.overlapSamples;
  for (int b = 0; b < kAgreementBins; ++b) {
    const int inBin = counters[kHistogramStart + b];
    if (below + inBin >= half) {
      a.medianDepthDifferenceMm = (b + (half - below) / std::max(inBin, 1)) * kAgreementBinMm;
      break;
    }
    below += inBin;
  }
  return a;
}

}  // namespace

DisparityRangePx workingDisparityRange(const RectifiedGeometry& g, const FusionParameters& fusion) {
  const double fb = g.focalPx * g.baselineMm;
  DisparityRangePx kept;
  kept.lowestPx = static_cast<float>(fb / fusion.maxDepthMm - g.doffsPx);
  if (fusion.minDepthMm > 0) kept.highestPx = static_cast<float>(fb / fusion.minDepthMm - g.doffsPx);
  return kept;
}

PointFusion::PointFusion(const RectifiedGeometry& geometry, const FusionParameters& parameters, Device device)
    : geometry_(geometry), parameters_(parameters), device_(device) {
  parameters_.validate();
  require(geometry.imageSize.width > 0 && geometry.imageSize.height > 0 && geometry.focalPx > 0,
          "PointFusion: the rectified geometry has no image size or focal length");
  requireUsableDevice(device, "CUDA point fusion");
  model_ = std::make_unique<fusion::FusionModel>(device, geometry.imageSize.width, geometry.imageSize.height);
}

PointFusion::~PointFusion() = default;
PointFusion::PointFusion(PointFusion&&) noexcept = default;
PointFusion& PointFusion::operator=(PointFusion&&) noexcept = default;

FusionStats PointFusion::integrate(const SurfaceMeasurement& measurement, const Eigen::Matrix4d& T_world_camera) {
  const auto start = std::chrono::steady_clock::now();
  const cv::Size size = geometry_.imageSize;
  require((usableHostMaps(measurement.pointsCameraMm, measurement.normalsCamera) || measurement.onDevice) &&
              measurement.size() == size &&
              measurement.colourBgr.type() == CV_8UC3 && measurement.colourBgr.size() == size,
          "PointFusion::integrate: the measurement must hold CV_32FC3 points and normals and a CV_8UC3 colour image "
          "of the rectified size " + std::to_string(size.width) + "x" + std::to_string(size.height));
  const fusion::FramePose pose = framePose(T_world_camera);
  fusion::FusionModel& model = *model_;
  require(!model.deforming || model.warpedCount == model.count,
          "PointFusion::integrate: the model's points have no motions (followDeformation after the last change)");
  const SurfaceMapsOnDevice* onDevice = measurement.onDevice.get();
  copySurfaceMaps(measurement.pointsCameraMm, measurement.normalsCamera, onDevice, model.pointsMm, model.normals);
  if (device_ == Device::Cuda && onDevice && onDevice->colourBgr.size() == model.colourBgr.size()) {
    model.colourBgr.copyFrom(onDevice->colourBgr);  // uploaded where the surface was measured
  } else {
    model.colourBgr.upload(continuous(measurement.colourBgr).ptr<uint8_t>());
  }

  const fusion::FusionSettings settings = fusionSettings(geometry_, parameters_);
  const std::size_t countBefore = model.count;
  const fusion::IntegrateCounts counts = device_ == Device::Cuda
                                             ? fusion::integrateCuda(model, pose, settings, parameters_.maxPoints)
                                             : fusion::integrateCpu(model, pose, settings, parameters_.maxPoints);
  synchronize(device_);
  if (model.deforming && model.count > countBefore) restNewPoints(countBefore);
  FusionStats stats;
  stats.merged = counts.merged;
  stats.added = counts.added;
  stats.refusedForBudget = counts.refused;
  stats.milliseconds = millisecondsSince(start);
  return stats;
}

std::size_t PointFusion::pointCount() const { return model_->count - model_->markers; }
std::size_t PointFusion::movedTissueMarkerCount() const { return model_->markers - model_->retiredMarkers; }
std::size_t PointFusion::retiredMarkerCount() const { return model_->retiredMarkers; }

bool PointFusion::budgetReached() const { return model_->budgetReached; }

namespace {

/// Copies host values into elements first..first+count-1 of a device (or host) buffer.
template <class T>
void uploadRange(Buffer<T>& buffer, std::size_t first, std::size_t count, const T* host) {
  if (count == 0) return;
  if (buffer.device() == Device::Cuda) cuda::copyHostToDevice(buffer.data() + first, host, count * sizeof(T));
  else std::copy_n(host, count, buffer.data() + first);
}

Eigen::Vector3f vector3(const fusion::Float4& a) { return {a.x, a.y, a.z}; }

}  // namespace

bool PointFusion::deforming() const { return model_->deforming; }

void PointFusion::followDeformation(ModelDeformation& field) {
  fusion::FusionModel& model = *model_;
  deformation_ = &field;
  const std::size_t n = model.count;
  std::vector<fusion::Float4> positions(n);
  downloadRange(model.store.positionWeight, 0, n, positions.data());
  std::vector<Eigen::Vector3f> restMm(n);
  for (std::size_t i = 0; i < n; ++i) restMm[i] = vector3(positions[i]);
  motions_.clear();
  field.motionsOf(restMm, motions_);
  require(motions_.size() == n, "PointFusion::followDeformation: the field gave a motion count other than the points'");
  model.deforming = true;
  uploadWarps();
}

void PointFusion::uploadWarps() {
  fusion::FusionModel& model = *model_;
  const std::size_t n = motions_.size();
  std::vector<fusion::Float4> rows(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const PointMotion& m = motions_[i];
    for (int r = 0; r < 3; ++r)
      rows[3 * i + r] = {m.rotation(r, 0), m.rotation(r, 1), m.rotation(r, 2), m.translationMm(r)};
  }
  if (model.warpRows.size() < rows.size()) {  // room for the store's capacity: reallocated as rarely as the store
    model.warpRows = Buffer<fusion::Float4>(device_, std::max<std::size_t>(rows.size(), 3 * model.store.capacity()));
  }
  uploadRange(model.warpRows, 0, rows.size(), rows.data());
  model.warpedCount = n;
  model.depthKeysCurrent = false;  // the points moved
}

void PointFusion::restNewPoints(std::size_t first) {
  fusion::FusionModel& model = *model_;
  const std::size_t added = model.count - first;
  std::vector<fusion::Float4> positions(added), normals(added);
  downloadRange(model.store.positionWeight, first, added, positions.data());
  downloadRange(model.store.normal, first, added, normals.data());
  std::vector<Eigen::Vector3f> liveMm(added), restMm;
  for (std::size_t i = 0; i < added; ++i) liveMm[i] = vector3(positions[i]);
  std::vector<PointMotion> motions;
  deformation_->restOf(liveMm, restMm, motions);
  require(restMm.size() == added && motions.size() == added,
          "PointFusion::integrate: the deformation field gave a rest count other than the new points'");
  for (std::size_t i = 0; i < added; ++i) {
    fusion::Float4& p = positions[i];
    fusion::Float4& n = normals[i];
    const Eigen::Vector3f restNormal = motions[i].rotation.transpose() * vector3(n);
    p = {restMm[i].x(), restMm[i].y(), restMm[i].z(), p.w};
    n = {restNormal.x(), restNormal.y(), restNormal.z(), n.w};
  }
  uploadRange(model.store.positionWeight, first, added, positions.data());
  uploadRange(model.store.normal, first, added, normals.data());
  motions_.resize(first);
  motions_.insert(motions_.end(), motions.begin(), motions.end());
  uploadWarps();
}

ModelPoints PointFusion::download() const { return downloadPoints(false); }

ModelPoints PointFusion::downloadLive() const { return downloadPoints(model_->deforming); }

ModelPoints PointFusion::downloadPoints(bool whereNow) const {
  const std::size_t n = model_->count;
  std::vector<fusion::Float4> positions(n), normals(n), colours(n);
  downloadRange(model_->store.positionWeight, 0, n, positions.data());
  downloadRange(model_->store.normal, 0, n, normals.data());
  downloadRange(model_->store.colourWeight, 0, n, colours.data());
  if (whereNow) {
    for (std::size_t i = 0; i < std::min(n, motions_.size()); ++i) {
      const PointMotion& m = motions_[i];
      const Eigen::Vector3f p = m.rotation * vector3(positions[i]) + m.translationMm;
      const Eigen::Vector3f normal = m.rotation * vector3(normals[i]);
      positions[i] = {p.x(), p.y(), p.z(), positions[i].w};
      normals[i] = {normal.x(), normal.y(), normal.z(), normals[i].w};
    }
  }
  ModelPoints model;
  const std::size_t live = n - model_->markers;
  model.cloud.pointsMm.reserve(live);
  model.cloud.normals.reserve(live);
  model.cloud.colorsRgb.reserve(live);
  model.weights.reserve(live);
  for (std::size_t i = 0; i < n; ++i) {
    if (!fusion::isLive(positions[i])) continue;  // a moved-tissue marker
    model.cloud.pointsMm.emplace_back(positions[i].x, positions[i].y, positions[i].z);
    model.cloud.normals.emplace_back(normals[i].x, normals[i].y, normals[i].z);
    model.cloud.colorsRgb.emplace_back(cv::saturate_cast<uchar>(colours[i].x), cv::saturate_cast<uchar>(colours[i].y),
                                       cv::saturate_cast<uchar>(colours[i].z));
    model.weights.push_back(positions[i].w);
  }
  return model;
}

void PointFusion::sampleVisible(const Eigen::Matrix4d& T_world_camera, int maxPoints,
                                std::vector<Eigen::Vector3f>& pointsWorldMm,
                                std::vector<Eigen::Vector3f>& normalsWorld) const {
  pointsWorldMm.clear();
  normalsWorld.clear();
  const fusion::FramePose pose = framePose(T_world_camera);
  const fusion::FusionSettings settings = fusionSettings(geometry_, parameters_);
  fusion::FusionModel& model = *model_;  // scratch buffers only: the model's points are not changed
  const int n = device_ == Device::Cuda ? fusion::sampleVisibleCuda(model, pose, settings, maxPoints)
                                        : fusion::sampleVisibleCpu(model, pose, settings, maxPoints);
  std::vector<fusion::Float4> positions(n), normals(n);
  downloadRange(model.samplePositions, 0, n, positions.data());
  downloadRange(model.sampleNormals, 0, n, normals.data());
  pointsWorldMm.reserve(n);
  normalsWorld.reserve(n);
  for (int i = 0; i < n; ++i) {
    pointsWorldMm.emplace_back(positions[i].x, positions[i].y, positions[i].z);
    normalsWorld.emplace_back(normals[i].x, normals[i].y, normals[i].z);
  }
}

namespace {

fusion::MeasuredDepth measuredDepth(ImageView<const float> disparityPx, const RectifiedGeometry& geometry,
                                    const FusionParameters& parameters) {
  require(disparityPx.width == geometry.imageSize.width && disparityPx.height == geometry.imageSize.height &&
              disparityPx.data != nullptr,
          "PointFusion: the disparity must have the rectified size " + std::to_string(geometry.imageSize.width) + "x" +
              std::to_string(geometry.imageSize.height));
  const DisparityRangePx kept = workingDisparityRange(geometry, parameters);
  return {disparityPx, reprojectionOf(geometry), kept.lowestPx, kept.highestPx};
}

/// A host disparity copied into `scratch` on the fusion's device, as a view.
ImageView<const float> disparityOnDevice(const cv::Mat& disparityPx, Device device, Image<float>& scratch) {
  require(disparityPx.type() == CV_32F && !disparityPx.empty(), "PointFusion: the disparity must be CV_32F");
  const cv::Mat host = continuous(disparityPx);
  if (scratch.width() != host.cols || scratch.height() != host.rows) scratch = Image<float>(device, host.cols, host.rows);
  scratch.buffer().upload(host.ptr<float>());
  return scratch.view();
}

}  // namespace

ModelAgreement PointFusion::measureAgreement(ImageView<const float> disparityPx, const Eigen::Matrix4d& T_world_camera,
                                             int sampleStridePx) const {
  require(sampleStridePx >= 1, "PointFusion::measureAgreement: the sample stride must be at least 1 px");
  const fusion::MeasuredDepth measured = measuredDepth(disparityPx, geometry_, parameters_);
  if (pointCount() == 0) return {};
  const fusion::FramePose pose = framePose(T_world_camera);
  const fusion::FusionSettings settings = fusionSettings(geometry_, parameters_);
  const fusion::AgreementGrid grid{geometry_.imageSize.width, geometry_.imageSize.height, sampleStridePx};
  fusion::FusionModel& model = *model_;  // scratch buffers only: the model's points are not changed
  return agreementFromCounters(device_ == Device::Cuda
                                   ? fusion::measureAgreementCuda(model, pose, settings, measured, grid)
                                   : fusion::measureAgreementCpu(model, pose, settings, measured, grid));
}

ModelAgreement PointFusion::measureAgreement(const cv::Mat& disparityPx, const Eigen::Matrix4d& T_world_camera,
                                             int sampleStridePx) const {
  return measureAgreement(disparityOnDevice(disparityPx, device_, model_->disparity), T_world_camera, sampleStridePx);
}

double PointFusion::motionThresholdMm(const ModelAgreement& agreement) const {
  const double median = agreement.measured ? agreement.medianDepthDifferenceMm : 0.0;
  const double threshold = std::max(parameters_.motionMinThresholdMm, parameters_.motionNoiseFactor * median);
  return model_->deforming && deformation_ ? std::max(threshold, deformation_->explainedWithinMm()) : threshold;
}

int PointFusion::updateMotion(ImageView<const float> disparityPx, const Eigen::Matrix4d& T_world_camera,
                              const ModelAgreement& agreement) {
  const fusion::MeasuredDepth measured = measuredDepth(disparityPx, geometry_, parameters_);
  if (parameters_.motionPenalty <= 0 || !agreement.measured ||
      agreement.shareWithin1mm < parameters_.motionMinAgreementShare || pointCount() == 0) {
    return 0;
  }
  const fusion::FramePose pose = framePose(T_world_camera);
  const fusion::FusionSettings settings = fusionSettings(geometry_, parameters_);
  const auto threshold = static_cast<float>(motionThresholdMm(agreement));
  const auto margin = static_cast<float>(parameters_.occlusionMarginMm);
  const auto penalty = static_cast<float>(parameters_.motionPenalty);
  return device_ == Device::Cuda ? fusion::updateMotionCuda(*model_, pose, settings, measured, threshold, margin, penalty)
                                 : fusion::updateMotionCpu(*model_, pose, settings, measured, threshold, margin, penalty);
}

int PointFusion::updateMotion(const cv::Mat& disparityPx, const Eigen::Matrix4d& T_world_camera,
                              const ModelAgreement& agreement) {
  return updateMotion(disparityOnDevice(disparityPx, device_, model_->disparity), T_world_camera, agreement);
}

std::size_t PointFusion::deviceBytes() const { return device_ == Device::Cuda ? model_->bytes() : 0; }

void PointFusion::reset() {
  model_ = std::make_unique<fusion::FusionModel>(device_, geometry_.imageSize.width, geometry_.imageSize.height);
  deformation_ = nullptr;
  motions_.clear();
}

}  // namespace tissuemosaic
