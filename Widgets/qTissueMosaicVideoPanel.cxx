#include "qTissueMosaicVideoPanel.h"

#include "vtkTissueMosaicDisparityColours.h"

#include "Core/StereoRig.h"

#include <opencv2/imgproc.hpp>

#include <QHBoxLayout>
#include <QMouseEvent>
#include <QPainter>
#include <QToolTip>

#include <cmath>

namespace {

/// Width of the disparity legend: colour bar and its two columns of labels.
constexpr int kLegendWidthPx = 112;
constexpr int kLegendTicks = 5;

QString depthText(double depthMm) { return std::isfinite(depthMm) ? QString("%1 mm").arg(depthMm, 0, 'f', 0) : "far"; }

}  // namespace

qTissueMosaicImageView::qTissueMosaicImageView(const QString& caption, QWidget* parent)
    : QWidget(parent), Caption(caption) {
  this->setMinimumSize(120, 80);
  this->setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Expanding);
}

QRect qTissueMosaicImageView::imageArea() const {
  QRect area = this->rect().adjusted(2, 2, -2, -2);
  if (this->HasLegend) area.setRight(area.right() - kLegendWidthPx);
  return area;
}

cv::Size qTissueMosaicImageView::shownSize(const cv::Size& source) const {
  // Before the view is laid out its size means nothing: keep the frame's own.
  if (!this->isVisible()) return source;
  QSize size(source.width, source.height);
  const QSize area = this->imageArea().size() * this->devicePixelRatioF();
  if (size.width() > area.width() || size.height() > area.height()) size.scale(area, Qt::KeepAspectRatio);
  return cv::Size(std::max(1, size.width()), std::max(1, size.height()));
}

void qTissueMosaicImageView::wrap(const cv::Mat& rgb) {
  // The QImage shows Rgb's pixels; a new buffer (another size) needs a new QImage.
  if (this->Image.isNull() || this->Image.constBits() != rgb.data || this->Image.width() != rgb.cols ||
      this->Image.height() != rgb.rows) {
    this->Image = QImage(rgb.data, rgb.cols, rgb.rows, static_cast<int>(rgb.step), QImage::Format_RGB888);
  }
  this->update();
}

void qTissueMosaicImageView::setImage(const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_8U) {
    this->clear();
    return;
  }
  this->SourceSize = QSize(image.cols, image.rows);
  const cv::Size size = this->shownSize(image.size());
  // INTER_AREA averages the pixels a shown pixel covers; into buffers kept from frame to frame (no allocation).
  const cv::Mat* reduced = &image;
  if (size != image.size()) {
    cv::resize(image, this->Reduced, size, 0, 0, cv::INTER_AREA);
    reduced = &this->Reduced;
  }
  switch (reduced->channels()) {
    case 1: cv::cvtColor(*reduced, this->Rgb, cv::COLOR_GRAY2RGB); break;
    case 3: cv::cvtColor(*reduced, this->Rgb, cv::COLOR_BGR2RGB); break;
    case 4: cv::cvtColor(*reduced, this->Rgb, cv::COLOR_BGRA2RGB); break;
    default: this->clear(); return;
  }
  this->wrap(this->Rgb);
}

void qTissueMosaicImageView::setDisparity(const cv::Mat& disparityPx, const tissuemosaic::RectifiedGeometry* geometry,
                                          double fallbackLowPx, double fallbackHighPx) {
  if (disparityPx.empty() || disparityPx.type() != CV_32F) {
    this->clear();
    return;
  }
  const bool hadLegend = this->HasLegend;
  this->HasLegend = true;
  this->SourceSize = QSize(disparityPx.cols, disparityPx.rows);
  // Nearest: an average of disparities across a depth edge, or with NaN, is no disparity.
  cv::resize(disparityPx, this->ReducedDisparityPx, this->shownSize(disparityPx.size()), 0, 0, cv::INTER_NEAREST);
  tissuemosaic::DisparityColouring colouring;
  colouring.bgr = this->Reduced;  // reuse the buffer
  tissuemosaic::colourDisparity(this->ReducedDisparityPx, fallbackLowPx, fallbackHighPx, colouring);
  this->Reduced = colouring.bgr;
  cv::cvtColor(this->Reduced, this->Rgb, cv::COLOR_BGR2RGB);
  this->LowPx = colouring.lowPx;
  this->HighPx = colouring.highPx;
  this->FocalPx = geometry ? geometry->focalPx : 0;
  this->BaselineMm = geometry ? geometry->baselineMm : 0;
  this->DoffsPx = geometry ? geometry->doffsPx : 0;
  this->setMouseTracking(true);
  this->wrap(this->Rgb);
  if (!hadLegend) this->update();
}

