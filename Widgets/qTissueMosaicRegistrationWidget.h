#pragma once
/// @class qTissueMosaicRegistrationWidget
/// @brief The registration module panel (issue 6): aligns the reconstructed model to the patient's CT/MR surface
/// model by landmark pairs and ICP, and shows how well they agree. It holds the controls only; the scene (model,
/// CT/MR surface, landmarks, distance colours) is drawn by its qTissueMosaicRegistrationView, sceneView(), which the
/// application shows in its main view area while this module is active (3D Slicer's rule: module panels hold
/// controls, the layout holds the views).
///
/// Workflow: the model is the live reconstruction by default ("Use the current scan", with its point count, kept up
/// to date as the scan grows), or a file (Load model...); load the CT/MR model (frame: from the file, LPS or RAS);
/// pick landmark pairs in the view (pick mode "on model" or "on CT/MR", then click: a click without dragging picks,
/// a drag still rotates), edit or delete them in the table; register (rigid or with a uniform scale); refine with
/// ICP (on a worker thread, with progress, Cancel and Undo; a refinement that made the fit worse says so); then read
/// the distances: the model coloured by its distance to the CT/MR surface with a colour bar, the error histogram
/// and the numbers. Results that no longer match the model (the scan grew or was reset) are marked out of date.
/// Export writes the files of `tissuemosaic register` (docs/REGISTRATION.md) and confirms each file written.
///
/// All the work is done by one vtkTissueMosaicRegistrationLogic (no Qt), which the panel owns; the panel only
/// shows its state. Messages appear where the action was: each group of controls has its own message line.
#include "qTissueMosaicRegistrationView.h"

#include <Eigen/Core>

#include <QScopedPointer>
#include <QString>
#include <QVector>
#include <QWidget>

class qTissueMosaicLandmarkTable;
class qTissueMosaicRegistrationWidgetPrivate;
class vtkPolyData;
class vtkTissueMosaicRegistrationLogic;

class qTissueMosaicRegistrationWidget : public QWidget {
  Q_OBJECT
public:
  explicit qTissueMosaicRegistrationWidget(QWidget* parent = nullptr);
  ~qTissueMosaicRegistrationWidget() override;

  /// The logic holding the registration state (owned by the panel). Change it through the panel's methods, or
  /// call updateFromLogic() afterwards.
  vtkTissueMosaicRegistrationLogic* registrationLogic() const;
  /// The 3D scene of this panel. Created with the panel and without a parent: the application puts it in its view
  /// area (it then belongs there); a view nobody took is deleted with the panel.
  qTissueMosaicRegistrationView* sceneView() const;

  /// @name Models
  ///@{
  /// The live reconstruction (world mm, used as LPS; referenced, not copied): the default model ("Use the current
  /// scan"). Call liveModelChanged() when it grew or was emptied.
  void setReconstructedModel(vtkPolyData* liveModel);
  /// Makes the live reconstruction the model again (after a file); false when there is none.
  bool useCurrentScan();
  bool usesCurrentScan() const;
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
  /// The table of pairs (qTissueMosaicLandmarkTable::Column).
  qTissueMosaicLandmarkTable* landmarkTable() const;
  void setPickMode(qTissueMosaicRegistrationView::PickMode mode);
  qTissueMosaicRegistrationView::PickMode pickMode() const;
  ///@}

  /// @name Registration
  ///@{
  void setScaleEnabled(bool withScale);
  bool scaleEnabled() const;
  /// Landmark registration of the complete pairs (with the scale option).
  bool registerLandmarks();
  /// ICP from the current transform with the panel's settings, on a worker thread; the panel shows its progress
  /// and stays responsive. False when it cannot start (the message says why). icpFinished() follows.
  bool startIcp();
  /// startIcp(), then waits (running the event loop) until it has finished; its result.
  bool refineIcp();
  /// Stops a running ICP; nothing changes.
  void cancelIcp();
  bool isIcpRunning() const;
  /// Puts back the transform and results of before the last registration step.
  bool undo();
  void setIcpMaxIterations(int iterations);
  void setIcpInlierFraction(double fraction);
  /// Recomputes the distances of the current model (e.g. after the live reconstruction grew).
  bool updateDistances();
  ///@}

  /// @name What the panel shows (also for tests)
  ///@{
  /// The text of a number in the results box: "rmse", "mean", "median", "p95", "max", "points", "icpIterations",
  /// "icpInlierRmse", "landmarkRmse" (under the current transform), "scale". Empty for an unknown name.
  QString shownNumber(const QString& name) const;
  /// The transform shown (T_target_model, 4 rows of 4 numbers).
  QString shownTransform() const;
  /// The model's line: "Use the current scan (12 345 points)" or the file's name and size.
  QString shownModelText() const;
  /// The message of the last failed action; empty after a success.
  QString errorText() const;
  /// The last message of any kind (a confirmation, a warning such as "ICP made the fit worse", an error).
  QString lastMessage() const;
  /// The out-of-date notice over the results ("The model has grown since ..."); empty when the results are current.
  QString resultsNotice() const;
  /// Histogram bars as shown: share of the model points per bin, in percent; and the bin width.
  QVector<double> histogramPercent() const;
  double histogramBinWidthMm() const;
  /// The note for points beyond the last bin, e.g. "63.0% of the points lie beyond 10 mm" (empty when none).
  QString histogramOverflowNote() const;
  void setColourByDistance(bool enabled);
  bool colourByDistance() const;
  ///@}

  /// @name Export (the file formats of `tissuemosaic register`); each success is confirmed beside the buttons
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
  /// The live reconstruction changed (grew, or was emptied by a reset): counts, out-of-date notice, view.
  void liveModelChanged();

signals:
  /// The landmark list changed (pick, edit, delete, load).
  void landmarksChanged();
  /// The transform or the distances changed.
  void registrationChanged();
  /// A running ICP ended (ok: its result is shown; else the message says why).
  void icpFinished(bool ok);

protected:
  QScopedPointer<qTissueMosaicRegistrationWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qTissueMosaicRegistrationWidget);
  Q_DISABLE_COPY(qTissueMosaicRegistrationWidget);
};
