#include "qTissueMosaicRegistrationResults.h"

#include "qTissueMosaicHistogramPlot.h"
#include "qTissueMosaicMessageLine.h"
#include "qTissueMosaicWheelGuard.h"
#include "vtkTissueMosaicRegistrationLogic.h"

#include <QCheckBox>
#include <QDoubleSpinBox>
#include <QFontDatabase>
#include <QGridLayout>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QVBoxLayout>

#include <cmath>

qTissueMosaicRegistrationResults::qTissueMosaicRegistrationResults(QWidget* parent)
    : QGroupBox(tr("Results"), parent) {
  auto* layout = new QVBoxLayout(this);
  this->Notice = new qTissueMosaicMessageLine(this);
  this->Notice->setObjectName("resultsNotice");
  layout->addWidget(this->Notice);

  // Two columns of "name value": the ten numbers in five rows.
  auto* grid = new QGridLayout;
  const std::pair<const char*, const char*> rows[] = {
      {"landmarkRmse", "Landmark RMSE"}, {"scale", "Scale"},
      {"icpIterations", "ICP steps"},    {"icpInlierRmse", "ICP inlier RMSE"},
      {"points", "Model points"},        {"rmse", "Distance RMSE"},
      {"mean", "Mean"},                  {"median", "Median"},
      {"p95", "95th percentile"},        {"max", "Max"}};
  int index = 0;
  for (const auto& [name, title] : rows) {
    auto* value = new QLabel("-", this);
    value->setObjectName(QString(name) + "Value");
    value->setTextInteractionFlags(Qt::TextSelectableByMouse);
    this->Numbers.insert(name, value);
    const int row = index / 2, column = 2 * (index % 2);
    grid->addWidget(new QLabel(tr(title), this), row, column);
    grid->addWidget(value, row, column + 1);
    ++index;
  }
  grid->setColumnStretch(1, 1);
  grid->setColumnStretch(3, 1);
  layout->addLayout(grid);
  auto* units = new QLabel(tr("Distances in mm; landmark RMSE under the current transform."), this);
  units->setWordWrap(true);
  layout->addWidget(units);

  layout->addWidget(new QLabel(tr("Transform model -> CT/MR (LPS):"), this));
  this->Transform = new QLabel(this);
  this->Transform->setObjectName("transformLabel");
  this->Transform->setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
  this->Transform->setTextInteractionFlags(Qt::TextSelectableByMouse);
  this->Transform->setToolTip(tr("T_target_model: model (LPS mm) -> CT/MR (LPS mm)"));
  layout->addWidget(this->Transform);

  auto* colourRow = new QHBoxLayout;
  this->ColourByDistance = new QCheckBox(tr("Colour model by distance"), this);
  this->ColourByDistance->setObjectName("colourByDistanceCheckBox");
  this->ColourByDistance->setChecked(true);
  this->BinWidth = new QDoubleSpinBox(this);
  this->BinWidth->setObjectName("binWidthSpinBox");
  this->BinWidth->setRange(0.01, 10);
  this->BinWidth->setSingleStep(0.05);
  this->BinWidth->setValue(0.1);
  this->BinWidth->setPrefix(tr("bin "));
  this->BinWidth->setSuffix(" mm");
  tissuemosaic::widgets::guardWheel(this->BinWidth);
  colourRow->addWidget(this->ColourByDistance);
  colourRow->addStretch(1);
  colourRow->addWidget(this->BinWidth);
  layout->addLayout(colourRow);
  this->Histogram = new qTissueMosaicHistogramPlot(this);
  this->Histogram->setObjectName("histogramPlot");
  layout->addWidget(this->Histogram);
  auto* update = new QPushButton(tr("Update distances"), this);
  update->setObjectName("updateDistancesButton");
  update->setToolTip(tr("Recompute the distances of the current model (after the reconstruction grew)"));
  layout->addWidget(update);

  connect(this->ColourByDistance, &QCheckBox::toggled, this, &qTissueMosaicRegistrationResults::colourByDistanceToggled);
  connect(this->BinWidth, QOverload<double>::of(&QDoubleSpinBox::valueChanged), this,
          &qTissueMosaicRegistrationResults::binWidthChanged);
  connect(update, &QPushButton::clicked, this, &qTissueMosaicRegistrationResults::updateDistancesRequested);
}

