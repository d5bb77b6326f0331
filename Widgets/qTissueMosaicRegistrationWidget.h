#pragma once
/// @class qTissueMosaicRegistrationWidget
/// @brief The registration panel (issue 6): aligns the reconstructed model to the patient's CT/MR surface model
/// by landmark pairs and ICP, and shows how well they agree.
///
/// Workflow: load (or receive) the reconstructed model, load the CT/MR model (frame: from the file, LPS or RAS),
/// pick landmark pairs in the panel's 3D view (pick mode "on model" or "on CT/MR", then click: a click without
/// dragging picks, a drag still rotates), edit or delete them in the table, register (rigid or with a uniform
/// scale), refine with ICP, then read the distances: the model coloured by its distance to the CT/MR surface with
/// a colour bar, the error histogram and the numbers (RMSE, mean, median, 95th percentile, maximum, ICP
/// iterations). Export writes the files of `tissuemosaic register` (docs/REGISTRATION.md).
///
/// All the work is done by one vtkTissueMosaicRegistrationLogic (no Qt), which the panel owns; the panel only
/// shows its state. The 3D view shows everything in the CT/MR model's frame (LPS mm): the model is drawn through
/// the current transform T_target_model, so it moves onto the CT/MR model as the registration proceeds.
///
/// The view is a QVTKOpenGLNativeWidget: call QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::
/// defaultFormat()) before creating the QApplication.
#include <Eigen/Core>

#include <QScopedPointer>
#include <QString>
#include <QVector>
#include <QWidget>

class QTableWidget;
class QVTKOpenGLNativeWidget;
class qTissueMosaicRegistrationWidgetPrivate;
class vtkActor;
class vtkPolyData;
class vtkRenderer;
class vtkScalarBarActor;
class vtkTissueMosaicRegistrationLogic;

class qTissueMosaicRegistrationWidget : public QWidget {
  Q_OBJECT
public:
  /// What a click in the 3D view picks.
  enum PickMode { PickNone = 0, PickOnModel, PickOnTarget };
  Q_ENUM(PickMode)

  /// Columns of the landmark table.
  enum LandmarkColumn { LabelColumn = 0, ModelColumn, TargetColumn, ResidualColumn };

  explicit qTissueMosaicRegistrationWidget(QWidget* parent = nullptr);
  ~qTissueMosaicRegistrationWidget() override;

  /// The logic holding the registration state (owned by the panel). Change it through the panel's methods, or
  /// call updateFromLogic() afterwards.
  vtkTissueMosaicRegistrationLogic* registrationLogic() const;

  /// @name Models
  ///@{
  /// Registers this model (the live reconstruction, LPS/world mm; referenced, not copied). The view follows
  /// in-place updates of it; distances are recomputed by the next registration step or by updateDistances().
  void setReconstructedModel(vtkPolyData* modelLps);
  /// Reads the reconstructed model from a file (.ply .vtp .vtk .stl .obj) in the frame chosen in the panel.
  bool loadModelFile(const QString& path);
  /// Reads the CT/MR surface model (must have triangles) in the frame chosen in the panel.
  bool loadTargetFile(const QString& path);
  /// Frame choice for the files loaded next: 0 from the file, 1 LPS, 2 RAS (tissuemosaic::ModelFrameChoice).
  void setModelFrameChoice(int choice);
  void setTargetFrameChoice(int choice);
  ///@}

  /// @name Landmarks
  ///@{
  /// Appends a complete pair (model point in the model's frame, target point in the CT/MR frame); its row, or -1.
  int addLandmarkPair(const Eigen::Vector3d& modelLps, const Eigen::Vector3d& targetLps);
  /// Deletes the pair shown in this table row.
  bool removeLandmarkPair(int row);
  /// Replaces the pairs with those of a .mrk.json holding two lists (the model's, then the CT/MR model's).
  bool loadLandmarksFile(const QString& path);
  /// The table of pairs: label, model point, CT/MR point (both "x, y, z" in mm, editable), residual (mm).
  QTableWidget* landmarkTable() const;
  void setPickMode(PickMode mode);
  PickMode pickMode() const;
  /// Picks at a position of the 3D view in VTK display pixels (origin at the bottom left), as a click does: on
  /// the model (the point under the cursor) or on the CT/MR surface, by the pick mode. False when nothing was hit.
  bool pickAt(int displayX, int displayY);
  ///@}

  /// @name Registration
  ///@{
  void setScaleEnabled(bool withScale);
  bool scaleEnabled() const;
  /// Landmark registration of the complete pairs (with the scale option).
  bool registerLandmarks();
  /// ICP from the current transform with the panel's ICP settings.
  bool refineIcp();
  void setIcpMaxIterations(int iterations);
  void setIcpInlierFraction(double fraction);
  /// Recomputes the distances of the current model (e.g. after the live reconstruction grew).
  bool updateDistances();
  ///@}

  /// @name What the panel shows (also for tests)
  ///@{
  /// The text of a number in the results box: "rmse", "mean", "median", "p95", "max", "points", "icpIterations",
  /// "icpInlierRmse", "landmarkRmse", "scale". Empty for an unknown name.
  QString shownNumber(const QString& name) const;
  /// The transform shown (T_target_model, 4 rows of 4 numbers).
  QString shownTransform() const;
  /// The message of the last failed action; empty after a success.
  QString errorText() const;
  /// Histogram bars as shown: share of the model points per bin, in percent; and the bin width.
  QVector<double> histogramPercent() const;
  double histogramBinWidthMm() const;
  void setColourByDistance(bool enabled);
  bool colourByDistance() const;
  QVTKOpenGLNativeWidget* view() const;
  vtkRenderer* renderer() const;
  vtkScalarBarActor* scalarBar() const;
  /// The actor of the model coloured by distance: it draws the logic's registered model (through vertex glyphs
  /// when that model has no cells).
  vtkActor* distanceActor() const;
  ///@}

  /// @name Export (the file formats of `tissuemosaic register`)
  ///@{
  bool exportTransform(const QString& tfmPath);
  bool exportRegisteredModel(const QString& path);
  bool exportLandmarks(const QString& mrkJsonPath);
  /// The distance CSV and the histogram PNG.
  bool exportDistanceReport(const QString& csvPath, const QString& pngPath);
  ///@}

public slots:
  /// Shows the logic's state (models, table, transform, numbers, colours) and renders.
  void updateFromLogic();

signals:
  /// The landmark list changed (pick, edit, delete, load).
  void landmarksChanged();
  /// The transform or the distances changed.
  void registrationChanged();

protected:
  QScopedPointer<qTissueMosaicRegistrationWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qTissueMosaicRegistrationWidget);
  Q_DISABLE_COPY(qTissueMosaicRegistrationWidget);
};
