#include "qTissueMosaicModelView.h"

#include "qTissueMosaicViewLegends.h"
#include "vtkTissueMosaicModelScene.h"
#include "vtkTissueMosaicPointCloud.h"
#include "vtkTissueMosaicReconstructionLogic.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkCallbackCommand.h>
#include <vtkUnsignedCharArray.h>
#include <vtkPoints.h>
#include <vtkPointData.h>
#include <vtkFloatArray.h>
#include <vtkCellArray.h>
#include <vtkCamera.h>
#include <vtkInteractorObserver.h>
#include <vtkInteractorStyle.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkOrientationMarkerWidget.h>
#include <vtkPNGWriter.h>
#include <vtkPolyData.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkWindowToImageFilter.h>

#include <QCoreApplication>
#include <QElapsedTimer>
#include <QTimer>
#include <QVBoxLayout>

#include <algorithm>
#include <memory>

class qTissueMosaicModelView::Private {
public:
  QVTKOpenGLNativeWidget* widget = nullptr;
  vtkNew<vtkGenericOpenGLRenderWindow> window;
  vtkNew<vtkRenderer> renderer;
  vtkNew<vtkTissueMosaicModelScene> scene;
  vtkSmartPointer<vtkPolyData> model;
  vtkSmartPointer<vtkPolyData> keyFrameFrusta, currentFrustum, trajectory;
  bool warmedUp = false;  ///< the scene's shaders are compiled
  bool renderPending = false;
  QElapsedTimer sinceRender;  ///< since the last render ended
  qint64 lastRenderMs = 0;
  QElapsedTimer sinceRenderRequest;  ///< since requestRender() scheduled the pending render
  qint64 renderWaitMs = 0;           ///< the pending render's timer interval
  unsigned renderRequest = 0;        ///< numbers the requests: a timer of an earlier one (rendered since) does nothing
  bool userMovedCamera = false;  ///< until the user turns the view, it follows the growing model
  double interactiveFrameTimeMs = 25;
  double msPerPoint = 0;    ///< of the last full render of a large model
  bool live = false;        ///< a scan is running: reduce renders that would be slow
  vtkNew<vtkCallbackCommand> interaction;
  std::unique_ptr<qTissueMosaicViewLegends> legends;  ///< axes and scale bar

  /// The smallest level of detail; also what is drawn while the speed of this view is still unknown.
  static constexpr vtkIdType kSmallestSubsample = 20000;
  /// A render timer that fires this late found the event loop busy with something else that long (most often the
  /// window's composition, 25-50 ms on software OpenGL). Rendering straight after it would make one stall of both.
  static constexpr qint64 kLateRenderMs = 8;

  /// The level-of-detail budget for the next reduced render, from the speed of the last render of a large
  /// model (0: every point). Until that speed is known, the smallest subsample: a first live render of a large
  /// model must not stall the interface to find out.
  void updateBudget() {
    vtkIdType budget = 0;
    if (interactiveFrameTimeMs > 0) {
      budget = msPerPoint > 0
                   ? std::max(kSmallestSubsample, static_cast<vtkIdType>(interactiveFrameTimeMs / msPerPoint))
                   : kSmallestSubsample;
    }
    scene->SetInteractivePointBudget(budget);
  }
  /// Draws a three-point model and a line through the scene's actors once, so that OpenGL compiles their shaders
  /// now, before any scan: the first frame with a model had taken 50 ms of this thread and 400 ms of software
  /// OpenGL (llvmpipe compiles shaders), a stall in the middle of the scan.
  void warmUp() {
    warmedUp = true;
    vtkNew<vtkPoints> points;
    points->SetDataTypeToFloat();
    vtkNew<vtkCellArray> vertices, lines;
    for (vtkIdType i = 0; i < 3; ++i) {
      points->InsertNextPoint(double(i), 0.0, 100.0);
      vertices->InsertNextCell(1, &i);
    }
    const vtkIdType line[2] = {0, 1};
    lines->InsertNextCell(2, line);
    vtkNew<vtkUnsignedCharArray> colours;
    colours->SetName(tissuemosaic::kPointCloudColorArrayName);
    colours->SetNumberOfComponents(3);
    vtkNew<vtkFloatArray> normals;
    normals->SetName("Normals");
    normals->SetNumberOfComponents(3);
    for (int i = 0; i < 3; ++i) {
      colours->InsertNextTuple3(200, 100, 90);
      normals->InsertNextTuple3(0, 0, -1);
    }
    vtkNew<vtkPolyData> dummyModel, dummyLines;
    dummyModel->SetPoints(points);
    dummyModel->SetVerts(vertices);
    dummyModel->GetPointData()->SetScalars(colours);
    dummyModel->GetPointData()->SetNormals(normals);
    dummyLines->SetPoints(points);
    dummyLines->SetLines(lines);
    scene->SetModel(dummyModel);
    scene->SetKeyFrameFrusta(dummyLines);
    scene->SetCurrentFrustum(dummyLines);
    scene->SetTrajectory(dummyLines);
    window->Render();
    scene->SetModel(model);
    scene->SetKeyFrameFrusta(keyFrameFrusta);
    scene->SetCurrentFrustum(currentFrustum);
    scene->SetTrajectory(trajectory);
  }
  static void onInteraction(vtkObject*, unsigned long event, void* clientData, void*) {
    auto* self = static_cast<Private*>(clientData);
    if (event == vtkCommand::StartInteractionEvent) {
      self->userMovedCamera = true;
      self->updateBudget();
      self->scene->SetInteracting(true);
    } else {
      self->scene->SetInteracting(false);
      self->widget->renderWindow()->Render();  // the full model again when the user lets go
    }
  }
};

