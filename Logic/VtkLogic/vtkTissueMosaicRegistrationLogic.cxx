#include "vtkTissueMosaicRegistrationLogic.h"

#include "vtkTissueMosaicDistanceReport.h"
#include "vtkTissueMosaicItkTransformFile.h"
#include "vtkTissueMosaicLandmarksFile.h"
#include "vtkTissueMosaicSurfaceModelFile.h"

#include "Core/Error.h"

#include <vtkObjectFactory.h>
#include <vtkPolyData.h>

#include <atomic>
#include <cmath>
#include <limits>

vtkStandardNewMacro(vtkTissueMosaicRegistrationLogic);

/// One registration step's inputs (snapshots taken on the owner thread), progress and outputs.
class vtkTissueMosaicRegistrationLogic::Job {
public:
  enum Kind { LandmarkStep, IcpStep, EvaluationStep };
  Kind kind = EvaluationStep;
  // Inputs
  vtkPolyData* sourceModel = nullptr;             ///< the logic's model when prepared (identity only, never read)
  vtkSmartPointer<vtkPolyData> model;             ///< a copy of it, which the step reads on its thread
  std::shared_ptr<const tissuemosaic::TargetSurface> surface;
  Eigen::Matrix4d start = Eigen::Matrix4d::Identity();
  std::vector<Eigen::Vector3d> modelLandmarks, targetLandmarks;
  bool withScale = false;
  tissuemosaic::IcpParameters icpParameters;
  double histogramBinWidthMm = 0.1;
  // Progress
  std::atomic<int> iterations{0};
  std::atomic<bool> cancelled{false};
  // Outputs
  Eigen::Matrix4d transform = Eigen::Matrix4d::Identity();
  std::optional<tissuemosaic::LandmarkRegistration> landmarks;
  std::optional<tissuemosaic::IcpResult> icp;
  Evaluation evaluation;
  bool ran = false;
  std::string errorText;
};

namespace {

bool finite(const Eigen::Vector3d& point) { return point.allFinite(); }

}  // namespace

vtkTissueMosaicRegistrationLogic::vtkTissueMosaicRegistrationLogic() = default;
vtkTissueMosaicRegistrationLogic::~vtkTissueMosaicRegistrationLogic() = default;

void vtkTissueMosaicRegistrationLogic::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Model points: " << (this->Model ? this->Model->GetNumberOfPoints() : 0) << "\n";
  os << indent << "Target cells: " << (this->Target ? this->Target->GetNumberOfCells() : 0) << "\n";
  os << indent << "Landmark pairs: " << this->Pairs.size() << " (" << this->GetNumberOfCompleteLandmarkPairs()
     << " complete)\n";
  os << indent << "TargetFromModel:\n" << this->TargetFromModel << "\n";
  if (this->HasEvaluation()) os << indent << "RMSE (mm): " << this->Result.statistics.rmseMm << "\n";
}

// Turns what the registration functions throw into the error text; the state is only changed by `work` itself,
// which commits after everything that can throw has run.
template <class Work>
bool vtkTissueMosaicRegistrationLogic::Run(Work&& work) {
  try {
    work();
    this->LastErrorText.clear();
    return true;
  } catch (const std::exception& error) {
    return this->Fail(error.what());
  }
}

bool vtkTissueMosaicRegistrationLogic::Fail(const std::string& message) {
  this->LastErrorText = message;
  return false;
}

int vtkTissueMosaicRegistrationLogic::FailIndex(const std::string& message) {
  this->Fail(message);
  return -1;
}

// ---- models -----------------------------------------------------------------------------------------------------

bool vtkTissueMosaicRegistrationLogic::LoadModel(const std::string& path, tissuemosaic::ModelFrameChoice frame) {
  return this->Run([&] {
    tissuemosaic::SurfaceModelFile file = tissuemosaic::readSurfaceModel(path, frame);
    this->Model = file.polyDataLps;
    this->ResetResults();
    this->Modified();
  });
}

void vtkTissueMosaicRegistrationLogic::SetModel(vtkPolyData* modelLps) {
  if (modelLps == this->Model) return;
  this->Model = modelLps;
  this->ResetResults();
  this->LastErrorText.clear();
  this->Modified();
}

