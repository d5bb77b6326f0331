#pragma once
/// @class qTissueMosaicRegistrationView
/// @brief The 3D scene of a registration (one vtkTissueMosaicRegistrationLogic), in the CT/MR model's frame (LPS
/// mm): the model in its own colours (unlit, as scanned) or coloured by its distance to the CT/MR surface with a
/// colour bar, the CT/MR surface, the landmark spheres (yellow: model, green: CT/MR) with their labels, orientation
/// axes and a scale bar. The model and its landmarks are drawn through the current transform T_target_model, so the
/// model moves onto the CT/MR model as the registration proceeds.
///
/// Picking: in a pick mode, a left click that does not drag puts a landmark on the model (the scan point drawn under
/// the cursor, see vtkTissueMosaicPointPick.h, or the hit point of a surface) or on the CT/MR surface (the hit
/// point); dragging still turns the camera.
///
/// The application shows this view in its main view area while the Registration module is active (as 3D Slicer
/// switches its layout); the panel, qTissueMosaicRegistrationWidget, holds the controls. The view is a
/// QVTKOpenGLNativeWidget: call QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat()) before
/// creating the QApplication.
#include <QWidget>

class QVTKOpenGLNativeWidget;
class vtkActor;
class vtkRenderer;
class vtkScalarBarActor;
class vtkTissueMosaicRegistrationLogic;

class qTissueMosaicRegistrationView : public QWidget {
  Q_OBJECT
public:
  /// What a click in the view picks.
  enum PickMode { PickNone = 0, PickOnModel, PickOnTarget };
  Q_ENUM(PickMode)

  /// Shows `logic` (referenced).
  explicit qTissueMosaicRegistrationView(vtkTissueMosaicRegistrationLogic* logic, QWidget* parent = nullptr);
  ~qTissueMosaicRegistrationView() override;

  void setPickMode(PickMode mode);
  PickMode pickMode() const;
  /// Picks at a position in VTK display pixels (origin at the bottom left), as a click does, by the pick mode. True
  /// when a landmark was placed (landmarkPicked follows); else pickMissed says why.
  bool pickAt(int displayX, int displayY);

  /// The model coloured by its distance to the CT/MR surface (when there is an evaluation), or in its own colours.
  void setColourByDistance(bool enabled);
  bool colourByDistance() const;

  QVTKOpenGLNativeWidget* vtkWidget() const;
  vtkRenderer* renderer() const;
  vtkScalarBarActor* scalarBar() const;
  /// The model in its own colours (through the transform).
  vtkActor* modelActor() const;
  /// The model coloured by distance: it draws the logic's registered model (through vertex glyphs when that model
  /// has no cells).
  vtkActor* distanceActor() const;
  vtkActor* targetActor() const;

public slots:
  /// Shows the logic's state (models, transform, landmarks, distance colours) and renders.
  void updateFromLogic();
  /// Landmark spheres and labels only (after a pick or an edit), then renders.
  void updateLandmarks();
  /// Fits the camera to what is shown.
  void resetCamera();
  /// Renders now, when the view is visible (a hidden view renders when it is shown).
  void render();

signals:
  /// A click placed a landmark: the pair at `pairIndex` changed.
  void landmarkPicked(int pairIndex);
  /// A click in a pick mode hit nothing to pick: `reason` in plain words.
  void pickMissed(const QString& reason);

protected:
  void showEvent(QShowEvent* event) override;

private:
  class Private;
  Private* d;
};