qTissueMosaicModelView::qTissueMosaicModelView(QWidget* parent) : QWidget(parent), d(new Private) {
  d->widget = new QVTKOpenGLNativeWidget(this);
  d->widget->setObjectName("modelVtkWidget");
  d->widget->setRenderWindow(d->window);
  d->window->AddRenderer(d->renderer);
  // Multisampling multiplies the per-pixel work of software OpenGL (8 samples: an empty frame took 80 ms instead of
  // 8 on llvmpipe) for edges that points barely have; the offscreen snapshot draws without it too.
  d->window->SetMultiSamples(0);
  d->scene->AddToRenderer(d->renderer);
  vtkTissueMosaicModelScene::ResetScopeView(d->renderer, d->scene->GetModelActor());
  d->interaction->SetClientData(d);
  d->interaction->SetCallback(&Private::onInteraction);
  if (vtkInteractorObserver* style = d->widget->interactor()->GetInteractorStyle()) {
    style->AddObserver(vtkCommand::StartInteractionEvent, d->interaction);
    style->AddObserver(vtkCommand::EndInteractionEvent, d->interaction);
  }
  d->legends = std::make_unique<qTissueMosaicViewLegends>(d->renderer, d->widget->interactor());
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(d->widget);
  this->setMinimumSize(200, 150);
}

qTissueMosaicModelView::~qTissueMosaicModelView() { delete d; }

void qTissueMosaicModelView::setReconstructionLogic(vtkTissueMosaicReconstructionLogic* logic) {
  if (logic) {
    this->setSceneData(logic->GetModel(), logic->GetKeyFrameFrusta(), logic->GetCurrentFrustum(),
                       logic->GetTrajectory());
  } else {
    this->setSceneData(nullptr, nullptr, nullptr, nullptr);
  }
}

void qTissueMosaicModelView::setSceneData(vtkPolyData* model, vtkPolyData* keyFrameFrusta, vtkPolyData* currentFrustum,
                                          vtkPolyData* trajectory) {
  d->model = model;
  d->keyFrameFrusta = keyFrameFrusta;
  d->currentFrustum = currentFrustum;
  d->trajectory = trajectory;
  d->scene->SetModel(model);
  d->scene->SetKeyFrameFrusta(keyFrameFrusta);
  d->scene->SetCurrentFrustum(currentFrustum);
  d->scene->SetTrajectory(trajectory);
  d->userMovedCamera = false;
  this->requestRender();
}

vtkTissueMosaicModelScene* qTissueMosaicModelView::scene() const { return d->scene; }
QString qTissueMosaicModelView::scaleBarText() const { return QString::fromStdString(d->legends->scaleBarLabel()); }
bool qTissueMosaicModelView::axesShown() const { return d->legends->axes()->GetEnabled() != 0; }
vtkRenderer* qTissueMosaicModelView::renderer() const { return d->renderer; }
vtkRenderWindow* qTissueMosaicModelView::renderWindow() const { return d->window; }
QVTKOpenGLNativeWidget* qTissueMosaicModelView::vtkWidget() const { return d->widget; }

void qTissueMosaicModelView::requestRender() {
  if (d->renderPending) return;
  d->renderPending = true;
  // Between two renders the event loop gets at least twice the last render's time (software OpenGL on a busy CPU
  // can take a large part of a second per frame), and renders come at most at about 30 Hz: the interface keeps
  // responding however often the logic has news. Mouse interaction renders directly, unthrottled.
  const qint64 sinceLastMs = d->sinceRender.isValid() ? d->sinceRender.elapsed() : 1000000;
  // At least 1 ms: a zero-time single shot is a posted event, and posted events run in the same pass as the window
  // repaint that the caller's other updates queued (at low priority, after them): render and repaint back to back.
  const qint64 waitMs = std::max<qint64>(1, std::max<qint64>(33, 2 * d->lastRenderMs) - sinceLastMs);
  d->sinceRenderRequest.start();
  d->renderWaitMs = waitMs;
  const unsigned request = ++d->renderRequest;
  QTimer::singleShot(static_cast<int>(waitMs), this, [this, request] { this->renderWhenLoopIsFree(request, true); });
}

