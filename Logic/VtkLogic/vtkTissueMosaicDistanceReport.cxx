#include "vtkTissueMosaicDistanceReport.h"

#include "IO/AtomicFile.h"
#include "Core/Error.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vtkFloatArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>

namespace tissuemosaic {

namespace {

std::string fixed(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof(text), "%.*f", digits, value);
  return text;
}

/// A "nice" tick step (1, 2 or 5 times a power of ten) giving about `ticks` ticks over `range`.
double niceStep(double range, int ticks) {
  const double raw = range / ticks;
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0}) {
    if (factor * power >= raw) return factor * power;
  }
  return 10 * power;
}

int digitsFor(double step) { return std::max(0, static_cast<int>(std::ceil(-std::log10(step) - 1e-9))); }

}  // namespace

void writeDistanceCsv(const std::string& path, const std::vector<Eigen::Vector3d>& pointsLps,
                      const std::vector<double>& distancesMm, const std::vector<double>& signedDistancesMm) {
  require(pointsLps.size() == distancesMm.size() && distancesMm.size() == signedDistancesMm.size(),
          "distance report: one distance per point is needed");
  writeStreamAtomically(path, "distance report", [&](std::ostream& file) {
    file << "index,x_mm,y_mm,z_mm,distance_mm,signed_distance_mm\n" << std::setprecision(9);
    for (std::size_t i = 0; i < pointsLps.size(); ++i) {
      file << i << ',' << pointsLps[i].x() << ',' << pointsLps[i].y() << ',' << pointsLps[i].z() << ','
           << distancesMm[i] << ',' << signedDistancesMm[i] << '\n';
    }
  });
}

void addDistanceArrays(vtkPolyData* polyData, const std::vector<double>& distancesMm,
                       const std::vector<double>& signedDistancesMm) {
  const auto n = static_cast<std::size_t>(polyData->GetNumberOfPoints());
  require(distancesMm.size() == n && signedDistancesMm.size() == n, "distance map: one distance per point is needed");
  vtkNew<vtkFloatArray> distances, signedDistances;
  distances->SetName(kDistanceArrayName);
  signedDistances->SetName(kSignedDistanceArrayName);
  distances->SetNumberOfTuples(static_cast<vtkIdType>(n));
  signedDistances->SetNumberOfTuples(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i) {
    distances->SetValue(static_cast<vtkIdType>(i), static_cast<float>(distancesMm[i]));
    signedDistances->SetValue(static_cast<vtkIdType>(i), static_cast<float>(signedDistancesMm[i]));
  }
  polyData->GetPointData()->AddArray(signedDistances);
  polyData->GetPointData()->SetScalars(distances);
}

