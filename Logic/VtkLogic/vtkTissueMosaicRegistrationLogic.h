#pragma once
/// @class vtkTissueMosaicRegistrationLogic
/// @brief The state of one registration of the reconstructed model to a CT/MR surface model, for the application:
/// the two models, the landmark pairs being picked, the current transform, and the accuracy evaluation that
/// follows every change of the transform. It only holds state and calls the registration functions
/// (vtkTissueMosaicRegistration, SurfaceDistance, DistanceReport and the file readers/writers); it computes
/// nothing of its own. No Qt.
///
/// Frames: everything is LPS millimetres (see docs/REGISTRATION.md). Model landmarks are in the model's own frame,
/// target landmarks in the target's; the transform is T_target_model (target = T * model).
///
/// Methods that can fail return false (or -1) and leave a message in GetLastErrorText(); they never throw, and a
/// failed call leaves the state as it was. Every change of the state calls Modified().
#include "vtkTissueMosaicAnatomicalFrame.h"
#include "vtkTissueMosaicRegistration.h"
#include "vtkTissueMosaicSurfaceDistance.h"

#include <Eigen/Core>
#include <vtkObject.h>
#include <vtkPolyData.h>  // GetRegisteredModel() converts a smart pointer: the type must be complete
#include <vtkSmartPointer.h>

#include <memory>
#include <optional>
#include <string>
#include <vector>

class vtkTissueMosaicRegistrationLogic : public vtkObject {
public:
  static vtkTissueMosaicRegistrationLogic* New();
  vtkTypeMacro(vtkTissueMosaicRegistrationLogic, vtkObject);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  vtkTissueMosaicRegistrationLogic(const vtkTissueMosaicRegistrationLogic&) = delete;
  void operator=(const vtkTissueMosaicRegistrationLogic&) = delete;

  /// @name Models
  /// A new model or target resets the transform to the identity and drops the results; the landmarks are kept
  /// (the user deletes the ones that no longer apply).
  ///@{
  /// Reads a model file (.ply .vtp .vtk .stl .obj) in the frame it declares, or the one forced by `frame`.
  bool LoadModel(const std::string& path, tissuemosaic::ModelFrameChoice frame = tissuemosaic::ModelFrameChoice::FromFile);
  /// Uses this model (LPS/world mm; referenced, not copied): the live reconstruction may keep growing in place;
  /// registration and evaluation use its points at the time they run. Setting the model already held changes
  /// nothing. nullptr removes the model.
  void SetModel(vtkPolyData* modelLps);
  vtkPolyData* GetModel() const;
  /// Reads the CT/MR surface (must have polygons).
  bool LoadTarget(const std::string& path, tissuemosaic::ModelFrameChoice frame = tissuemosaic::ModelFrameChoice::FromFile);
  /// Uses this surface (LPS mm, referenced); false when it has no polygons. nullptr removes the target.
  bool SetTarget(vtkPolyData* targetLps);
  vtkPolyData* GetTarget() const;
  ///@}

  /// @name Landmark pairs
  /// A pair may be incomplete while the user picks (only its model or only its target point); registration uses
  /// the complete pairs. Labels are unique and non-empty ("L1", "L2", ... unless set).
  ///@{
  struct LandmarkPair {
    std::string label;
    std::optional<Eigen::Vector3d> modelLps;   ///< in the model's frame
    std::optional<Eigen::Vector3d> targetLps;  ///< in the target's frame
    bool IsComplete() const { return modelLps.has_value() && targetLps.has_value(); }
  };
  int GetNumberOfLandmarkPairs() const { return static_cast<int>(this->Pairs.size()); }
  int GetNumberOfCompleteLandmarkPairs() const;
  /// The pair at `index` (0 <= index < GetNumberOfLandmarkPairs()).
  const LandmarkPair& GetLandmarkPair(int index) const { return this->Pairs.at(static_cast<std::size_t>(index)); }
  /// Appends a complete pair; returns its index (-1 for non-finite positions or a duplicate label).
  int AddLandmarkPair(const Eigen::Vector3d& modelLps, const Eigen::Vector3d& targetLps, const std::string& label = "");
  /// A point picked on the model: completes the first pair that has no model point yet, else starts a new pair.
  /// Returns the pair's index (-1 for a non-finite position).
  int AddModelLandmark(const Eigen::Vector3d& modelLps);
  /// The same for a point picked on the target.
  int AddTargetLandmark(const Eigen::Vector3d& targetLps);
  bool SetModelLandmark(int index, const Eigen::Vector3d& modelLps);
  bool SetTargetLandmark(int index, const Eigen::Vector3d& targetLps);
  bool SetLandmarkLabel(int index, const std::string& label);
  bool RemoveLandmarkPair(int index);
  void ClearLandmarks();
  /// Drops the model side of every pair (the model they were picked on is gone) and keeps the CT/MR side, so that
  /// the user picks only the model points again.
  void ClearModelLandmarks();
  /// Replaces the pairs with those of a .mrk.json holding two lists (model's, then target's) as written by
  /// WriteLandmarks and `tissuemosaic register --out-landmarks`.
  bool LoadLandmarkPairs(const std::string& path,
                         std::optional<tissuemosaic::AnatomicalFrame> frameIfUndeclared = std::nullopt);
  /// |target - T * model| of a complete pair under the current transform; NaN for an incomplete one.
  double GetLandmarkResidualMm(int index) const;
  /// RMS of the complete pairs' residuals under the current transform (after ICP it differs from the landmark
  /// registration's own RMSE); NaN without a complete pair.
  double GetCurrentLandmarkRmseMm() const;
  ///@}

