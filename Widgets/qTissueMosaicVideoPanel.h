#pragma once
/// @class qTissueMosaicVideoPanel
/// @brief The live video of a reconstruction: the rectified left and right frames and the left-view disparity
/// (false colour), side by side, each scaled to fit with its aspect ratio kept.
#include <opencv2/core.hpp>

#include <QImage>
#include <QWidget>

class QLabel;
class qTissueMosaicImageView;

class qTissueMosaicVideoPanel : public QWidget {
  Q_OBJECT
public:
  explicit qTissueMosaicVideoPanel(QWidget* parent = nullptr);
  ~qTissueMosaicVideoPanel() override;

  /// Shows new frames: 8-bit BGR (or grey) images; the disparity already in colour (e.g.
  /// vtkTissueMosaicReconstructionLogic::GetDisparityColorImage). Empty images show "no image". Copies the pixels.
  void setFrames(const cv::Mat& leftBgr, const cv::Mat& rightBgr, const cv::Mat& disparityBgr);
  void clear();

  /// What is shown now (null images when empty).
  QImage leftImage() const;
  QImage rightImage() const;
  QImage disparityImage() const;

  /// An 8-bit BGR, BGRA or grey cv::Mat as a QImage (RGB888, a copy); a null image when empty or another type.
  static QImage toQImage(const cv::Mat& image);

private:
  qTissueMosaicImageView* Left;
  qTissueMosaicImageView* Right;
  qTissueMosaicImageView* Disparity;
};

/// One image scaled to fit (aspect kept), with a caption; grey text when there is no image.
class qTissueMosaicImageView : public QWidget {
  Q_OBJECT
public:
  qTissueMosaicImageView(const QString& caption, QWidget* parent = nullptr);
  void setImage(const QImage& image);
  const QImage& image() const { return this->Image; }
  QSize sizeHint() const override { return QSize(320, 200); }

protected:
  void paintEvent(QPaintEvent* event) override;

private:
  QString Caption;
  QImage Image;
};
