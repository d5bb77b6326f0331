#pragma once
/// @class qTissueMosaicHistogramPlot
/// @brief The distance histogram of a registration as a bar chart (x: distance to the CT/MR surface in mm, y: share
/// of the model points in %), with the mean and the 95th percentile marked and the share of points beyond the last
/// bin written in the plot, as in the PNG that DistanceReport writes. Drawn with QPainter: a second OpenGL view
/// (vtkChartXY) would cost a context for a handful of bars.
#include <QVector>
#include <QWidget>

class qTissueMosaicHistogramPlot : public QWidget {
  Q_OBJECT
public:
  explicit qTissueMosaicHistogramPlot(QWidget* parent = nullptr);

  /// percent: share of the points per bin [i w, (i+1) w); overflowPercent: share beyond the last bin.
  void setHistogram(QVector<double> percent, double binWidthMm, double meanMm, double p95Mm, double overflowPercent);
  const QVector<double>& percent() const { return this->Percent; }
  double binWidthMm() const { return this->BinWidthMm; }
  double overflowPercent() const { return this->OverflowPercent; }
  /// The note shown for the points beyond the last bin ("63.0% of the points lie beyond 10 mm"); empty when none.
  QString overflowNote() const;

  QSize sizeHint() const override { return QSize(320, 170); }

protected:
  void paintEvent(QPaintEvent* event) override;

private:
  QVector<double> Percent;
  double BinWidthMm = 0, MeanMm = 0, P95Mm = 0, OverflowPercent = 0;
};
