#include "qTissueMosaicRegistrationView.h"

#include "qTissueMosaicViewLegends.h"
#include "vtkTissueMosaicDistanceReport.h"
#include "vtkTissueMosaicPointPick.h"
#include "vtkTissueMosaicRegistrationLogic.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkCellPicker.h>
#include <vtkDataArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGlyph3DMapper.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLabeledDataMapper.h>
#include <vtkLookupTable.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkVertexGlyphFilter.h>

#include <QTimer>
#include <QVBoxLayout>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <memory>

namespace {

/// How far from the cursor a click still picks a scan point: a fraction of the view's diagonal (5.7 px at 900x700).
constexpr double kPickRadiusOfDiagonal = 0.005;

/// The usual trackball camera, plus: a left click that does not drag calls `Click` (picking). A style rather than
/// an interactor observer, because the style grabs the mouse focus on a press and then receives the release alone.
class ClickPickingStyle : public vtkInteractorStyleTrackballCamera {
public:
  static ClickPickingStyle* New();
  vtkTypeMacro(ClickPickingStyle, vtkInteractorStyleTrackballCamera);

  std::function<void(int displayX, int displayY)> Click;

  void OnLeftButtonDown() override {
    this->Interactor->GetEventPosition(this->PressPosition);
    this->Pressed = true;
    this->Superclass::OnLeftButtonDown();
  }
  void OnLeftButtonUp() override {
    this->Superclass::OnLeftButtonUp();
    int position[2];
    this->Interactor->GetEventPosition(position);
    // A click picks; a drag (it turned the camera) does not.
    const bool click = this->Pressed && std::abs(position[0] - this->PressPosition[0]) <= 3 &&
                       std::abs(position[1] - this->PressPosition[1]) <= 3;
    this->Pressed = false;
    if (click && this->Click) this->Click(position[0], position[1]);
  }

private:
  int PressPosition[2] = {0, 0};
  bool Pressed = false;
};
vtkStandardNewMacro(ClickPickingStyle);

void setMatrix(vtkMatrix4x4* matrix, const Eigen::Matrix4d& transform) {
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 4; ++column) matrix->SetElement(row, column, transform(row, column));
  }
}

Eigen::Vector3d mapped(const Eigen::Matrix4d& transform, const Eigen::Vector3d& point) {
  return transform.topLeftCorner<3, 3>() * point + transform.topRightCorner<3, 1>();
}

/// Point scalars the renderer uses as colours as they are: 8-bit RGB(A) (our reconstructions' "RGB").
bool hasDirectColours(vtkPolyData* polyData) {
  vtkDataArray* scalars = polyData ? polyData->GetPointData()->GetScalars() : nullptr;
  return scalars && vtkUnsignedCharArray::SafeDownCast(scalars) &&
         (scalars->GetNumberOfComponents() == 3 || scalars->GetNumberOfComponents() == 4);
}

/// Draws `polyData` with `mapper`, through vertex glyphs when it has no cells (same point order, so picked ids
/// are the polydata's).
void connectPoints(vtkPolyData* polyData, vtkVertexGlyphFilter* vertices, vtkPolyDataMapper* mapper) {
  if (polyData->GetNumberOfCells() == 0) {
    vertices->SetInputData(polyData);
    mapper->SetInputConnection(vertices->GetOutputPort());
  } else {
    mapper->SetInputData(polyData);
  }
}

}  // namespace

class qTissueMosaicRegistrationView::Private {
public:
  explicit Private(vtkTissueMosaicRegistrationLogic* logic) : Logic(logic) {}

  void setupScene();
  void updateModelPipeline();
  void updateTargetPipeline();
  void updateDistanceColours();
  /// Frames everything shown, looking as the scope looked at the model (its +z, -y up) moved into the CT/MR frame
  /// by the current transform: the surgeon's view of the scan, not VTK's default from the far side.
  void fitCamera();
  /// The index of the pair that got the picked point, or -1 with the reason.
  int pickModel(int x, int y, QString& reason);
  int pickTarget(int x, int y, QString& reason);

