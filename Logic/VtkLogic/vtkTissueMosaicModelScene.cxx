#include "vtkTissueMosaicModelScene.h"

#include "vtkTissueMosaicPointCloud.h"

#include <vtkActor.h>
#include <vtkActorCollection.h>
#include <vtkType.h>
#include <vtkPointSet.h>
#include <vtkCellArray.h>
#include <vtkIdList.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkCamera.h>
#include <vtkObjectFactory.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkTissueMosaicModelScene);

namespace {

vtkSmartPointer<vtkActor> lineActor(double red, double green, double blue, double widthPx) {
  auto actor = vtkSmartPointer<vtkActor>::New();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->ScalarVisibilityOff();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(red, green, blue);
  actor->GetProperty()->SetLineWidth(static_cast<float>(widthPx));
  actor->GetProperty()->LightingOff();
  actor->VisibilityOff();  // until there is an input
  return actor;
}

void setInput(vtkActor* actor, vtkPolyData* polyData) {
  vtkPolyDataMapper::SafeDownCast(actor->GetMapper())->SetInputData(polyData);
  actor->SetVisibility(polyData != nullptr);
}

}  // namespace

vtkTissueMosaicModelScene::vtkTissueMosaicModelScene()
    : ModelActor(vtkSmartPointer<vtkActor>::New()),
      FullMapper(vtkSmartPointer<vtkPolyDataMapper>::New()),
      InteractiveMapper(vtkSmartPointer<vtkPolyDataMapper>::New()),
      InteractiveModel(vtkSmartPointer<vtkPolyData>::New()),
      // Key frames amber, the live camera green, the path light blue: distinct from tissue colours.
      KeyFrameFrustaActor(lineActor(1.0, 0.75, 0.1, 1.5)),
      CurrentFrustumActor(lineActor(0.2, 1.0, 0.3, 3.0)),
      TrajectoryActor(lineActor(0.35, 0.75, 1.0, 2.0)) {
  for (vtkPolyDataMapper* mapper : {this->FullMapper.Get(), this->InteractiveMapper.Get()}) {
    mapper->ScalarVisibilityOn();
    mapper->SetScalarModeToUsePointFieldData();
    mapper->SelectColorArray(tissuemosaic::kPointCloudColorArrayName);
    mapper->SetColorModeToDirectScalars();  // the RGB bytes are the tissue's colours, not values to map
  }
  this->InteractiveMapper->SetInputData(this->InteractiveModel);
  this->ModelActor->SetMapper(this->FullMapper);
  // The colours come from the video, lit by the scope: show them as they are.
  this->ModelActor->GetProperty()->LightingOff();
  this->ModelActor->GetProperty()->SetRepresentationToPoints();
  this->ModelActor->GetProperty()->SetPointSize(static_cast<float>(this->PointSizePx));
  this->ModelActor->VisibilityOff();
}

vtkTissueMosaicModelScene::~vtkTissueMosaicModelScene() = default;

void vtkTissueMosaicModelScene::PrintSelf(ostream& os, vtkIndent indent) {
  this->Superclass::PrintSelf(os, indent);
  os << indent << "PointSizePx: " << this->GetPointSizePx() << "\n";
}

void vtkTissueMosaicModelScene::SetModel(vtkPolyData* model) {
  this->FullMapper->SetInputData(model);
  this->ModelActor->SetVisibility(model != nullptr);
  this->InteractiveModelTime = 0;
  this->SetInteracting(this->Interacting);
}
void vtkTissueMosaicModelScene::SetKeyFrameFrusta(vtkPolyData* frusta) { setInput(this->KeyFrameFrustaActor, frusta); }
void vtkTissueMosaicModelScene::SetCurrentFrustum(vtkPolyData* frustum) {
  setInput(this->CurrentFrustumActor, frustum);
}
void vtkTissueMosaicModelScene::SetTrajectory(vtkPolyData* trajectory) {
  setInput(this->TrajectoryActor, trajectory);
}

void vtkTissueMosaicModelScene::AddToRenderer(vtkRenderer* renderer) {
  for (vtkActor* actor : {this->ModelActor.Get(), this->TrajectoryActor.Get(), this->KeyFrameFrustaActor.Get(),
                          this->CurrentFrustumActor.Get()}) {
    if (!renderer->HasViewProp(actor)) renderer->AddActor(actor);
  }
  // Dark blue-grey: tissue reds and the amber frusta stand out, as in surgical navigation displays.
  renderer->SetBackground(0.08, 0.09, 0.12);
  renderer->SetBackground2(0.22, 0.24, 0.30);
  renderer->GradientBackgroundOn();
}

