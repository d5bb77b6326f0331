#include "qTissueMosaicHistogramPlot.h"

#include <QPainter>

#include <algorithm>
#include <cmath>

qTissueMosaicHistogramPlot::qTissueMosaicHistogramPlot(QWidget* parent) : QWidget(parent) {
  this->setMinimumSize(240, 150);
}

void qTissueMosaicHistogramPlot::setHistogram(QVector<double> percent, double binWidthMm, double meanMm, double p95Mm,
                                              double overflowPercent) {
  this->Percent = std::move(percent);
  this->BinWidthMm = binWidthMm;
  this->MeanMm = meanMm;
  this->P95Mm = p95Mm;
  this->OverflowPercent = overflowPercent;
  this->update();
}

QString qTissueMosaicHistogramPlot::overflowNote() const {
  if (this->Percent.isEmpty() || this->OverflowPercent <= 0) return QString();
  return tr("%1% of the points lie beyond %2 mm")
      .arg(this->OverflowPercent, 0, 'f', 1)
      .arg(this->BinWidthMm * this->Percent.size(), 0, 'g', 3);
}

void qTissueMosaicHistogramPlot::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.fillRect(this->rect(), this->palette().base());
  const QFontMetrics metrics = painter.fontMetrics();
  const int left = metrics.horizontalAdvance("100%") + 8, bottom = 2 * metrics.height() + 4, right = 10;
  const QString note = this->overflowNote();
  const int top = note.isEmpty() ? 6 : metrics.height() + 6;  // the overflow note sits above the plot
  const QRect plot(left, top, std::max(10, this->width() - left - right), std::max(10, this->height() - top - bottom));
  painter.setPen(this->palette().text().color());
  if (this->Percent.isEmpty()) {
    painter.drawText(this->rect(), Qt::AlignCenter, tr("no distances yet"));
    return;
  }
  const double highest = std::max(1e-9, *std::max_element(this->Percent.begin(), this->Percent.end()));
  const double rangeMm = this->BinWidthMm * this->Percent.size();
  const auto xOf = [&](double mm) { return plot.left() + plot.width() * mm / rangeMm; };
  painter.setBrush(QColor(70, 130, 180));
  for (int i = 0; i < this->Percent.size(); ++i) {
    const double x0 = xOf(i * this->BinWidthMm), x1 = xOf((i + 1) * this->BinWidthMm);
    const double h = plot.height() * this->Percent[i] / highest;
    painter.drawRect(QRectF(x0, plot.bottom() - h, std::max(1.0, x1 - x0), h));
  }
  painter.setBrush(Qt::NoBrush);
  painter.drawRect(plot);
  const auto marker = [&](double mm, const QColor& colour, const QString& name, int line) {
    if (!(mm >= 0 && mm <= rangeMm)) return;
    painter.setPen(QPen(colour, 2, Qt::DashLine));
    painter.drawLine(QPointF(xOf(mm), plot.top()), QPointF(xOf(mm), plot.bottom()));
    painter.drawText(QPointF(xOf(mm) + 3, plot.top() + metrics.ascent() + line * metrics.height()), name);
  };
  marker(this->MeanMm, QColor(0, 150, 0), tr("mean"), 0);
  // The p95 label a line lower when the two marks are close: their names would print over each other.
  const bool close = std::abs(xOf(this->P95Mm) - xOf(this->MeanMm)) < metrics.horizontalAdvance(tr("mean")) + 6;
  marker(this->P95Mm, QColor(200, 0, 0), tr("p95"), close ? 1 : 0);
  if (!note.isEmpty()) {
    painter.setPen(QColor(200, 0, 0));
    painter.drawText(QRect(left, 2, this->width() - left - right, metrics.height()), Qt::AlignRight, note);
  }
  painter.setPen(this->palette().text().color());
  painter.drawText(QRect(0, plot.top(), left - 4, metrics.height()), Qt::AlignRight,
                   QString::number(highest, 'f', 1) + "%");
  painter.drawText(QRect(0, plot.bottom() - metrics.height(), left - 4, metrics.height()), Qt::AlignRight, "0%");
  const int axisY = plot.bottom() + 2;
  painter.drawText(QRect(plot.left(), axisY, plot.width(), metrics.height()), Qt::AlignLeft, "0");
  painter.drawText(QRect(plot.left(), axisY, plot.width(), metrics.height()), Qt::AlignRight,
                   QString::number(rangeMm, 'g', 3));
  painter.drawText(QRect(plot.left(), axisY + metrics.height(), plot.width(), metrics.height()), Qt::AlignHCenter,
                   tr("distance to the CT/MR surface (mm)"));
}