vtkPolyData* vtkTissueMosaicRegistrationLogic::GetModel() const { return this->Model; }

bool vtkTissueMosaicRegistrationLogic::LoadTarget(const std::string& path, tissuemosaic::ModelFrameChoice frame) {
  return this->Run([&] {
    tissuemosaic::SurfaceModelFile file = tissuemosaic::readSurfaceModel(path, frame);
    auto surface = std::make_shared<const tissuemosaic::TargetSurface>(file.polyDataLps);  // throws without polygons
    this->Target = file.polyDataLps;
    this->Surface = std::move(surface);
    this->ResetResults();
    this->Modified();
  });
}

bool vtkTissueMosaicRegistrationLogic::SetTarget(vtkPolyData* targetLps) {
  return this->Run([&] {
    std::shared_ptr<const tissuemosaic::TargetSurface> surface;
    if (targetLps) surface = std::make_shared<const tissuemosaic::TargetSurface>(targetLps);
    this->Target = targetLps;
    this->Surface = std::move(surface);
    this->ResetResults();
    this->Modified();
  });
}

vtkPolyData* vtkTissueMosaicRegistrationLogic::GetTarget() const { return this->Target; }

void vtkTissueMosaicRegistrationLogic::ResetResults() {
  this->TargetFromModel.setIdentity();
  this->Landmarks.reset();
  this->Icp.reset();
  this->Registered = false;
  this->History.clear();
  this->Result = {};
}

// ---- landmarks --------------------------------------------------------------------------------------------------

int vtkTissueMosaicRegistrationLogic::GetNumberOfCompleteLandmarkPairs() const {
  int complete = 0;
  for (const LandmarkPair& pair : this->Pairs) complete += pair.IsComplete();
  return complete;
}

bool vtkTissueMosaicRegistrationLogic::IsLabelTaken(const std::string& label, int exceptIndex) const {
  for (std::size_t i = 0; i < this->Pairs.size(); ++i) {
    if (static_cast<int>(i) != exceptIndex && this->Pairs[i].label == label) return true;
  }
  return false;
}

std::string vtkTissueMosaicRegistrationLogic::NextLabel() const {
  for (std::size_t n = this->Pairs.size() + 1;; ++n) {
    const std::string label = "L" + std::to_string(n);
    if (!this->IsLabelTaken(label, -1)) return label;
  }
}

bool vtkTissueMosaicRegistrationLogic::ValidIndex(int index) {
  if (index >= 0 && index < this->GetNumberOfLandmarkPairs()) return true;
  return this->Fail("no landmark pair " + std::to_string(index) + " (there are " +
                    std::to_string(this->Pairs.size()) + ")");
}

int vtkTissueMosaicRegistrationLogic::AddLandmarkPair(const Eigen::Vector3d& modelLps, const Eigen::Vector3d& targetLps,
                                                      const std::string& label) {
  if (!finite(modelLps) || !finite(targetLps)) return this->FailIndex("landmark positions must be finite");
  const std::string name = label.empty() ? this->NextLabel() : label;
  if (this->IsLabelTaken(name, -1)) return this->FailIndex("landmark label '" + name + "' is already used");
  this->Pairs.push_back({name, modelLps, targetLps});
  this->LastErrorText.clear();
  this->Modified();
  return this->GetNumberOfLandmarkPairs() - 1;
}

int vtkTissueMosaicRegistrationLogic::AddModelLandmark(const Eigen::Vector3d& modelLps) {
  if (!finite(modelLps)) return this->FailIndex("landmark positions must be finite");
  for (std::size_t i = 0; i < this->Pairs.size(); ++i) {
    if (!this->Pairs[i].modelLps) {
      this->Pairs[i].modelLps = modelLps;
      this->LastErrorText.clear();
      this->Modified();
      return static_cast<int>(i);
    }
  }
  this->Pairs.push_back({this->NextLabel(), modelLps, std::nullopt});
  this->LastErrorText.clear();
  this->Modified();
  return this->GetNumberOfLandmarkPairs() - 1;
}