  vtkSmartPointer<vtkTissueMosaicRegistrationLogic> Logic;
  QVTKOpenGLNativeWidget* Widget = nullptr;
  vtkNew<vtkGenericOpenGLRenderWindow> RenderWindow;
  vtkNew<vtkRenderer> Renderer;
  std::unique_ptr<qTissueMosaicViewLegends> Legends;
  vtkNew<vtkMatrix4x4> ModelToTarget;
  vtkNew<vtkVertexGlyphFilter> ModelVertices;
  vtkNew<vtkPolyDataMapper> ModelMapper;
  vtkNew<vtkActor> ModelActor;
  vtkNew<vtkPolyDataMapper> TargetMapper;
  vtkNew<vtkActor> TargetActor;
  vtkNew<vtkLookupTable> DistanceColours;
  vtkNew<vtkVertexGlyphFilter> DistanceVertices;
  vtkNew<vtkPolyDataMapper> DistanceMapper;
  vtkNew<vtkActor> DistanceActor;
  vtkNew<vtkScalarBarActor> ScalarBar;
  vtkNew<vtkSphereSource> Sphere;
  vtkNew<vtkPolyData> ModelLandmarkPoints;   ///< model frame
  vtkNew<vtkPolyData> TargetLandmarkPoints;  ///< CT/MR frame
  vtkNew<vtkGlyph3DMapper> ModelLandmarkMapper;
  vtkNew<vtkGlyph3DMapper> TargetLandmarkMapper;
  vtkNew<vtkActor> ModelLandmarkActor;
  vtkNew<vtkActor> TargetLandmarkActor;
  vtkNew<vtkPolyData> LabelPoints;
  vtkNew<vtkLabeledDataMapper> LabelMapper;
  vtkNew<vtkActor2D> LabelActor;
  vtkNew<vtkCellPicker> CellPicker;
  vtkNew<ClickPickingStyle> InteractorStyle;
  PickMode Mode = PickNone;
  bool ColourByDistance = true;
  bool CameraFitted = false;  ///< the camera was fitted to a scene with something in it
};

