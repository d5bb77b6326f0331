#pragma once
/// @class qTissueMosaicRegistrationResults
/// @brief The results group of the registration panel: the numbers of the last registration step (landmark RMSE
/// under the current transform, scale, ICP iterations and inlier RMSE) and of the evaluation over all model points
/// (distance RMSE, mean, median, 95th percentile, maximum), the 4x4 T_target_model, the distance histogram, the
/// colour-by-distance switch, and a notice when the results no longer match the model.
#include <QGroupBox>
#include <QMap>

class QCheckBox;
class QDoubleSpinBox;
class QLabel;
class QPushButton;
class qTissueMosaicHistogramPlot;
class qTissueMosaicMessageLine;
class vtkTissueMosaicRegistrationLogic;

class qTissueMosaicRegistrationResults : public QGroupBox {
  Q_OBJECT
public:
  explicit qTissueMosaicRegistrationResults(QWidget* parent = nullptr);

  /// Shows the logic's transform, numbers and histogram.
  void showResults(vtkTissueMosaicRegistrationLogic* logic);
  /// An out-of-date notice over the results (empty: none).
  void setNotice(const QString& text);
  QString notice() const;

  /// The text of a number by name (see qTissueMosaicRegistrationWidget::shownNumber); empty for an unknown name.
  QString number(const QString& name) const;
  QString transformText() const;
  qTissueMosaicHistogramPlot* histogram() const { return this->Histogram; }
  QCheckBox* colourByDistanceCheckBox() const { return this->ColourByDistance; }
  QDoubleSpinBox* binWidthSpinBox() const { return this->BinWidth; }

signals:
  void colourByDistanceToggled(bool enabled);
  void binWidthChanged(double binWidthMm);
  void updateDistancesRequested();

private:
  QMap<QString, QLabel*> Numbers;
  qTissueMosaicMessageLine* Notice = nullptr;
  QLabel* Transform = nullptr;
  QCheckBox* ColourByDistance = nullptr;
  QDoubleSpinBox* BinWidth = nullptr;
  qTissueMosaicHistogramPlot* Histogram = nullptr;
};