void qTissueMosaicModelView::renderWhenLoopIsFree(unsigned request, bool mayGiveWay) {
  if (!d->renderPending || request != d->renderRequest) return;  // rendered meanwhile
  // Late: a long event ran just before this timer in the same pass of the event loop. Give way once, to the next
  // timer pass, so that input and other timers are handled between that event and this render. A timer started
  // now never fires in the pass that is running.
  const qint64 lateMs = d->sinceRenderRequest.elapsed() - d->renderWaitMs;
  if (mayGiveWay && lateMs > Private::kLateRenderMs) {
    QTimer::singleShot(1, this, [this, request] { this->renderWhenLoopIsFree(request, false); });
    return;
  }
  this->render();
}

void qTissueMosaicModelView::render() {
  d->renderPending = false;
  if (!d->warmedUp && d->widget->isValid()) d->warmUp();
  // The scan starts from nothing and grows: keep it framed until the user takes the camera (resetView() and a
  // new, empty model hand it back).
  if (d->model && d->model->GetNumberOfPoints() == 0) d->userMovedCamera = false;
  if (!d->userMovedCamera && d->model && d->model->GetNumberOfPoints() > 0) {
    vtkTissueMosaicModelScene::ResetScopeView(d->renderer, d->scene->GetModelActor());
    d->scene->FitPointSizeToView(d->renderer);
  }
  d->renderer->ResetCameraClippingRange();
  auto* style = vtkInteractorStyle::SafeDownCast(d->widget->interactor()->GetInteractorStyle());
  const bool userInteracting = style && style->GetState() != VTKIS_NONE;
  if (!userInteracting) {
    // The scene reduces only a model larger than the budget (vtkTissueMosaicModelScene::SetInteracting).
    d->updateBudget();
    d->scene->SetInteracting(d->live);
  }
  QElapsedTimer timer;
  timer.start();
  // The widget's updates are not held around the render (to keep Qt's repaint of the window from running straight
  // after it): a window resized before the view's first render then stayed grey for good (test
  // app.view_after_resize). On a real 1280x1024 clip (1.01 M points) the longest stall without it was 81-92 ms.
  d->widget->renderWindow()->Render();
  d->lastRenderMs = timer.elapsed();
  d->sinceRender.start();
  // The speed estimate includes the frame's fixed costs, so it errs toward reducing: a growing model switches to
  // the subsample before a full draw of it would ever stall the interface.
  const vtkIdType points = d->scene->GetDrawnModelPoints();
  if (points >= Private::kSmallestSubsample / 2) d->msPerPoint = double(d->lastRenderMs) / points;
}

void qTissueMosaicModelView::setLiveUpdates(bool live) {
  if (live == d->live) return;
  d->live = live;
  this->requestRender();  // the full model once the scan ends
}

void qTissueMosaicModelView::setInteractiveFrameTimeMs(double milliseconds) {
  d->interactiveFrameTimeMs = std::max(0.0, milliseconds);
}

double qTissueMosaicModelView::interactiveFrameTimeMs() const { return d->interactiveFrameTimeMs; }

void qTissueMosaicModelView::resetView() {
  d->userMovedCamera = false;
  vtkTissueMosaicModelScene::ResetScopeView(d->renderer, d->scene->GetModelActor());
  this->requestRender();
}

void qTissueMosaicModelView::renderFullModel() {
  const bool live = d->live;
  d->live = false;  // a picture shows every point, however long it takes
  this->render();
  d->live = live;
  d->widget->setUpdatesEnabled(true);  // a picture of the window follows: its repaint cannot wait (see render())
}

bool qTissueMosaicModelView::saveScreenshot(const QString& path) {
  this->renderFullModel();
  vtkNew<vtkWindowToImageFilter> grabber;
  grabber->SetInput(d->window);
  grabber->SetInputBufferTypeToRGB();
  grabber->ReadFrontBufferOff();
  grabber->Update();
  vtkNew<vtkPNGWriter> writer;
  const QByteArray file = path.toLocal8Bit();
  writer->SetFileName(file.constData());
  writer->SetInputConnection(grabber->GetOutputPort());
  writer->Write();
  return writer->GetErrorCode() == 0;
}

double qTissueMosaicModelView::measureFrameRate(int frames, bool interacting, bool shown) {
  vtkCamera* camera = d->renderer->GetActiveCamera();
  vtkNew<vtkCamera> saved;
  saved->DeepCopy(camera);
  this->render();  // uploads the data once: the measurement is of drawing, as during interaction
  if (interacting) {
    d->updateBudget();
    d->scene->SetInteracting(true);
    d->widget->renderWindow()->Render();  // the subsample's upload, once per interaction
  }
  QElapsedTimer timer;
  timer.start();
  for (int i = 0; i < frames; ++i) {
    camera->Azimuth(1.0);
    d->widget->renderWindow()->Render();
    if (shown) {
      d->window->WaitForCompletion();
      // The render asked Qt to repaint the window (a posted request); composing it draws the frame on screen.
      QCoreApplication::processEvents();
    }
  }
  d->window->WaitForCompletion();  // count the drawing, not only its submission
  const double seconds = timer.nsecsElapsed() * 1e-9;
  d->scene->SetInteracting(false);
  camera->DeepCopy(saved);
  this->render();
  return seconds > 0 ? frames / seconds : 0;
}