void qTissueMosaicRegistrationView::Private::setupScene() {
  this->RenderWindow->AddRenderer(this->Renderer);
  this->RenderWindow->SetMultiSamples(0);  // software OpenGL pays for every sample (see qTissueMosaicModelView)
  // The reconstruction view's background: tissue colours and the CT/MR surface stand out.
  this->Renderer->SetBackground(0.08, 0.09, 0.12);
  this->Renderer->SetBackground2(0.22, 0.24, 0.30);
  this->Renderer->GradientBackgroundOn();

  this->ModelMapper->SetInputConnection(this->ModelVertices->GetOutputPort());
  this->ModelActor->SetMapper(this->ModelMapper);
  this->ModelActor->SetUserMatrix(this->ModelToTarget);
  this->ModelActor->GetProperty()->SetPointSize(2);
  this->ModelActor->GetProperty()->SetColor(0.95, 0.6, 0.45);
  this->ModelActor->VisibilityOff();

  this->TargetActor->SetMapper(this->TargetMapper);
  this->TargetActor->GetProperty()->SetColor(0.9, 0.86, 0.75);
  this->TargetActor->GetProperty()->SetOpacity(0.5);
  this->TargetMapper->ScalarVisibilityOff();
  this->TargetActor->VisibilityOff();

  // Blue (on the surface) to red (far from it).
  this->DistanceColours->SetHueRange(0.667, 0.0);
  this->DistanceColours->Build();
  this->DistanceMapper->SetLookupTable(this->DistanceColours);
  this->DistanceMapper->UseLookupTableScalarRangeOn();
  this->DistanceMapper->SetScalarModeToUsePointFieldData();
  this->DistanceMapper->SelectColorArray(tissuemosaic::kDistanceArrayName);
  this->DistanceMapper->ScalarVisibilityOn();
  this->DistanceActor->SetMapper(this->DistanceMapper);
  this->DistanceActor->GetProperty()->SetPointSize(2);
  this->DistanceActor->GetProperty()->LightingOff();  // the colour is the distance: no shading over it
  this->DistanceActor->VisibilityOff();
  this->ScalarBar->SetLookupTable(this->DistanceColours);
  this->ScalarBar->SetTitle("distance (mm)");
  this->ScalarBar->SetNumberOfLabels(5);
  this->ScalarBar->SetPosition(0.88, 0.1);
  this->ScalarBar->SetWidth(0.1);
  this->ScalarBar->SetHeight(0.8);
  this->ScalarBar->SetMaximumWidthInPixels(90);
  this->ScalarBar->UnconstrainedFontSizeOn();
  this->ScalarBar->GetTitleTextProperty()->SetFontSize(14);
  this->ScalarBar->GetLabelTextProperty()->SetFontSize(12);
  this->ScalarBar->VisibilityOff();

  this->Sphere->SetRadius(1.0);
  this->Sphere->SetThetaResolution(16);
  this->Sphere->SetPhiResolution(16);
  for (auto [mapper, points] : {std::pair{this->ModelLandmarkMapper.Get(), this->ModelLandmarkPoints.Get()},
                                std::pair{this->TargetLandmarkMapper.Get(), this->TargetLandmarkPoints.Get()}}) {
    points->SetPoints(vtkNew<vtkPoints>());
    mapper->SetInputData(points);
    mapper->SetSourceConnection(this->Sphere->GetOutputPort());
    mapper->ScalingOff();
    mapper->ScalarVisibilityOff();
  }
  this->ModelLandmarkActor->SetMapper(this->ModelLandmarkMapper);
  this->ModelLandmarkActor->SetUserMatrix(this->ModelToTarget);
  this->ModelLandmarkActor->GetProperty()->SetColor(1.0, 0.85, 0.1);
  this->ModelLandmarkActor->PickableOff();
  this->TargetLandmarkActor->SetMapper(this->TargetLandmarkMapper);
  this->TargetLandmarkActor->GetProperty()->SetColor(0.2, 0.9, 0.3);
  this->TargetLandmarkActor->PickableOff();

  this->LabelPoints->SetPoints(vtkNew<vtkPoints>());
  this->LabelMapper->SetInputData(this->LabelPoints);
  this->LabelMapper->SetLabelModeToLabelFieldData();
  this->LabelMapper->SetFieldDataName("label");
  this->LabelMapper->GetLabelTextProperty()->SetFontSize(14);
  this->LabelMapper->GetLabelTextProperty()->SetColor(1, 1, 1);
  this->LabelActor->SetMapper(this->LabelMapper);
  this->LabelActor->PickableOff();

  for (vtkActor* actor : {this->ModelActor.Get(), this->TargetActor.Get(), this->DistanceActor.Get(),
                          this->ModelLandmarkActor.Get(), this->TargetLandmarkActor.Get()}) {
    this->Renderer->AddActor(actor);
  }
  this->Renderer->AddActor2D(this->ScalarBar);
  this->Renderer->AddActor2D(this->LabelActor);

  if (vtkRenderWindowInteractor* interactor = this->RenderWindow->GetInteractor()) {
    interactor->SetInteractorStyle(this->InteractorStyle);
  }
  this->Legends = std::make_unique<qTissueMosaicViewLegends>(this->Renderer, this->RenderWindow->GetInteractor());
}

void qTissueMosaicRegistrationView::Private::fitCamera() {
  const Eigen::Matrix3d rotation = this->Logic->GetTargetFromModel().topLeftCorner<3, 3>();
  const Eigen::Vector3d forward = (rotation * Eigen::Vector3d::UnitZ()).normalized();
  const Eigen::Vector3d up = (rotation * -Eigen::Vector3d::UnitY()).normalized();
  vtkCamera* camera = this->Renderer->GetActiveCamera();
  camera->SetFocalPoint(0, 0, 0);
  camera->SetPosition(-forward.x(), -forward.y(), -forward.z());
  camera->SetViewUp(up.x(), up.y(), up.z());
  this->Renderer->ResetCamera();  // keeps the direction
}