void qTissueMosaicImageView::clear() {
  this->Image = QImage();
  this->SourceSize = QSize();
  this->HasLegend = false;
  this->ReducedDisparityPx.release();
  this->update();
}

QStringList qTissueMosaicImageView::legendLabels() const {
  QStringList labels;
  if (!this->HasLegend) return labels;
  tissuemosaic::RectifiedGeometry geometry;
  geometry.focalPx = this->FocalPx;
  geometry.baselineMm = this->BaselineMm;
  geometry.doffsPx = this->DoffsPx;
  for (int i = 0; i < kLegendTicks; ++i) {
    const double disparity = this->HighPx - (this->HighPx - this->LowPx) * i / (kLegendTicks - 1);
    QString label = QString("%1 px").arg(disparity, 0, 'f', 0);
    if (this->FocalPx > 0) label += " = " + depthText(tissuemosaic::depthOfDisparityMm(geometry, disparity));
    labels << label;
  }
  return labels;
}

void qTissueMosaicImageView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.fillRect(this->rect(), QColor(20, 22, 28));
  const QRect area = this->imageArea();
  QRect target;
  if (!this->Image.isNull()) {
    QSize size = this->Image.size();
    size.scale(area.size(), Qt::KeepAspectRatio);
    target = QRect(area.x() + (area.width() - size.width()) / 2, area.y() + (area.height() - size.height()) / 2,
                   size.width(), size.height());
    // Already reduced to about this size: a plain draw, no smooth scaling at every repaint.
    painter.drawImage(target, this->Image);
  } else {
    painter.setPen(QColor(120, 120, 130));
    painter.drawText(area, Qt::AlignCenter, tr("no image"));
  }
  if (this->HasLegend && !this->Image.isNull()) {
    // The colour bar (red: near, at the top) with the disparities on its left and the depths on its right.
    const QFontMetrics metrics = painter.fontMetrics();
    const int barX = area.right() + 44, barTop = target.top() + metrics.height() / 2,
              barBottom = std::max(barTop + 20, target.bottom() - metrics.height() / 2);
    tissuemosaic::DisparityColouring colouring;
    colouring.lowPx = this->LowPx;
    colouring.highPx = this->HighPx;
    for (int y = barTop; y <= barBottom; ++y) {
      const double disparity = this->HighPx - (this->HighPx - this->LowPx) * (y - barTop) / std::max(1, barBottom - barTop);
      const cv::Vec3b bgr = tissuemosaic::disparityColour(colouring, disparity);
      painter.setPen(QColor(bgr[2], bgr[1], bgr[0]));
      painter.drawLine(barX, y, barX + 10, y);
    }
    painter.setPen(Qt::white);
    tissuemosaic::RectifiedGeometry geometry;
    geometry.focalPx = this->FocalPx;
    geometry.baselineMm = this->BaselineMm;
    geometry.doffsPx = this->DoffsPx;
    for (int i = 0; i < kLegendTicks; ++i) {
      const int y = barTop + (barBottom - barTop) * i / (kLegendTicks - 1);
      const double disparity = this->HighPx - (this->HighPx - this->LowPx) * i / (kLegendTicks - 1);
      painter.drawText(QRect(barX - 44, y - metrics.height() / 2, 40, metrics.height()), Qt::AlignRight | Qt::AlignVCenter,
                       QString("%1 px").arg(disparity, 0, 'f', 0));
      if (this->FocalPx > 0) {
        painter.drawText(QRect(barX + 14, y - metrics.height() / 2, kLegendWidthPx - 58, metrics.height()),
                         Qt::AlignLeft | Qt::AlignVCenter, depthText(tissuemosaic::depthOfDisparityMm(geometry, disparity)));
      }
    }
  }
  // Caption on a dark band, readable over any image.
  const QRect band(area.x(), area.y(), painter.fontMetrics().horizontalAdvance(this->Caption) + 12,
                   painter.fontMetrics().height() + 4);
  painter.fillRect(band, QColor(0, 0, 0, 150));
  painter.setPen(Qt::white);
  painter.drawText(band, Qt::AlignCenter, this->Caption);
}

