#pragma once
/// @class qTissueMosaicVideoPanel
/// @brief The live video of a reconstruction: the rectified left and right frames and the left-view disparity in
/// false colour with its legend (disparity in px and depth in mm; hovering a pixel shows its own), side by side,
/// each scaled to fit with its aspect ratio kept.
///
/// Frames are reduced to the size they are shown at when they arrive (cv::resize into buffers kept from frame to
/// frame), so that a 1280x1024 video costs the GUI thread a few small copies per frame instead of three full-size
/// conversions and smooth scalings at every repaint; the disparity is coloured after the reduction.
#include <opencv2/core.hpp>

#include <QImage>
#include <QWidget>

namespace tissuemosaic {
struct RectifiedGeometry;
}

class qTissueMosaicImageView;

class qTissueMosaicVideoPanel : public QWidget {
  Q_OBJECT
public:
  explicit qTissueMosaicVideoPanel(QWidget* parent = nullptr);
  ~qTissueMosaicVideoPanel() override;

  /// Shows new frames: 8-bit BGR (or grey) images and the left-view disparity (CV_32F px, NaN = no estimate).
  /// `geometry` (may be null) turns disparities into depths for the legend; the disparity range of a map without
  /// any estimate is [fallbackLowPx, fallbackHighPx]. Empty images show "no image".
  void setFrames(const cv::Mat& leftBgr, const cv::Mat& rightBgr, const cv::Mat& disparityPx,
                 const tissuemosaic::RectifiedGeometry* geometry = nullptr, double fallbackLowPx = 0,
                 double fallbackHighPx = 1);
  void clear();

  /// What is shown now, as displayed (reduced to the view; null images when empty), and the frames' own size.
  QImage leftImage() const;
  QImage rightImage() const;
  QImage disparityImage() const;
  QSize frameSize() const;
  /// The disparity legend's tick labels, e.g. {"20 px = 101 mm", ...} (empty without a disparity).
  QStringList disparityLegend() const;

  /// An 8-bit BGR, BGRA or grey cv::Mat as a QImage (RGB888, a copy); a null image when empty or another type.
  static QImage toQImage(const cv::Mat& image);

private:
  qTissueMosaicImageView* Left;
  qTissueMosaicImageView* Right;
  qTissueMosaicImageView* Disparity;
};

/// One image scaled to fit (aspect kept), with a caption; grey text when there is no image. The disparity view
/// also draws its legend and shows the disparity and depth under the cursor.
class qTissueMosaicImageView : public QWidget {
  Q_OBJECT
public:
  qTissueMosaicImageView(const QString& caption, QWidget* parent = nullptr);
  /// Reduces `image` (8-bit BGR or grey) to the view's size when it is larger and shows it.
  void setImage(const cv::Mat& image);
  /// Reduces `disparityPx` to the view's size, colours it and shows it with a legend.
  void setDisparity(const cv::Mat& disparityPx, const tissuemosaic::RectifiedGeometry* geometry, double fallbackLowPx,
                    double fallbackHighPx);
  void clear();
  const QImage& image() const { return this->Image; }
  QSize sourceSize() const { return this->SourceSize; }
  QStringList legendLabels() const;
  QSize sizeHint() const override { return QSize(320, 200); }

protected:
  void paintEvent(QPaintEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;

private:
  /// The area the image is drawn in (left of the legend, when there is one).
  QRect imageArea() const;
  /// The size `source` is reduced to (its own when it fits the view).
  cv::Size shownSize(const cv::Size& source) const;
  void wrap(const cv::Mat& rgb);

  QString Caption;
  QSize SourceSize;
  cv::Mat Reduced;          ///< the source reduced to the view (BGR/grey), kept between frames
  cv::Mat Rgb;              ///< what Image shows (its pixels)
  QImage Image;
  // Disparity only.
  bool HasLegend = false;
  cv::Mat ReducedDisparityPx;
  double LowPx = 0, HighPx = 1;
  double FocalPx = 0, BaselineMm = 0, DoffsPx = 0;  ///< 0: no depth
};