void qTissueMosaicRegistrationView::Private::updateModelPipeline() {
  vtkPolyData* model = this->Logic->GetModel();
  if (!model) {
    this->ModelActor->VisibilityOff();
    return;
  }
  connectPoints(model, this->ModelVertices, this->ModelMapper);
  // Our reconstructions' 8-bit "RGB" colours are drawn as they are (also when a live model gets them later);
  // other scalars (e.g. a distance map read back) would be mapped through a meaningless range: solid colour.
  // A live scan without points has no colours yet: colour by scalars from the start, so that they show as it grows.
  vtkDataArray* scalars = model->GetPointData()->GetScalars();
  this->ModelMapper->SetScalarVisibility(!scalars || hasDirectColours(model));
  this->ModelMapper->SetColorModeToDirectScalars();
  // A scanned point cloud carries the scope's lighting in its colours: drawn unlit, as the reconstruction view
  // does (lit, the points whose normals face away from the light came out black). Surfaces are shaded.
  this->ModelActor->GetProperty()->SetLighting(model->GetNumberOfPolys() > 0);
}

void qTissueMosaicRegistrationView::Private::updateTargetPipeline() {
  vtkPolyData* target = this->Logic->GetTarget();
  this->TargetActor->SetVisibility(target != nullptr);
  if (target) this->TargetMapper->SetInputData(target);
}

void qTissueMosaicRegistrationView::Private::updateDistanceColours() {
  vtkPolyData* registered = this->Logic->GetRegisteredModel();
  const bool show = registered && this->ColourByDistance;
  if (registered) {
    connectPoints(registered, this->DistanceVertices, this->DistanceMapper);
    // Up to the 95th percentile: the few far points (tissue the CT/MR model lacks) would wash out the rest;
    // everything beyond shows in the top colour.
    const tissuemosaic::DistanceStatistics& statistics = this->Logic->GetDistanceStatistics();
    const double top = statistics.p95Mm > 0 ? statistics.p95Mm : std::max(statistics.maxMm, 1e-3);
    this->DistanceColours->SetTableRange(0, top);
    this->DistanceActor->GetProperty()->SetLighting(registered->GetNumberOfPolys() > 0);
  }
  this->DistanceActor->SetVisibility(show);
  this->ScalarBar->SetVisibility(show);
  this->ModelActor->SetVisibility(this->Logic->GetModel() != nullptr && !show);
}

int qTissueMosaicRegistrationView::Private::pickModel(int x, int y, QString& reason) {
  vtkPolyData* model = this->Logic->GetModel();
  if (!model || model->GetNumberOfPoints() == 0) {
    reason = QObject::tr("There is no model to pick on yet: scan or load one first.");
    return -1;
  }
  const QString missed = QObject::tr("No model point under the cursor: click on the model.");
  const Eigen::Matrix4d targetFromModel = this->Logic->GetTargetFromModel();
  if (model->GetNumberOfPolys() > 0) {
    // A surface: the point where the ray meets it, taken back into the model's frame.
    this->CellPicker->InitializePickList();
    this->CellPicker->PickFromListOn();
    this->CellPicker->AddPickList(this->ModelActor);
    this->CellPicker->AddPickList(this->DistanceActor);
    if (!this->CellPicker->Pick(x, y, 0, this->Renderer) || this->CellPicker->GetCellId() < 0) {
      reason = missed;
      return -1;
    }
    const double* world = this->CellPicker->GetPickPosition();
    const Eigen::Vector3d modelPoint = mapped(targetFromModel.inverse(), Eigen::Vector3d(world[0], world[1], world[2]));
    return this->Logic->AddModelLandmark(modelPoint);
  }
  // A point cloud: the scan point drawn under the cursor, in whichever actor shows the model (ids are the model's:
  // both keep its point order). Not vtkPointPicker: its threaded search made the same click pick different points.
  const bool byDistance = this->DistanceActor->GetVisibility();
  vtkActor* shown = byDistance ? this->DistanceActor.Get() : this->ModelActor.Get();
  vtkPolyData* drawn = byDistance ? this->Logic->GetRegisteredModel() : model;
  const int* sizePx = this->Renderer->GetSize();
  const double radiusPx = kPickRadiusOfDiagonal * std::hypot(sizePx[0], sizePx[1]);
  const vtkIdType id = drawn ? tissuemosaic::pickDrawnPoint(this->Renderer, shown, drawn->GetPoints(), x, y,
                                                            shown->GetProperty()->GetPointSize(), radiusPx)
                             : -1;
  if (id < 0 || id >= model->GetNumberOfPoints()) {
    reason = missed;
    return -1;
  }
  double point[3];
  model->GetPoint(id, point);
  return this->Logic->AddModelLandmark(Eigen::Vector3d(point[0], point[1], point[2]));
}

