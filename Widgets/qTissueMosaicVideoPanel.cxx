#include "qTissueMosaicVideoPanel.h"

#include <opencv2/imgproc.hpp>

#include <QHBoxLayout>
#include <QPainter>

qTissueMosaicImageView::qTissueMosaicImageView(const QString& caption, QWidget* parent)
    : QWidget(parent), Caption(caption) {
  this->setMinimumSize(120, 80);
  this->setSizePolicy(QSizePolicy::Expanding, QSizePolicy::Expanding);
}

void qTissueMosaicImageView::setImage(const QImage& image) {
  this->Image = image;
  this->update();
}

void qTissueMosaicImageView::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  painter.fillRect(this->rect(), QColor(20, 22, 28));
  const QRect area = this->rect().adjusted(2, 2, -2, -2);
  if (!this->Image.isNull()) {
    QSize size = this->Image.size();
    size.scale(area.size(), Qt::KeepAspectRatio);
    const QRect target(area.x() + (area.width() - size.width()) / 2, area.y() + (area.height() - size.height()) / 2,
                       size.width(), size.height());
    painter.setRenderHint(QPainter::SmoothPixmapTransform);
    painter.drawImage(target, this->Image);
  } else {
    painter.setPen(QColor(120, 120, 130));
    painter.drawText(area, Qt::AlignCenter, tr("no image"));
  }
  // Caption on a dark band, readable over any image.
  const QRect band(area.x(), area.y(), painter.fontMetrics().horizontalAdvance(this->Caption) + 12,
                   painter.fontMetrics().height() + 4);
  painter.fillRect(band, QColor(0, 0, 0, 150));
  painter.setPen(Qt::white);
  painter.drawText(band, Qt::AlignCenter, this->Caption);
}

qTissueMosaicVideoPanel::qTissueMosaicVideoPanel(QWidget* parent)
    : QWidget(parent),
      Left(new qTissueMosaicImageView(tr("Left (rectified)"), this)),
      Right(new qTissueMosaicImageView(tr("Right (rectified)"), this)),
      Disparity(new qTissueMosaicImageView(tr("Disparity"), this)) {
  this->Left->setObjectName("leftImageView");
  this->Right->setObjectName("rightImageView");
  this->Disparity->setObjectName("disparityImageView");
  this->Disparity->setToolTip(tr("Left-view disparity in false colour (blue: far, red: near; black: no estimate)"));
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

void qTissueMosaicVideoPanel::setFrames(const cv::Mat& leftBgr, const cv::Mat& rightBgr, const cv::Mat& disparityBgr) {
  this->Left->setImage(toQImage(leftBgr));
  this->Right->setImage(toQImage(rightBgr));
  this->Disparity->setImage(toQImage(disparityBgr));
}

void qTissueMosaicVideoPanel::clear() { this->setFrames(cv::Mat(), cv::Mat(), cv::Mat()); }

QImage qTissueMosaicVideoPanel::leftImage() const { return this->Left->image(); }
QImage qTissueMosaicVideoPanel::rightImage() const { return this->Right->image(); }
QImage qTissueMosaicVideoPanel::disparityImage() const { return this->Disparity->image(); }