int vtkTissueMosaicRegistrationLogic::AddTargetLandmark(const Eigen::Vector3d& targetLps) {
  if (!finite(targetLps)) return this->FailIndex("landmark positions must be finite");
  for (std::size_t i = 0; i < this->Pairs.size(); ++i) {
    if (!this->Pairs[i].targetLps) {
      this->Pairs[i].targetLps = targetLps;
      this->LastErrorText.clear();
      this->Modified();
      return static_cast<int>(i);
    }
  }
  this->Pairs.push_back({this->NextLabel(), std::nullopt, targetLps});
  this->LastErrorText.clear();
  this->Modified();
  return this->GetNumberOfLandmarkPairs() - 1;
}

bool vtkTissueMosaicRegistrationLogic::SetModelLandmark(int index, const Eigen::Vector3d& modelLps) {
  if (!this->ValidIndex(index)) return false;
  if (!finite(modelLps)) return this->Fail("landmark positions must be finite");
  this->Pairs[static_cast<std::size_t>(index)].modelLps = modelLps;
  this->LastErrorText.clear();
  this->Modified();
  return true;
}

bool vtkTissueMosaicRegistrationLogic::SetTargetLandmark(int index, const Eigen::Vector3d& targetLps) {
  if (!this->ValidIndex(index)) return false;
  if (!finite(targetLps)) return this->Fail("landmark positions must be finite");
  this->Pairs[static_cast<std::size_t>(index)].targetLps = targetLps;
  this->LastErrorText.clear();
  this->Modified();
  return true;
}

bool vtkTissueMosaicRegistrationLogic::SetLandmarkLabel(int index, const std::string& label) {
  if (!this->ValidIndex(index)) return false;
  if (label.empty()) return this->Fail("a landmark label must not be empty");
  if (this->IsLabelTaken(label, index)) return this->Fail("landmark label '" + label + "' is already used");
  this->Pairs[static_cast<std::size_t>(index)].label = label;
  this->LastErrorText.clear();
  this->Modified();
  return true;
}

bool vtkTissueMosaicRegistrationLogic::RemoveLandmarkPair(int index) {
  if (!this->ValidIndex(index)) return false;
  this->Pairs.erase(this->Pairs.begin() + index);
  this->LastErrorText.clear();
  this->Modified();
  return true;
}

void vtkTissueMosaicRegistrationLogic::ClearLandmarks() {
  this->Pairs.clear();
  this->LastErrorText.clear();
  this->Modified();
}

void vtkTissueMosaicRegistrationLogic::ClearModelLandmarks() {
  std::vector<LandmarkPair> kept;
  for (LandmarkPair& pair : this->Pairs) {
    if (!pair.targetLps) continue;  // a pair with nothing left goes
    pair.modelLps.reset();
    kept.push_back(std::move(pair));
  }
  this->Pairs = std::move(kept);
  this->LastErrorText.clear();
  this->Modified();
}

bool vtkTissueMosaicRegistrationLogic::LoadLandmarkPairs(const std::string& path,
                                                         std::optional<tissuemosaic::AnatomicalFrame> frameIfUndeclared) {
  return this->Run([&] {
    const tissuemosaic::LandmarkPairs read = tissuemosaic::readLandmarkPairs(path, frameIfUndeclared);
    std::vector<LandmarkPair> pairs;
    for (std::size_t i = 0; i < read.modelLps.size(); ++i) {
      std::string label = i < read.labels.size() ? read.labels[i] : std::string();
      bool taken = label.empty();
      for (const LandmarkPair& pair : pairs) taken = taken || pair.label == label;
      if (taken) label = "L" + std::to_string(i + 1);  // pairs matched by order may have empty or repeated labels
      pairs.push_back({label, read.modelLps[i], read.targetLps[i]});
    }
    this->Pairs = std::move(pairs);
    this->Modified();
  });
}

double vtkTissueMosaicRegistrationLogic::GetLandmarkResidualMm(int index) const {
  const LandmarkPair& pair = this->GetLandmarkPair(index);
  if (!pair.IsComplete()) return std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d mapped =
      this->TargetFromModel.topLeftCorner<3, 3>() * *pair.modelLps + this->TargetFromModel.topRightCorner<3, 1>();
  return (*pair.targetLps - mapped).norm();
}