int qTissueMosaicRegistrationView::Private::pickTarget(int x, int y, QString& reason) {
  if (!this->Logic->GetTarget()) {
    reason = QObject::tr("There is no CT/MR model to pick on yet: load one first.");
    return -1;
  }
  this->CellPicker->InitializePickList();
  this->CellPicker->PickFromListOn();
  this->CellPicker->AddPickList(this->TargetActor);
  if (!this->CellPicker->Pick(x, y, 0, this->Renderer) || this->CellPicker->GetCellId() < 0) {
    reason = QObject::tr("No CT/MR surface under the cursor: click on the surface. Nothing was added.");
    return -1;
  }
  const double* world = this->CellPicker->GetPickPosition();
  return this->Logic->AddTargetLandmark(Eigen::Vector3d(world[0], world[1], world[2]));
}

// ---- public -----------------------------------------------------------------------------------------------------

qTissueMosaicRegistrationView::qTissueMosaicRegistrationView(vtkTissueMosaicRegistrationLogic* logic, QWidget* parent)
    : QWidget(parent), d(new Private(logic)) {
  d->Widget = new QVTKOpenGLNativeWidget(this);
  d->Widget->setObjectName("registrationVtkWidget");
  d->Widget->setRenderWindow(d->RenderWindow);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(d->Widget);
  this->setMinimumSize(200, 150);
  d->setupScene();
  d->InteractorStyle->Click = [this](int x, int y) {
    if (d->Mode != PickNone) this->pickAt(x, y);
  };
  this->updateFromLogic();
}

qTissueMosaicRegistrationView::~qTissueMosaicRegistrationView() { delete d; }

void qTissueMosaicRegistrationView::setPickMode(PickMode mode) {
  d->Mode = mode;
  d->Widget->setCursor(mode == PickNone ? Qt::ArrowCursor : Qt::CrossCursor);
}

qTissueMosaicRegistrationView::PickMode qTissueMosaicRegistrationView::pickMode() const { return d->Mode; }

bool qTissueMosaicRegistrationView::pickAt(int displayX, int displayY) {
  QString reason;
  int pair = -1;
  if (d->Mode == PickOnModel) pair = d->pickModel(displayX, displayY, reason);
  else if (d->Mode == PickOnTarget) pair = d->pickTarget(displayX, displayY, reason);
  else reason = tr("Choose \"Pick on model\" or \"Pick on CT/MR\" first.");
  if (pair < 0) {
    if (reason.isEmpty()) reason = QString::fromStdString(d->Logic->GetLastErrorText());
    emit pickMissed(reason);
    return false;
  }
  this->updateLandmarks();
  emit landmarkPicked(pair);
  return true;
}

void qTissueMosaicRegistrationView::setColourByDistance(bool enabled) {
  d->ColourByDistance = enabled;
  d->updateDistanceColours();
  this->render();
}

