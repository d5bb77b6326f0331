#pragma once
/// @class vtkTissueMosaicStereoLogic
/// @brief Section II of the paper for the application: runs the engine's StereoMatcher on a rectified stereo
/// pair and exposes the result as a coloured point cloud (vtkPolyData).
///
/// The parameters are one tissuemosaic::StereoParameters object (the same struct the command line, the parameter
/// files and the GUI panel edit). Methods that can fail return false and leave a message in GetLastErrorText();
/// they never throw.
///
/// The reconstruction is in the left rectified camera frame (x right, y down, z forward), in millimetres, one
/// vertex per pixel with a disparity estimate, coloured from the left image ("RGB" point scalars).
#include "Core/Device.h"
#include "Core/StereoRig.h"
#include "Stereo/DisparityRangeEstimator.h"
#include "Stereo/StereoMatcher.h"
#include "Stereo/StereoParameters.h"

#include <vtkObject.h>
#include <vtkSmartPointer.h>

#include <memory>
#include <string>

class vtkPolyData;

class vtkTissueMosaicStereoLogic : public vtkObject {
public:
  static vtkTissueMosaicStereoLogic* New();
  vtkTypeMacro(vtkTissueMosaicStereoLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkTissueMosaicStereoLogic(const vtkTissueMosaicStereoLogic&) = delete;
  void operator=(const vtkTissueMosaicStereoLogic&) = delete;

  /// @name Parameters
  /// SetStereoParameters validates first: invalid parameters are refused (false, error text) and the current
  /// ones are kept.
  ///@{
  const tissuemosaic::StereoParameters& GetStereoParameters() const { return this->Parameters; }
  bool SetStereoParameters(const tissuemosaic::StereoParameters& parameters);
  /// Reads the "stereo" map of an OpenCV YAML/XML file (missing keys keep the paper defaults).
  bool ReadParametersFile(const std::string& path);
  bool WriteParametersFile(const std::string& path);
  ///@}

  /// @name Parameter files without a logic object (used by the widgets for presets)
  ///@{
  static bool ReadStereoParametersFile(const std::string& path, tissuemosaic::StereoParameters& parameters,
                                       std::string& errorText);
  /// Same as ReadStereoParametersFile, from YAML text in memory (e.g. a Qt resource).
  static bool ParseStereoParameters(const std::string& yamlText, tissuemosaic::StereoParameters& parameters,
                                    std::string& errorText);
  static bool WriteStereoParametersFile(const std::string& path, const tissuemosaic::StereoParameters& parameters,
                                        std::string& errorText);
  ///@}

  /// @name Device
  /// Auto uses CUDA when this build and machine have it, else the CPU. Cuda on a machine without it makes
  /// ComputeReconstruction fail with the reason; it never falls back silently.
  ///@{
  enum DeviceChoiceType { DeviceAuto = 0, DeviceCpu, DeviceCuda };
  vtkSetClampMacro(DeviceChoice, int, DeviceAuto, DeviceCuda);
  vtkGetMacro(DeviceChoice, int);
  void SetDeviceChoiceToAuto() { this->SetDeviceChoice(DeviceAuto); }
  void SetDeviceChoiceToCpu() { this->SetDeviceChoice(DeviceCpu); }
  void SetDeviceChoiceToCuda() { this->SetDeviceChoice(DeviceCuda); }
  static const char* GetDeviceChoiceAsString(int choice);
  ///@}

  /// @name Geometry of the rectified pair
  /// Either set directly, or read from a calibration file (the rectification it implies gives the geometry).
  ///@{
  void SetRectifiedGeometry(const tissuemosaic::RectifiedGeometry& geometry);
  const tissuemosaic::RectifiedGeometry& GetRectifiedGeometry() const { return this->Geometry; }
  bool LoadCalibration(const std::string& path);
  bool HasRectifiedGeometry() const { return this->Geometry.focalPx > 0; }
  ///@}

  /// Disparity and point cloud of a rectified pair (8-bit grey or BGR, equal sizes matching the geometry), over the
  /// disparity range the parameters ask for (automatic: measured from this pair's sparse feature matches; a pair
  /// with too few fails with the reason). On failure the previous result is cleared.
  bool ComputeReconstruction(const cv::Mat& leftRectified, const cv::Mat& rightRectified);

  /// @name Results of the last successful ComputeReconstruction
  ///@{
  /// Points in mm (left rectified camera frame), "RGB" scalars, one vertex per point. Empty before the first
  /// success. The same object is updated in place by later calls, so a pipeline can hold on to it.
  vtkPolyData* GetReconstruction();
  /// Left-view disparity in pixels (CV_32F, NaN = no estimate).
  const cv::Mat& GetLastDisparityPx() const { return this->LastDisparityPx; }
  const tissuemosaic::StereoTimingsMs& GetLastTimingsMs() const { return this->LastTimingsMs; }
  /// The disparity range the pair was matched over, and how it was chosen ("auto: 64..95 px (from 412 left-right
  /// feature matches)", "fixed: -20..80 px", "working distance 30..150 mm: 28..143 px").
  const tissuemosaic::DisparityRange& GetLastDisparityRange() const { return this->LastDisparityRange; }
  const std::string& GetLastDisparityRangeText() const { return this->LastDisparityRangeText; }
  ///@}

  /// Message of the last failure, empty after a success.
  const std::string& GetLastErrorText() const { return this->LastErrorText; }

protected:
  vtkTissueMosaicStereoLogic();
  ~vtkTissueMosaicStereoLogic() override;

private:
  bool Fail(const std::string& message);

  tissuemosaic::StereoParameters Parameters;
  int DeviceChoice = DeviceAuto;
  tissuemosaic::RectifiedGeometry Geometry;
  std::unique_ptr<tissuemosaic::StereoMatcher> Matcher;  ///< rebuilt when the parameters or the device change
  std::unique_ptr<tissuemosaic::DisparityRangeEstimator> RangeEstimator;  ///< automatic range; rebuilt with the device
  vtkSmartPointer<vtkPolyData> Reconstruction;
  cv::Mat LastDisparityPx;
  tissuemosaic::StereoTimingsMs LastTimingsMs;
  tissuemosaic::DisparityRange LastDisparityRange;
  std::string LastDisparityRangeText;
  std::string LastErrorText;
};