double vtkTissueMosaicRegistrationLogic::GetCurrentLandmarkRmseMm() const {
  double sum = 0;
  int complete = 0;
  for (int i = 0; i < this->GetNumberOfLandmarkPairs(); ++i) {
    const double residual = this->GetLandmarkResidualMm(i);
    if (!std::isfinite(residual)) continue;
    sum += residual * residual;
    ++complete;
  }
  return complete > 0 ? std::sqrt(sum / complete) : std::numeric_limits<double>::quiet_NaN();
}

// ---- registration -----------------------------------------------------------------------------------------------

bool vtkTissueMosaicRegistrationLogic::RegisterLandmarks(bool withScale) {
  const std::shared_ptr<Job> job = this->PrepareLandmarkRegistration(withScale);
  if (!job) return false;
  RunJob(*job);
  return this->FinishJob(*job);
}

bool vtkTissueMosaicRegistrationLogic::RefineIcp(const tissuemosaic::IcpParameters& parameters) {
  const std::shared_ptr<Job> job = this->PrepareIcp(parameters);
  if (!job) return false;
  RunJob(*job);
  return this->FinishJob(*job);
}

bool vtkTissueMosaicRegistrationLogic::SetTargetFromModel(const Eigen::Matrix4d& targetFromModel) {
  if (!targetFromModel.allFinite()) return this->Fail("the transform must be finite");
  if (!targetFromModel.row(3).isApprox(Eigen::RowVector4d(0, 0, 0, 1))) {
    return this->Fail("the transform's last row must be 0 0 0 1");
  }
  return this->Run([&] {
    vtkSmartPointer<vtkPolyData> model;
    if (this->Model) {
      model = vtkSmartPointer<vtkPolyData>::New();
      model->DeepCopy(this->Model);
    }
    Evaluation evaluation =
        Evaluated(model, this->Surface.get(), targetFromModel, this->HistogramBinWidthMm);
    this->History.push_back({this->TargetFromModel, this->Landmarks, this->Icp, this->Registered, this->Result});
    this->TargetFromModel = targetFromModel;
    this->Landmarks.reset();
    this->Icp.reset();
    this->Registered = true;
    this->Result = std::move(evaluation);
    this->Modified();
  });
}

bool vtkTissueMosaicRegistrationLogic::Undo() {
  if (this->History.empty()) return this->Fail("nothing to undo");
  RegistrationState state = std::move(this->History.back());
  this->History.pop_back();
  this->TargetFromModel = state.targetFromModel;
  this->Landmarks = std::move(state.landmarks);
  this->Icp = std::move(state.icp);
  this->Registered = state.registered;
  this->Result = std::move(state.result);
  this->LastErrorText.clear();
  this->Modified();
  return true;
}

// ---- jobs -------------------------------------------------------------------------------------------------------

std::shared_ptr<vtkTissueMosaicRegistrationLogic::Job> vtkTissueMosaicRegistrationLogic::NewJob() {
  auto job = std::make_shared<Job>();
  job->sourceModel = this->Model;
  if (this->Model) {
    // The live reconstruction grows in place on the owner thread: the step reads a copy of it.
    job->model = vtkSmartPointer<vtkPolyData>::New();
    job->model->DeepCopy(this->Model);
  }
  job->surface = this->Surface;
  job->start = this->TargetFromModel;
  job->histogramBinWidthMm = this->HistogramBinWidthMm;
  return job;
}

std::shared_ptr<vtkTissueMosaicRegistrationLogic::Job> vtkTissueMosaicRegistrationLogic::PrepareLandmarkRegistration(
    bool withScale) {
  std::shared_ptr<Job> job = this->NewJob();
  job->kind = Job::LandmarkStep;
  job->withScale = withScale;
  for (const LandmarkPair& pair : this->Pairs) {
    if (!pair.IsComplete()) continue;
    job->modelLandmarks.push_back(*pair.modelLps);
    job->targetLandmarks.push_back(*pair.targetLps);
  }
  return job;
}

