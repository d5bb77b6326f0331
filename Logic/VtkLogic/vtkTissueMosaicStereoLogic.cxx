#include "vtkTissueMosaicStereoLogic.h"
#include "vtkTissueMosaicRunCatching.h"

#include "vtkTissueMosaicPointCloud.h"

#include "Core/Error.h"
#include "IO/Calibration/CalibrationFile.h"
#include "Stereo/DisparityRangeFollower.h"

#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include <opencv2/core/persistence.hpp>

#include <filesystem>
#include <optional>

vtkStandardNewMacro(vtkTissueMosaicStereoLogic);

namespace {

using tissuemosaic::runCatching;

bool readParameters(cv::FileStorage& storage, const std::string& source, tissuemosaic::StereoParameters& parameters,
                    std::string& errorText) {
  tissuemosaic::StereoParameters read;
  if (!runCatching([&] { read = tissuemosaic::StereoParameters::read(storage["stereo"]); }, errorText)) {
    errorText = source + ": " + errorText;
    return false;
  }
  parameters = read;
  return true;
}

}  // namespace

vtkTissueMosaicStereoLogic::vtkTissueMosaicStereoLogic() : Reconstruction(vtkSmartPointer<vtkPolyData>::New()) {}

vtkTissueMosaicStereoLogic::~vtkTissueMosaicStereoLogic() = default;

vtkPolyData* vtkTissueMosaicStereoLogic::GetReconstruction() { return this->Reconstruction; }

bool vtkTissueMosaicStereoLogic::Fail(const std::string& message) {
  this->LastErrorText = message;
  return false;
}

void vtkTissueMosaicStereoLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  const tissuemosaic::StereoParameters& p = this->Parameters;
  os << indent << "DeviceChoice: " << GetDeviceChoiceAsString(this->DeviceChoice) << "\n";
  os << indent << "DisparityRangeMode: " << tissuemosaic::disparityRangeModeName(p.disparityRangeMode) << "\n";
  os << indent << "DisparityRangePx: [" << p.minDisparityPx << ", " << p.maxDisparityPx << "]\n";
  os << indent << "WorkingDistanceMm: [" << p.workingDistanceNearMm << ", " << p.workingDistanceFarMm << "]\n";
  os << indent << "LastDisparityRange: " << this->LastDisparityRangeText << "\n";
  os << indent << "ZnccWindowPx: " << p.znccWindowPx << "\n";
  os << indent << "OutlierIterations: " << p.outlierIterations << "\n";
  os << indent << "RefineIterations: " << p.refineIterations << "\n";
  os << indent << "RectifiedGeometry: ";
  if (this->HasRectifiedGeometry()) {
    os << this->Geometry.imageSize.width << "x" << this->Geometry.imageSize.height << " px, focal "
       << this->Geometry.focalPx << " px, baseline " << this->Geometry.baselineMm << " mm\n";
  } else {
    os << "(none)\n";
  }
  os << indent << "ReconstructionPoints: " << this->Reconstruction->GetNumberOfPoints() << "\n";
  os << indent << "LastErrorText: " << this->LastErrorText << "\n";
}

bool vtkTissueMosaicStereoLogic::SetStereoParameters(const tissuemosaic::StereoParameters& parameters) {
  if (!runCatching([&] { parameters.validate(); }, this->LastErrorText)) return false;
  this->Parameters = parameters;
  this->Matcher.reset();
  this->Modified();
  return true;
}

bool vtkTissueMosaicStereoLogic::ReadParametersFile(const std::string& path) {
  tissuemosaic::StereoParameters parameters;
  if (!ReadStereoParametersFile(path, parameters, this->LastErrorText)) return false;
  return this->SetStereoParameters(parameters);
}

bool vtkTissueMosaicStereoLogic::WriteParametersFile(const std::string& path) {
  return WriteStereoParametersFile(path, this->Parameters, this->LastErrorText);
}

bool vtkTissueMosaicStereoLogic::ReadStereoParametersFile(const std::string& path,
                                                          tissuemosaic::StereoParameters& parameters,
                                                          std::string& errorText) {
  if (!std::filesystem::is_regular_file(path)) {
    errorText = "the parameter file " + path + " does not exist";
    return false;
  }
  cv::FileStorage storage;
  if (!runCatching([&] { storage.open(path, cv::FileStorage::READ); }, errorText) || !storage.isOpened()) {
    errorText = "cannot read the parameter file " + path + (errorText.empty() ? "" : ": " + errorText);
    return false;
  }
  return readParameters(storage, path, parameters, errorText);
}

bool vtkTissueMosaicStereoLogic::ParseStereoParameters(const std::string& yamlText,
                                                       tissuemosaic::StereoParameters& parameters,
                                                       std::string& errorText) {
  cv::FileStorage storage;
  const int flags = cv::FileStorage::READ | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML;
  if (!runCatching([&] { storage.open(yamlText, flags); }, errorText) || !storage.isOpened()) {
    errorText = "cannot parse the parameter text" + (errorText.empty() ? std::string() : ": " + errorText);
    return false;
  }
  return readParameters(storage, "parameter text", parameters, errorText);
}