void qTissueMosaicRegistrationResults::showResults(vtkTissueMosaicRegistrationLogic* logic) {
  const auto& landmarks = logic->GetLandmarkRegistration();
  const auto& icp = logic->GetIcpResult();
  const bool evaluated = logic->HasEvaluation();
  const tissuemosaic::DistanceStatistics& statistics = logic->GetDistanceStatistics();
  const auto number = [](double value) { return QString::number(value, 'f', 3); };
  const QString none = "-";
  // Under the current transform: after ICP the landmark fit's own RMSE would no longer describe the pairs.
  const double landmarkRmse = logic->GetCurrentLandmarkRmseMm();
  this->Numbers["landmarkRmse"]->setText(logic->HasRegistration() && std::isfinite(landmarkRmse) ? number(landmarkRmse)
                                                                                                 : none);
  this->Numbers["scale"]->setText(landmarks ? QString::number(landmarks->scale, 'f', 5) : none);
  this->Numbers["icpIterations"]->setText(
      icp ? QStringLiteral("%1 (%2)").arg(icp->iterations).arg(icp->converged ? tr("converged") : tr("limit")) : none);
  this->Numbers["icpIterations"]->setToolTip(
      icp ? (icp->converged ? tr("ICP converged") : tr("ICP stopped at the iteration limit")) : QString());
  this->Numbers["icpInlierRmse"]->setText(icp ? number(icp->inlierRmseMm) : none);
  this->Numbers["points"]->setText(evaluated ? QString::number(statistics.count) : none);
  this->Numbers["rmse"]->setText(evaluated ? number(statistics.rmseMm) : none);
  this->Numbers["mean"]->setText(evaluated ? number(statistics.meanMm) : none);
  this->Numbers["median"]->setText(evaluated ? number(statistics.medianMm) : none);
  this->Numbers["p95"]->setText(evaluated ? number(statistics.p95Mm) : none);
  this->Numbers["max"]->setText(evaluated ? number(statistics.maxMm) : none);

  const Eigen::Matrix4d& transform = logic->GetTargetFromModel();
  QStringList lines;
  for (int row = 0; row < 4; ++row) {
    lines << QStringLiteral("%1 %2 %3 %4")
                 .arg(transform(row, 0), 10, 'f', 5)
                 .arg(transform(row, 1), 10, 'f', 5)
                 .arg(transform(row, 2), 10, 'f', 5)
                 .arg(transform(row, 3), 10, 'f', 5);
  }
  this->Transform->setText(lines.join('\n'));

  QVector<double> percent;
  double overflowPercent = 0;
  const tissuemosaic::DistanceHistogram& histogram = logic->GetDistanceHistogram();
  if (evaluated && statistics.count > 0) {
    const double total = static_cast<double>(statistics.count);
    for (std::size_t count : histogram.counts) percent.push_back(100.0 * static_cast<double>(count) / total);
    overflowPercent = 100.0 * static_cast<double>(histogram.overflow) / total;
  }
  this->Histogram->setHistogram(percent, histogram.binWidthMm, statistics.meanMm, statistics.p95Mm, overflowPercent);
  {
    const QSignalBlocker blocker(this->BinWidth);
    this->BinWidth->setValue(logic->GetHistogramBinWidthMm());
  }
}

void qTissueMosaicRegistrationResults::setNotice(const QString& text) { this->Notice->showWarning(text); }

QString qTissueMosaicRegistrationResults::notice() const { return this->Notice->text(); }

QString qTissueMosaicRegistrationResults::number(const QString& name) const {
  const QLabel* label = this->Numbers.value(name, nullptr);
  return label ? label->text() : QString();
}

QString qTissueMosaicRegistrationResults::transformText() const { return this->Transform->text(); }