void vtkTissueMosaicModelScene::SetPointSizePx(double sizePx) {
  this->PointSizePx = sizePx;
  this->SetInteracting(this->Interacting);
  this->Modified();
}

void vtkTissueMosaicModelScene::FitPointSizeToView(vtkRenderer* renderer) {
  auto* model = vtkPolyData::SafeDownCast(this->FullMapper->GetInput());
  const int* viewport = renderer->GetSize();
  if (!model || model->GetNumberOfPoints() == 0 || !viewport || viewport[0] <= 0 || viewport[1] <= 0) return;
  double bounds[6];
  model->GetBounds(bounds);
  double low[2] = {VTK_DOUBLE_MAX, VTK_DOUBLE_MAX}, high[2] = {-VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX};
  for (int corner = 0; corner < 8; ++corner) {
    renderer->SetWorldPoint(bounds[corner & 1], bounds[2 + ((corner >> 1) & 1)], bounds[4 + ((corner >> 2) & 1)], 1.0);
    renderer->WorldToDisplay();
    const double* display = renderer->GetDisplayPoint();
    for (int axis = 0; axis < 2; ++axis) {
      low[axis] = std::min(low[axis], std::clamp(display[axis], 0.0, double(viewport[axis])));
      high[axis] = std::max(high[axis], std::clamp(display[axis], 0.0, double(viewport[axis])));
    }
  }
  const double pixelsPerPoint = (high[0] - low[0]) * (high[1] - low[1]) / static_cast<double>(model->GetNumberOfPoints());
  this->SetPointSizePx(std::clamp(std::ceil(std::sqrt(std::max(pixelsPerPoint, 0.0))), 2.0, 8.0));
}

void vtkTissueMosaicModelScene::SetInteractivePointBudget(vtkIdType points) {
  this->InteractivePointBudget = std::max<vtkIdType>(points, 0);
  this->SetInteracting(this->Interacting);
}

void vtkTissueMosaicModelScene::SetInteracting(bool interacting) {
  this->Interacting = interacting;
  auto* model = vtkPolyData::SafeDownCast(this->FullMapper->GetInput());
  const bool reduce = interacting && model && this->InteractivePointBudget > 0 &&
                      model->GetNumberOfPoints() > this->InteractivePointBudget;
  double pointSize = this->PointSizePx;
  if (reduce) {
    vtkIdType step = 1;
    if (this->InteractiveModelTime != model->GetMTime()) {
      tissuemosaic::subsampleModel(model, this->InteractivePointBudget, this->InteractiveModel);
      this->InteractiveModelTime = model->GetMTime();
    }
    step = std::max<vtkIdType>(1, model->GetNumberOfPoints() / std::max<vtkIdType>(1, this->InteractiveModel->GetNumberOfPoints()));
    // A subsample of every k-th point leaves gaps of about sqrt(k) points: bigger points keep the surface closed
    // (at most twice as big: every pixel of a point costs fragment work).
    pointSize *= std::min(std::sqrt(static_cast<double>(step)), 2.0);
    this->ModelActor->SetMapper(this->InteractiveMapper);
  } else {
    this->ModelActor->SetMapper(this->FullMapper);
  }
  this->ModelActor->GetProperty()->SetPointSize(static_cast<float>(pointSize));
}

vtkIdType vtkTissueMosaicModelScene::GetDrawnModelPoints() {
  auto* drawn = vtkPolyData::SafeDownCast(vtkPolyDataMapper::SafeDownCast(this->ModelActor->GetMapper())->GetInput());
  return drawn ? drawn->GetNumberOfVerts() : 0;
}