void writeHistogramPng(const std::string& path, const DistanceHistogram& histogram,
                       const DistanceStatistics& statistics) {
  require(!histogram.counts.empty() && histogram.binWidthMm > 0, "the histogram is empty");
  const int width = 900, height = 560, left = 80, right = 30, top = 70, bottom = 70;
  const int plotWidth = width - left - right, plotHeight = height - top - bottom;
  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar black(0, 0, 0), grey(200, 200, 200), bar(180, 110, 40), meanColour(40, 160, 40),
      p95Colour(30, 30, 210);
  const int font = cv::FONT_HERSHEY_SIMPLEX;

  std::size_t total = histogram.overflow;
  for (std::size_t count : histogram.counts) total += count;
  const double rangeMm = histogram.binWidthMm * static_cast<double>(histogram.counts.size());
  double largestPercent = 0;
  for (std::size_t count : histogram.counts) {
    largestPercent = std::max(largestPercent, 100.0 * static_cast<double>(count) / static_cast<double>(std::max<std::size_t>(total, 1)));
  }
  const double yStep = niceStep(std::max(largestPercent, 1e-6), 5);
  const double yTop = std::ceil(largestPercent / yStep) * yStep + (largestPercent <= 0 ? yStep : 0);
  const auto xPixel = [&](double mm) { return left + static_cast<int>(std::lround(mm / rangeMm * plotWidth)); };
  const auto yPixel = [&](double percent) { return top + plotHeight - static_cast<int>(std::lround(percent / yTop * plotHeight)); };

  // Grid and y ticks.
  for (double percent = 0; percent <= yTop + 1e-9; percent += yStep) {
    cv::line(image, {left, yPixel(percent)}, {left + plotWidth, yPixel(percent)}, grey, 1);
    const std::string label = fixed(percent, digitsFor(yStep));
    cv::putText(image, label, {left - 10 - 9 * static_cast<int>(label.size()), yPixel(percent) + 5}, font, 0.45, black, 1,
                cv::LINE_AA);
  }
  // Bars.
  for (std::size_t i = 0; i < histogram.counts.size(); ++i) {
    const double percent = 100.0 * static_cast<double>(histogram.counts[i]) / static_cast<double>(std::max<std::size_t>(total, 1));
    const int x0 = xPixel(histogram.binWidthMm * static_cast<double>(i));
    const int x1 = xPixel(histogram.binWidthMm * static_cast<double>(i + 1));
    if (histogram.counts[i] > 0) {
      cv::rectangle(image, cv::Point(x0 + 1, yPixel(percent)), cv::Point(std::max(x0 + 1, x1 - 1), top + plotHeight),
                    bar, cv::FILLED);
    }
  }
  // Mean and 95th percentile markers.
  for (const auto& [valueMm, colour, name] : {std::tuple{statistics.meanMm, meanColour, "mean"},
                                             std::tuple{statistics.p95Mm, p95Colour, "p95"}}) {
    if (valueMm > rangeMm) continue;
    cv::line(image, {xPixel(valueMm), top}, {xPixel(valueMm), top + plotHeight}, colour, 2, cv::LINE_AA);
    cv::putText(image, name, {xPixel(valueMm) + 4, top + 15}, font, 0.45, colour, 1, cv::LINE_AA);
  }
  // Axes and x ticks.
  cv::line(image, {left, top + plotHeight}, {left + plotWidth, top + plotHeight}, black, 1);
  cv::line(image, {left, top}, {left, top + plotHeight}, black, 1);
  const double xStep = niceStep(rangeMm, 8);
  for (double mm = 0; mm <= rangeMm + 1e-9; mm += xStep) {
    cv::line(image, {xPixel(mm), top + plotHeight}, {xPixel(mm), top + plotHeight + 5}, black, 1);
    const std::string label = fixed(mm, digitsFor(xStep));
    cv::putText(image, label, {xPixel(mm) - 4 * static_cast<int>(label.size()), top + plotHeight + 22}, font, 0.45, black,
                1, cv::LINE_AA);
  }
  cv::putText(image, "distance to the target surface (mm)", {left + plotWidth / 2 - 150, height - 20}, font, 0.55,
              black, 1, cv::LINE_AA);
  cv::putText(image, "% of points", {10, top - 15}, font, 0.5, black, 1, cv::LINE_AA);
  const std::string title = "RMSE " + fixed(statistics.rmseMm, 3) + " mm   mean " + fixed(statistics.meanMm, 3) +
                            "   median " + fixed(statistics.medianMm, 3) + "   p95 " + fixed(statistics.p95Mm, 3) +
                            "   max " + fixed(statistics.maxMm, 3) + "   (" + std::to_string(statistics.count) + " points)";
  cv::putText(image, title, {left, 28}, font, 0.5, black, 1, cv::LINE_AA);
  if (histogram.overflow > 0) {
    cv::putText(image, std::to_string(histogram.overflow) + " points beyond " + fixed(rangeMm, 2) + " mm not shown",
                {left + plotWidth - 300, top - 15}, font, 0.45, p95Colour, 1, cv::LINE_AA);
  }
  writeFileAtomically(path, "histogram plot", [&](const std::string& temporaryPath) {
    try {
      return cv::imwrite(temporaryPath, image);
    } catch (const cv::Exception& error) {
      throw Error("cannot write histogram plot '" + path + "': " + error.err);  // not OpenCV's file and line
    }
  });
}

}  // namespace tissuemosaic