std::shared_ptr<vtkTissueMosaicRegistrationLogic::Job> vtkTissueMosaicRegistrationLogic::PrepareIcp(
    const tissuemosaic::IcpParameters& parameters) {
  if (!this->Model || this->Model->GetNumberOfPoints() == 0) {
    this->Fail("ICP needs the reconstructed model: load or set it first");
    return nullptr;
  }
  if (!this->Surface) {
    this->Fail("ICP needs the CT/MR model: load it first");
    return nullptr;
  }
  std::shared_ptr<Job> job = this->NewJob();
  job->kind = Job::IcpStep;
  job->icpParameters = parameters;
  return job;
}

std::shared_ptr<vtkTissueMosaicRegistrationLogic::Job> vtkTissueMosaicRegistrationLogic::PrepareEvaluation() {
  if (!this->Model || this->Model->GetNumberOfPoints() == 0) {
    this->Fail("no reconstructed model to evaluate");
    return nullptr;
  }
  if (!this->Surface) {
    this->Fail("no CT/MR model to evaluate against");
    return nullptr;
  }
  std::shared_ptr<Job> job = this->NewJob();
  job->kind = Job::EvaluationStep;
  return job;
}

void vtkTissueMosaicRegistrationLogic::RunJob(Job& job) {
  try {
    job.transform = job.start;
    if (job.kind == Job::LandmarkStep) {
      job.landmarks = tissuemosaic::registerLandmarks(job.modelLandmarks, job.targetLandmarks, job.withScale);
      job.transform = job.landmarks->targetFromModel;
    } else if (job.kind == Job::IcpStep) {
      tissuemosaic::IcpParameters parameters = job.icpParameters;
      const auto outer = parameters.progress;
      parameters.progress = [&job, outer](int iterations) {
        job.iterations = iterations;
        return !job.cancelled && (!outer || outer(iterations));
      };
      job.icp = tissuemosaic::refineIcp(tissuemosaic::polyDataPoints(job.model), *job.surface, job.start, parameters);
      job.transform = job.icp->targetFromModel;
    }
    if (job.cancelled) throw tissuemosaic::Error("cancelled");
    job.evaluation = Evaluated(job.model, job.surface.get(), job.transform, job.histogramBinWidthMm);
    job.ran = true;
  } catch (const std::exception& error) {
    job.errorText = error.what();
  }
}

bool vtkTissueMosaicRegistrationLogic::FinishJob(Job& job) {
  if (!job.ran) return this->Fail(job.errorText.empty() ? "the registration step did not run" : job.errorText);
  if (job.sourceModel != this->Model || job.surface != this->Surface || job.start != this->TargetFromModel) {
    return this->Fail("the models or the transform changed while the step ran: nothing was changed");
  }
  if (job.kind != Job::EvaluationStep) {
    this->History.push_back({this->TargetFromModel, this->Landmarks, this->Icp, this->Registered, this->Result});
    this->TargetFromModel = job.transform;
    if (job.kind == Job::LandmarkStep) {
      this->Landmarks = std::move(job.landmarks);
      this->Icp.reset();
    } else {
      this->Icp = job.icp;  // the landmark result stays: the scale came from it
    }
    this->Registered = true;
  }
  this->Result = std::move(job.evaluation);
  this->LastErrorText.clear();
  this->Modified();
  return true;
}

int vtkTissueMosaicRegistrationLogic::GetJobProgress(const Job& job) { return job.iterations.load(); }

void vtkTissueMosaicRegistrationLogic::CancelJob(Job& job) { job.cancelled = true; }

bool vtkTissueMosaicRegistrationLogic::LoadTransform(const std::string& path) {
  Eigen::Matrix4d transform;
  if (!this->Run([&] { transform = tissuemosaic::readModelToTargetTransform(path); })) return false;
  return this->SetTargetFromModel(transform);
}

// ---- evaluation -------------------------------------------------------------------------------------------------