bool vtkTissueMosaicStereoLogic::WriteStereoParametersFile(const std::string& path,
                                                           const tissuemosaic::StereoParameters& parameters,
                                                           std::string& errorText) {
  const bool written = runCatching(
      [&] {
        parameters.validate();
        cv::FileStorage storage(path, cv::FileStorage::WRITE);
        tissuemosaic::require(storage.isOpened(), "cannot write the parameter file " + path);
        parameters.write(storage);
      },
      errorText);
  return written;
}

const char* vtkTissueMosaicStereoLogic::GetDeviceChoiceAsString(int choice) {
  switch (choice) {
    case DeviceCpu: return "cpu";
    case DeviceCuda: return "cuda";
    default: return "auto";
  }
}

void vtkTissueMosaicStereoLogic::SetRectifiedGeometry(const tissuemosaic::RectifiedGeometry& geometry) {
  this->Geometry = geometry;
  this->Modified();
}

bool vtkTissueMosaicStereoLogic::LoadCalibration(const std::string& path) {
  tissuemosaic::RectifiedGeometry geometry;
  const bool loaded = runCatching(
      [&] {
        const tissuemosaic::StereoRectifier rectifier(tissuemosaic::readStereoCalibration(path));
        geometry = rectifier.geometry();
      },
      this->LastErrorText);
  if (!loaded) return this->Fail(path + ": " + this->LastErrorText);
  this->SetRectifiedGeometry(geometry);
  return true;
}

bool vtkTissueMosaicStereoLogic::ComputeReconstruction(const cv::Mat& leftRectified, const cv::Mat& rightRectified) {
  this->Reconstruction->Initialize();
  this->LastDisparityPx = cv::Mat();
  this->LastTimingsMs = {};
  this->LastDisparityRange = {};
  this->LastDisparityRangeText.clear();
  if (!this->HasRectifiedGeometry()) {
    return this->Fail("no stereo geometry: load a calibration file or set the rectified geometry first");
  }
  if (leftRectified.size() != this->Geometry.imageSize) {
    return this->Fail("the left image is " + std::to_string(leftRectified.cols) + "x" +
                      std::to_string(leftRectified.rows) + " px but the calibration is for " +
                      std::to_string(this->Geometry.imageSize.width) + "x" +
                      std::to_string(this->Geometry.imageSize.height) + " px");
  }
  tissuemosaic::ColoredPointCloud cloud;
  const bool computed = runCatching(
      [&] {
        const tissuemosaic::Device device = tissuemosaic::parseDevice(GetDeviceChoiceAsString(this->DeviceChoice));
        if (!this->Matcher || this->Matcher->device() != device) {
          this->Matcher = std::make_unique<tissuemosaic::StereoMatcher>(device, this->Parameters);
        }
        // Each pair stands alone: its own range (the reconstruction logic follows a video's instead).
        tissuemosaic::DisparityRangeHistory history;
        history.mode = this->Parameters.disparityRangeMode;
        std::optional<tissuemosaic::DisparityRange> range =
            tissuemosaic::requestedDisparityRange(this->Parameters, &this->Geometry);
        cv::Mat rightAligned = rightRectified;  // moved onto the left's rows where the check finds them apart
        if (!range) {
          if (!this->RangeEstimator || this->RangeEstimator->device() != device ||
              this->RangeEstimator->options().infinityDisparityPx != -this->Geometry.doffsPx) {
            tissuemosaic::DisparityRangeEstimatorOptions options;
            options.infinityDisparityPx = -this->Geometry.doffsPx;
            this->RangeEstimator = std::make_unique<tissuemosaic::DisparityRangeEstimator>(device, options);
          }
          const tissuemosaic::DisparitySample sample = this->RangeEstimator->measure(
              leftRectified, rightRectified, tissuemosaic::DisparityRangeEstimator::RowCheck::Measure);
          range = this->RangeEstimator->wantedRange(sample);
          history.firstMatches = sample.matches();
          history.rowOffsetPx = sample.rowOffsetPx;
          rightAligned = tissuemosaic::alignRightRows(rightRectified, sample.rowOffsetPx);
        }
        this->Matcher->setDisparityRange(*range);
        history.first = history.current = *range;
        this->LastDisparityRange = *range;
        this->LastDisparityRangeText = tissuemosaic::describeDisparityRange(history, this->Parameters);
        this->LastDisparityPx = this->Matcher->computeDisparity(leftRectified, rightAligned, &this->LastTimingsMs);
        cloud = tissuemosaic::disparityToPointCloud(this->LastDisparityPx, leftRectified, this->Geometry);
      },
      this->LastErrorText);
  if (!computed) {
    this->LastDisparityPx = cv::Mat();
    this->LastDisparityRange = {};
    this->LastDisparityRangeText.clear();
    return false;
  }
  // Update in place so that mappers and filters connected to GetReconstruction() see the new cloud.
  this->Reconstruction->ShallowCopy(tissuemosaic::pointCloudToPolyData(cloud));
  this->Modified();
  return true;
}