  /// @name Registration
  ///@{
  /// Least-squares fit of the complete pairs (rigid, or with a uniform scale); replaces the transform and drops
  /// the ICP result.
  bool RegisterLandmarks(bool withScale);
  /// ICP from the current transform (the landmark result, or the identity); needs the model and the target.
  bool RefineIcp(const tissuemosaic::IcpParameters& parameters = {});
  /// Sets the transform directly (e.g. one read from a file); drops the landmark and ICP results.
  bool SetTargetFromModel(const Eigen::Matrix4d& targetFromModel);
  /// Reads a .tfm written by WriteTransform (or Slicer's model->CT transform) as the current transform.
  bool LoadTransform(const std::string& path);
  const Eigen::Matrix4d& GetTargetFromModel() const { return this->TargetFromModel; }
  /// The result of the last RegisterLandmarks, if the transform still comes from it (or from ICP after it).
  const std::optional<tissuemosaic::LandmarkRegistration>& GetLandmarkRegistration() const { return this->Landmarks; }
  /// The result of the last RefineIcp, if the transform still comes from it.
  const std::optional<tissuemosaic::IcpResult>& GetIcpResult() const { return this->Icp; }
  /// True once a registration step, or SetTargetFromModel, has set the transform (the identity of a fresh state is
  /// not a registration); a new model or target clears it.
  bool HasRegistration() const { return this->Registered; }
  /// Puts back the transform and results of before the last registration step (landmarks, ICP, a set
  /// transform); the landmark pairs stay as they are. False when there is nothing to undo.
  bool Undo();
  bool CanUndo() const { return !this->History.empty(); }
  ///@}

  /// @name Long steps off the owner thread
  /// ICP and the evaluation of a large model take seconds. A job splits a step in three: Prepare* (owner thread)
  /// copies what the step needs, or fails with the error text like the synchronous method; RunJob (any thread,
  /// while the owner leaves the logic alone) computes, reporting progress and honouring Cancel(); FinishJob (owner
  /// thread) commits the result exactly as the synchronous method would, or leaves the state as it was and sets
  /// the error text. RegisterLandmarks, RefineIcp and Evaluate are these three calls in a row.
  ///@{
  class Job;
  std::shared_ptr<Job> PrepareLandmarkRegistration(bool withScale);
  std::shared_ptr<Job> PrepareIcp(const tissuemosaic::IcpParameters& parameters);
  std::shared_ptr<Job> PrepareEvaluation();
  /// Never throws: a failure is kept in the job for FinishJob.
  static void RunJob(Job& job);
  bool FinishJob(Job& job);
  /// ICP steps taken so far by a running job (0 for other steps); may be read from any thread.
  static int GetJobProgress(const Job& job);
  /// Asks a running job to stop (any thread); FinishJob then fails with "... cancelled" and changes nothing.
  static void CancelJob(Job& job);
  ///@}