vtkTissueMosaicRegistrationLogic::Evaluation vtkTissueMosaicRegistrationLogic::Evaluated(
    vtkPolyData* model, const tissuemosaic::TargetSurface* surface, const Eigen::Matrix4d& targetFromModel,
    double histogramBinWidthMm) {
  Evaluation evaluation;
  if (!model || !surface || model->GetNumberOfPoints() == 0) return evaluation;
  evaluation.modelPoints = model->GetNumberOfPoints();
  evaluation.registeredPointsLps = tissuemosaic::transformedPoints(tissuemosaic::polyDataPoints(model), targetFromModel);
  evaluation.distancesMm =
      tissuemosaic::distancesToSurface(*surface, evaluation.registeredPointsLps, &evaluation.signedDistancesMm);
  evaluation.statistics = tissuemosaic::distanceStatistics(evaluation.distancesMm);
  evaluation.histogram = tissuemosaic::distanceHistogram(evaluation.distancesMm, histogramBinWidthMm);
  evaluation.registeredModel = tissuemosaic::transformedPolyData(model, targetFromModel);
  tissuemosaic::addDistanceArrays(evaluation.registeredModel, evaluation.distancesMm, evaluation.signedDistancesMm);
  return evaluation;
}

bool vtkTissueMosaicRegistrationLogic::Evaluate() {
  const std::shared_ptr<Job> job = this->PrepareEvaluation();
  if (!job) return false;
  RunJob(*job);
  return this->FinishJob(*job);
}

bool vtkTissueMosaicRegistrationLogic::SetHistogramBinWidthMm(double binWidthMm) {
  if (!(binWidthMm > 0) || !std::isfinite(binWidthMm)) return this->Fail("the histogram bin width must be > 0 mm");
  return this->Run([&] {
    if (this->HasEvaluation()) this->Result.histogram = tissuemosaic::distanceHistogram(this->Result.distancesMm, binWidthMm);
    this->HistogramBinWidthMm = binWidthMm;
    this->Modified();
  });
}

// ---- export -----------------------------------------------------------------------------------------------------

bool vtkTissueMosaicRegistrationLogic::WriteTransform(const std::string& path) {
  if (!this->Registered) {
    return this->Fail("nothing registered yet: register the landmarks (or load a transform) before exporting it");
  }
  return this->Run([&] { tissuemosaic::writeModelToTargetTransform(path, this->TargetFromModel); });
}

bool vtkTissueMosaicRegistrationLogic::WriteRegisteredModel(const std::string& path) {
  if (!this->HasEvaluation()) return this->Fail("nothing to export yet: register the model to the CT/MR model first");
  return this->Run([&] { tissuemosaic::writeSurfaceModel(path, this->Result.registeredModel, tissuemosaic::AnatomicalFrame::LPS); });
}

bool vtkTissueMosaicRegistrationLogic::WriteLandmarks(const std::string& path) {
  if (this->GetNumberOfCompleteLandmarkPairs() == 0) return this->Fail("no complete landmark pair to export");
  return this->Run([&] {
    tissuemosaic::LandmarkList model{"model landmarks", {}, tissuemosaic::AnatomicalFrame::LPS};
    tissuemosaic::LandmarkList target{"target landmarks", {}, tissuemosaic::AnatomicalFrame::LPS};
    for (const LandmarkPair& pair : this->Pairs) {
      if (!pair.IsComplete()) continue;
      model.points.push_back({pair.label, *pair.modelLps});
      target.points.push_back({pair.label, *pair.targetLps});
    }
    tissuemosaic::writeLandmarkFile(path, {model, target});
  });
}

bool vtkTissueMosaicRegistrationLogic::WriteDistanceCsv(const std::string& path) {
  if (!this->HasEvaluation()) return this->Fail("no distances yet: register the model to the CT/MR model first");
  return this->Run([&] {
    tissuemosaic::writeDistanceCsv(path, this->Result.registeredPointsLps, this->Result.distancesMm,
                                   this->Result.signedDistancesMm);
  });
}

bool vtkTissueMosaicRegistrationLogic::WriteHistogramPng(const std::string& path) {
  if (!this->HasEvaluation()) return this->Fail("no histogram yet: register the model to the CT/MR model first");
  return this->Run([&] { tissuemosaic::writeHistogramPng(path, this->Result.histogram, this->Result.statistics); });
}