namespace tissuemosaic {

vtkIdType subsampleModel(vtkPolyData* model, vtkIdType maxPoints, vtkPolyData* subsample) {
  const vtkIdType n = model->GetNumberOfPoints();
  const vtkIdType step = std::max<vtkIdType>(1, (n + std::max<vtkIdType>(maxPoints, 1) - 1) / std::max<vtkIdType>(maxPoints, 1));
  vtkNew<vtkIdList> kept;
  kept->Allocate(n / step + 1);
  for (vtkIdType i = 0; i < n; i += step) kept->InsertNextId(i);
  vtkNew<vtkPoints> points;
  points->SetDataType(model->GetPoints() ? model->GetPoints()->GetDataType() : VTK_FLOAT);
  if (model->GetPoints()) model->GetPoints()->GetPoints(kept, points);
  subsample->Initialize();
  subsample->SetPoints(points);
  subsample->GetPointData()->CopyAllocate(model->GetPointData(), kept->GetNumberOfIds());
  vtkNew<vtkIdList> targets;
  targets->SetNumberOfIds(kept->GetNumberOfIds());
  for (vtkIdType i = 0; i < kept->GetNumberOfIds(); ++i) targets->SetId(i, i);
  subsample->GetPointData()->CopyData(model->GetPointData(), kept, targets);
  vtkNew<vtkCellArray> vertices;
  vertices->AllocateExact(kept->GetNumberOfIds(), kept->GetNumberOfIds());
  for (vtkIdType i = 0; i < kept->GetNumberOfIds(); ++i) vertices->InsertNextCell(1, &i);
  subsample->SetVerts(vertices);
  return step;
}

}  // namespace tissuemosaic

void vtkTissueMosaicModelScene::ResetScopeView(vtkRenderer* renderer, vtkActor* fitTo) {
  vtkCamera* camera = renderer->GetActiveCamera();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(0, 0, -1);  // behind the scope, looking along +z
  camera->SetViewUp(0, -1, 0);    // image rows grow downward (+y): -y is up on screen
  auto* fitData = fitTo && fitTo->GetVisibility() && fitTo->GetMapper()
                            ? vtkPointSet::SafeDownCast(fitTo->GetMapper()->GetInputAsDataSet())
                            : nullptr;
  const bool fitToActor = fitData && fitData->GetNumberOfPoints() > 0;
  if (fitToActor) renderer->ResetCamera(fitTo->GetBounds());  // keeps the direction
  else renderer->ResetCamera();   // keeps the direction, fits the bounding sphere of the visible props
  // The sphere leaves much empty space: centre what is drawn and zoom until it fills 90 % of the view (judged from
  // up to a few thousand points of each visible actor, so that this stays cheap for models of millions of points).
  renderer->ResetCameraClippingRange();
  double low[2] = {VTK_DOUBLE_MAX, VTK_DOUBLE_MAX}, high[2] = {-VTK_DOUBLE_MAX, -VTK_DOUBLE_MAX};
  vtkActorCollection* actors = renderer->GetActors();
  vtkCollectionSimpleIterator it;
  actors->InitTraversal(it);
  while (vtkActor* actor = actors->GetNextActor(it)) {
    if (fitToActor && actor != fitTo) continue;
    auto* data = actor->GetVisibility() && actor->GetMapper()
                     ? vtkPointSet::SafeDownCast(actor->GetMapper()->GetInputAsDataSet())
                     : nullptr;
    if (!data || data->GetNumberOfPoints() == 0) continue;
    const vtkIdType step = std::max<vtkIdType>(1, data->GetNumberOfPoints() / 4000);
    for (vtkIdType i = 0; i < data->GetNumberOfPoints(); i += step) {
      double p[3];
      data->GetPoint(i, p);
      renderer->WorldToView(p[0], p[1], p[2]);
      for (int axis = 0; axis < 2; ++axis) {
        low[axis] = std::min(low[axis], p[axis]);
        high[axis] = std::max(high[axis], p[axis]);
      }
    }
  }
  if (low[0] < high[0] && low[1] < high[1]) {
    // Move the camera sideways so that the drawn extent's centre is the view's centre.
    double focal[3], position[3];
    camera->GetFocalPoint(focal);
    camera->GetPosition(position);
    double view[3] = {focal[0], focal[1], focal[2]};
    renderer->WorldToView(view[0], view[1], view[2]);
    double target[3] = {view[0] + 0.5 * (low[0] + high[0]), view[1] + 0.5 * (low[1] + high[1]), view[2]};
    renderer->ViewToWorld(target[0], target[1], target[2]);
    for (int k = 0; k < 3; ++k) {
      const double shift = target[k] - focal[k];
      focal[k] += shift;
      position[k] += shift;
    }
    camera->SetFocalPoint(focal);
    camera->SetPosition(position);
    camera->Zoom(0.9 / std::max(0.5 * (high[0] - low[0]), 0.5 * (high[1] - low[1])));
  }
  renderer->ResetCameraClippingRange();
}