  /// @name Evaluation
  /// Recomputed after every registration step, when both models are set: the distance of every model point,
  /// mapped by the transform, to the target surface.
  ///@{
  /// Recomputes the evaluation now (e.g. after the live model grew). False when a model is missing.
  bool Evaluate();
  bool HasEvaluation() const { return this->Result.registeredModel != nullptr; }
  /// Model points when the evaluation was made (a live model may have grown since: the results are then out of
  /// date); 0 without an evaluation.
  vtkIdType GetEvaluatedModelPoints() const { return this->Result.modelPoints; }
  /// Zeros without an evaluation.
  const tissuemosaic::DistanceStatistics& GetDistanceStatistics() const { return this->Result.statistics; }
  const tissuemosaic::DistanceHistogram& GetDistanceHistogram() const { return this->Result.histogram; }
  /// Per model point (in the model's point order); empty without an evaluation.
  const std::vector<double>& GetDistancesMm() const { return this->Result.distancesMm; }
  const std::vector<double>& GetSignedDistancesMm() const { return this->Result.signedDistancesMm; }
  /// A copy of the model mapped into the target's frame, with the point arrays "DistanceMm" (active scalars) and
  /// "SignedDistanceMm"; nullptr without an evaluation. Replaced (a new object) by every evaluation.
  vtkPolyData* GetRegisteredModel() const { return this->Result.registeredModel; }
  /// Histogram bin width (mm, > 0; default 0.1, as the command line). Re-bins a present evaluation.
  bool SetHistogramBinWidthMm(double binWidthMm);
  double GetHistogramBinWidthMm() const { return this->HistogramBinWidthMm; }
  ///@}

  /// @name Export (LPS; the files and conventions of `tissuemosaic register`)
  ///@{
  /// ITK .tfm holding T_model_target (the resampling convention Slicer expects).
  bool WriteTransform(const std::string& path);
  /// The registered model with its distance arrays (.vtp .ply .vtk); needs an evaluation.
  bool WriteRegisteredModel(const std::string& path);
  /// The complete pairs as a .mrk.json with two lists (model's, then target's); incomplete pairs are not written.
  bool WriteLandmarks(const std::string& path);
  /// Per-point CSV of the registered positions and distances; needs an evaluation.
  bool WriteDistanceCsv(const std::string& path);
  /// PNG bar plot of the histogram; needs an evaluation.
  bool WriteHistogramPng(const std::string& path);
  ///@}

  /// Message of the last failure, empty after a success.
  const std::string& GetLastErrorText() const { return this->LastErrorText; }

protected:
  vtkTissueMosaicRegistrationLogic();
  ~vtkTissueMosaicRegistrationLogic() override;

private:
  template <class Work>
  bool Run(Work&& work);
  bool Fail(const std::string& message);
  struct Evaluation {
    vtkIdType modelPoints = 0;
    tissuemosaic::DistanceStatistics statistics;
    tissuemosaic::DistanceHistogram histogram;
    std::vector<Eigen::Vector3d> registeredPointsLps;  ///< double precision, as the CSV reports them
    std::vector<double> distancesMm;
    std::vector<double> signedDistancesMm;
    vtkSmartPointer<vtkPolyData> registeredModel;
  };
  /// What a registration step sets, kept for Undo.
  struct RegistrationState {
    Eigen::Matrix4d targetFromModel = Eigen::Matrix4d::Identity();
    std::optional<tissuemosaic::LandmarkRegistration> landmarks;
    std::optional<tissuemosaic::IcpResult> icp;
    bool registered = false;
    Evaluation result;
  };
  /// The evaluation of `model` (a snapshot) mapped by a transform against `surface`, else an empty one when either
  /// is missing or empty. Throws Error; changes nothing; safe on any thread.
  static Evaluation Evaluated(vtkPolyData* model, const tissuemosaic::TargetSurface* surface,
                              const Eigen::Matrix4d& targetFromModel, double histogramBinWidthMm);
  std::shared_ptr<Job> NewJob();
  void ResetResults();
  std::string NextLabel() const;
  bool IsLabelTaken(const std::string& label, int exceptIndex) const;
  bool ValidIndex(int index);
  int FailIndex(const std::string& message);

  vtkSmartPointer<vtkPolyData> Model;
  vtkSmartPointer<vtkPolyData> Target;
  std::shared_ptr<const tissuemosaic::TargetSurface> Surface;  ///< shared with running jobs
  std::vector<LandmarkPair> Pairs;

  Eigen::Matrix4d TargetFromModel = Eigen::Matrix4d::Identity();
  std::optional<tissuemosaic::LandmarkRegistration> Landmarks;
  std::optional<tissuemosaic::IcpResult> Icp;
  bool Registered = false;
  std::vector<RegistrationState> History;  ///< for Undo, oldest first

  double HistogramBinWidthMm = 0.1;
  Evaluation Result;

  std::string LastErrorText;
};