bool qTissueMosaicRegistrationView::colourByDistance() const { return d->ColourByDistance; }

QVTKOpenGLNativeWidget* qTissueMosaicRegistrationView::vtkWidget() const { return d->Widget; }
vtkRenderer* qTissueMosaicRegistrationView::renderer() const { return d->Renderer; }
vtkScalarBarActor* qTissueMosaicRegistrationView::scalarBar() const { return d->ScalarBar; }
vtkActor* qTissueMosaicRegistrationView::modelActor() const { return d->ModelActor; }
vtkActor* qTissueMosaicRegistrationView::distanceActor() const { return d->DistanceActor; }
vtkActor* qTissueMosaicRegistrationView::targetActor() const { return d->TargetActor; }

void qTissueMosaicRegistrationView::updateFromLogic() {
  d->updateModelPipeline();
  d->updateTargetPipeline();
  setMatrix(d->ModelToTarget, d->Logic->GetTargetFromModel());
  d->updateDistanceColours();
  this->updateLandmarks();  // renders
}

void qTissueMosaicRegistrationView::updateLandmarks() {
  // Glyph size: 1% of the CT/MR model (else the model), visible without hiding the surface.
  vtkPolyData* scene = d->Logic->GetTarget() ? d->Logic->GetTarget() : d->Logic->GetModel();
  const double diagonal = scene && scene->GetNumberOfPoints() > 0 ? scene->GetLength() : 100.0;
  d->Sphere->SetRadius(std::max(0.1, 0.01 * diagonal));

  vtkNew<vtkPoints> modelPoints, targetPoints, labelPoints;
  vtkNew<vtkStringArray> labels;
  labels->SetName("label");
  const Eigen::Matrix4d& transform = d->Logic->GetTargetFromModel();
  for (int i = 0; i < d->Logic->GetNumberOfLandmarkPairs(); ++i) {
    const auto& pair = d->Logic->GetLandmarkPair(i);
    if (pair.modelLps) modelPoints->InsertNextPoint(pair.modelLps->data());
    if (pair.targetLps) targetPoints->InsertNextPoint(pair.targetLps->data());
    const Eigen::Vector3d at = pair.targetLps ? *pair.targetLps : mapped(transform, *pair.modelLps);
    labelPoints->InsertNextPoint(at.data());
    labels->InsertNextValue(pair.label);
  }
  d->ModelLandmarkPoints->SetPoints(modelPoints);
  d->TargetLandmarkPoints->SetPoints(targetPoints);
  d->LabelPoints->SetPoints(labelPoints);
  d->LabelPoints->GetPointData()->Initialize();
  d->LabelPoints->GetPointData()->AddArray(labels);
  this->render();
}

void qTissueMosaicRegistrationView::resetCamera() {
  d->fitCamera();
  // Fitted to nothing (the live scan had no points yet): fit again once there is something (render()).
  vtkPolyData* model = d->Logic->GetModel();
  d->CameraFitted = (model && model->GetNumberOfPoints() > 0) || d->Logic->GetTarget();
  this->updateLandmarks();  // glyph size follows the scene; renders
}

void qTissueMosaicRegistrationView::render() {
  // Before the view is shown it has no OpenGL context; it renders when it is shown (showEvent).
  if (!this->isVisible()) return;
  // A scene that was empty when last fitted (the live scan had not started) is framed once it has content.
  vtkPolyData* model = d->Logic->GetModel();
  const bool content = (model && model->GetNumberOfPoints() > 0) || d->Logic->GetTarget();
  if (!content) d->CameraFitted = false;
  else if (!d->CameraFitted) {
    d->fitCamera();
    d->CameraFitted = true;
  }
  d->RenderWindow->Render();
}

void qTissueMosaicRegistrationView::showEvent(QShowEvent* event) {
  QWidget::showEvent(event);
  // What changed while the view was hidden: drawn once it is on screen.
  QTimer::singleShot(0, this, [this] { this->render(); });
}
