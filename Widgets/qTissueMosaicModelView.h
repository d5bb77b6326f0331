#pragma once
/// @class qTissueMosaicModelView
/// @brief The 3D view of a reconstruction (QVTKOpenGLNativeWidget): the textured point model, the key-frame
/// frusta, the live camera and its path (vtkTissueMosaicModelScene, the same scene as offscreen snapshots).
///
/// The view draws the logic's output polydata, which the logic updates in place; requestRender() (after
/// vtkTissueMosaicReconstructionLogic::UpdateOutputs) redraws at most once per event-loop pass, so a burst of
/// updates never queues renders. Until the user turns the view, the camera follows the growing model ("scope
/// view", vtkTissueMosaicModelScene::ResetScopeView).
/// The view stays interactive (rotate, zoom, pan with the mouse) while the scan runs.
///
/// Call QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat()) before creating the
/// QApplication.
#include <QWidget>

class QVTKOpenGLNativeWidget;
class vtkRenderer;
class vtkRenderWindow;
class vtkTissueMosaicModelScene;
class vtkTissueMosaicReconstructionLogic;
class vtkPolyData;

class qTissueMosaicModelView : public QWidget {
  Q_OBJECT
public:
  explicit qTissueMosaicModelView(QWidget* parent = nullptr);
  ~qTissueMosaicModelView() override;

  /// Shows this logic's model, frusta, current camera and path (nullptr: nothing).
  void setReconstructionLogic(vtkTissueMosaicReconstructionLogic* logic);
  /// Shows these polydata instead (any may be null), e.g. a model read from a file.
  void setSceneData(vtkPolyData* model, vtkPolyData* keyFrameFrusta, vtkPolyData* currentFrustum,
                    vtkPolyData* trajectory);

  vtkTissueMosaicModelScene* scene() const;
  /// The scale bar's label as of the last render ("10 mm"); empty before the first render.
  QString scaleBarText() const;
  /// Whether the orientation axes are shown in the corner.
  bool axesShown() const;
  vtkRenderer* renderer() const;
  vtkRenderWindow* renderWindow() const;
  QVTKOpenGLNativeWidget* vtkWidget() const;

  /// Renders `frames` frames, turning the camera a little each time, and returns the frames per second (the
  /// camera is put back). interacting: as while the user turns the view (level of detail, see below).
  /// shown: each frame also waits for Qt to compose it into the window, as when the user turns the view (with
  /// software OpenGL the composition of the whole window costs about as much as a render); otherwise only VTK's
  /// drawing is counted. For measuring interactivity with large models.
  double measureFrameRate(int frames, bool interacting = false, bool shown = false);

  /// While the user turns the view, the model is drawn with at most as many points as fit in this time per frame
  /// (estimated from the last full render; vtkTissueMosaicModelScene's level of detail). 0: always every point.
  /// Default 25 ms: with Qt's composition of the window (as long again on software OpenGL) a frame stays under
  /// 50 ms. On a GPU a model of millions of points draws faster than that and is never reduced; software OpenGL
  /// reduces it.
  void setInteractiveFrameTimeMs(double milliseconds);
  double interactiveFrameTimeMs() const;
  /// While the model changes live (a scan is running), renders use the same level of detail when the full model
  /// would take longer than the interactive frame time, so that the interface keeps responding between key
  /// frames; the full model is drawn again when live updates end (and whenever the user lets go of the view).
  void setLiveUpdates(bool live);

public slots:
  /// Redraws soon (once, however often it is called before the redraw). A redraw that falls due while another
  /// long event holds the event loop waits one more timer pass, so that the two never make one stall.
  void requestRender();
  /// Redraws now.
  void render();
  /// Redraws now with every point of the model, even during live updates (for pictures).
  void renderFullModel();
  /// Fits the camera to the scene, looking along the scope (vtkTissueMosaicModelScene::ResetScopeView).
  void resetView();
  /// Writes what the 3D view shows as a PNG. False when the file cannot be written.
  bool saveScreenshot(const QString& path);

private:
  /// The timer end of requestRender(): renders, unless the event loop has just been busy and the render may still
  /// give way (once: its second timer passes false; see the .cxx).
  void renderWhenLoopIsFree(unsigned request, bool mayGiveWay);

  class Private;
  Private* d;
};