void qTissueMosaicImageView::mouseMoveEvent(QMouseEvent* event) {
  QWidget::mouseMoveEvent(event);
  if (!this->HasLegend || this->ReducedDisparityPx.empty() || this->Image.isNull()) return;
  // Where the cursor is in the shown image.
  const QRect area = this->imageArea();
  QSize size = this->Image.size();
  size.scale(area.size(), Qt::KeepAspectRatio);
  const QRect target(area.x() + (area.width() - size.width()) / 2, area.y() + (area.height() - size.height()) / 2,
                     size.width(), size.height());
  if (!target.contains(event->pos())) {
    QToolTip::hideText();
    return;
  }
  const int x = (event->pos().x() - target.x()) * this->ReducedDisparityPx.cols / std::max(1, target.width());
  const int y = (event->pos().y() - target.y()) * this->ReducedDisparityPx.rows / std::max(1, target.height());
  const float disparity = this->ReducedDisparityPx.at<float>(std::min(y, this->ReducedDisparityPx.rows - 1),
                                                             std::min(x, this->ReducedDisparityPx.cols - 1));
  QString text = tr("no estimate");
  if (std::isfinite(disparity)) {
    text = tr("disparity %1 px").arg(disparity, 0, 'f', 1);
    if (this->FocalPx > 0) {
      tissuemosaic::RectifiedGeometry geometry;
      geometry.focalPx = this->FocalPx;
      geometry.baselineMm = this->BaselineMm;
      geometry.doffsPx = this->DoffsPx;
      text += tr(", depth %1").arg(depthText(tissuemosaic::depthOfDisparityMm(geometry, disparity)));
    }
  }
  QToolTip::showText(event->globalPos(), text, this);
}

qTissueMosaicVideoPanel::qTissueMosaicVideoPanel(QWidget* parent)
    : QWidget(parent),
      Left(new qTissueMosaicImageView(tr("Left (rectified)"), this)),
      Right(new qTissueMosaicImageView(tr("Right (rectified)"), this)),
      Disparity(new qTissueMosaicImageView(tr("Disparity"), this)) {
  this->Left->setObjectName("leftImageView");
  this->Right->setObjectName("rightImageView");
  this->Disparity->setObjectName("disparityImageView");
  this->Disparity->setToolTip(tr("Left-view disparity in false colour (red: near, blue: far; black: no estimate); "
                                 "the legend gives disparities (px) and depths (mm)"));
  auto* layout = new QHBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->setSpacing(2);
  layout->addWidget(this->Left);
  layout->addWidget(this->Right);
  layout->addWidget(this->Disparity);
}

qTissueMosaicVideoPanel::~qTissueMosaicVideoPanel() = default;

QImage qTissueMosaicVideoPanel::toQImage(const cv::Mat& image) {
  if (image.empty() || image.depth() != CV_8U) return QImage();
  cv::Mat rgb;
  switch (image.channels()) {
    case 1: cv::cvtColor(image, rgb, cv::COLOR_GRAY2RGB); break;
    case 3: cv::cvtColor(image, rgb, cv::COLOR_BGR2RGB); break;
    case 4: cv::cvtColor(image, rgb, cv::COLOR_BGRA2RGB); break;
    default: return QImage();
  }
  // QImage does not own rgb's pixels: copy before rgb goes away.
  return QImage(rgb.data, rgb.cols, rgb.rows, static_cast<int>(rgb.step), QImage::Format_RGB888).copy();
}

void qTissueMosaicVideoPanel::setFrames(const cv::Mat& leftBgr, const cv::Mat& rightBgr, const cv::Mat& disparityPx,
                                        const tissuemosaic::RectifiedGeometry* geometry, double fallbackLowPx,
                                        double fallbackHighPx) {
  this->Left->setImage(leftBgr);
  this->Right->setImage(rightBgr);
  this->Disparity->setDisparity(disparityPx, geometry, fallbackLowPx, fallbackHighPx);
}

void qTissueMosaicVideoPanel::clear() {
  this->Left->clear();
  this->Right->clear();
  this->Disparity->clear();
}

QImage qTissueMosaicVideoPanel::leftImage() const { return this->Left->image(); }
QImage qTissueMosaicVideoPanel::rightImage() const { return this->Right->image(); }
QImage qTissueMosaicVideoPanel::disparityImage() const { return this->Disparity->image(); }
QSize qTissueMosaicVideoPanel::frameSize() const { return this->Left->sourceSize(); }
QStringList qTissueMosaicVideoPanel::disparityLegend() const { return this->Disparity->legendLabels(); }
