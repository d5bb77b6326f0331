#include "qTissueMosaicRegistrationWidget.h"

#include "vtkTissueMosaicDistanceReport.h"
#include "vtkTissueMosaicRegistrationLogic.h"

#include <Eigen/LU>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCellPicker.h>
#include <vtkDataArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkGlyph3DMapper.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkLabeledDataMapper.h>
#include <vtkLookupTable.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkObjectFactory.h>
#include <vtkPointData.h>
#include <vtkPointPicker.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindowInteractor.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSphereSource.h>
#include <vtkStringArray.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>
#include <vtkVertexGlyphFilter.h>

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QFontDatabase>
#include <QFormLayout>
#include <QGridLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMap>
#include <QPainter>
#include <QPushButton>
#include <QRegularExpression>
#include <QScrollArea>
#include <QSignalBlocker>
#include <QSpinBox>
#include <QSplitter>
#include <QTableWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>

namespace {

using tissuemosaic::ModelFrameChoice;

/// The distance histogram as a bar chart (x: distance in mm, y: share of the points in %), with the mean and the
/// 95th percentile marked, as the PNG that DistanceReport writes. Drawn with QPainter: a second OpenGL view
/// (vtkChartXY) would cost a context for a handful of bars.
class HistogramPlot : public QWidget {
public:
  explicit HistogramPlot(QWidget* parent) : QWidget(parent) { this->setMinimumSize(240, 160); }

  void setHistogram(QVector<double> percent, double binWidthMm, double meanMm, double p95Mm) {
    this->Percent = std::move(percent);
    this->BinWidthMm = binWidthMm;
    this->MeanMm = meanMm;
    this->P95Mm = p95Mm;
    this->update();
  }
  const QVector<double>& percent() const { return this->Percent; }
  double binWidthMm() const { return this->BinWidthMm; }

protected:
  void paintEvent(QPaintEvent*) override {
    QPainter painter(this);
    painter.fillRect(this->rect(), this->palette().base());
    const QFontMetrics metrics = painter.fontMetrics();
    const int left = metrics.horizontalAdvance("100%") + 8, bottom = 2 * metrics.height() + 4, top = 6, right = 10;
    const QRect plot(left, top, std::max(10, this->width() - left - right), std::max(10, this->height() - top - bottom));
    painter.setPen(this->palette().text().color());
    if (this->Percent.isEmpty()) {
      painter.drawText(this->rect(), Qt::AlignCenter, QStringLiteral("no distances yet"));
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
    const auto marker = [&](double mm, const QColor& colour, const QString& name) {
      if (!(mm >= 0 && mm <= rangeMm)) return;
      painter.setPen(QPen(colour, 2, Qt::DashLine));
      painter.drawLine(QPointF(xOf(mm), plot.top()), QPointF(xOf(mm), plot.bottom()));
      painter.drawText(QPointF(xOf(mm) + 3, plot.top() + metrics.ascent()), name);
    };
    marker(this->MeanMm, QColor(0, 150, 0), QStringLiteral("mean"));
    marker(this->P95Mm, QColor(200, 0, 0), QStringLiteral("p95"));
    painter.setPen(this->palette().text().color());
    painter.drawText(QRect(0, plot.top(), left - 4, metrics.height()), Qt::AlignRight,
                     QString::number(highest, 'f', 1) + "%");
    painter.drawText(QRect(0, plot.bottom() - metrics.height(), left - 4, metrics.height()), Qt::AlignRight, "0%");
    const int axisY = plot.bottom() + 2;
    painter.drawText(QRect(plot.left(), axisY, plot.width(), metrics.height()), Qt::AlignLeft, "0");
    painter.drawText(QRect(plot.left(), axisY, plot.width(), metrics.height()), Qt::AlignRight,
                     QString::number(rangeMm, 'g', 3));
    painter.drawText(QRect(plot.left(), axisY + metrics.height(), plot.width(), metrics.height()), Qt::AlignHCenter,
                     QStringLiteral("distance to the CT/MR surface (mm)"));
  }

private:
  QVector<double> Percent;
  double BinWidthMm = 0, MeanMm = 0, P95Mm = 0;
};

/// The usual trackball camera, plus: a left click that does not drag calls `Click` (picking). A style rather than
/// an interactor observer, because the style grabs the mouse focus on a press and then receives the release alone.
class ClickPickingStyle : public vtkInteractorStyleTrackballCamera {
public:
  static ClickPickingStyle* New();
  vtkTypeMacro(ClickPickingStyle, vtkInteractorStyleTrackballCamera);

  std::function<void(int displayX, int displayY)> Click;

  void OnLeftButtonDown() override {
    this->Interactor->GetEventPosition(this->PressPosition);
    this->Pressed = true;
    this->Superclass::OnLeftButtonDown();
  }
  void OnLeftButtonUp() override {
    this->Superclass::OnLeftButtonUp();
    int position[2];
    this->Interactor->GetEventPosition(position);
    // A click picks; a drag (it turned the camera) does not.
    const bool click = this->Pressed && std::abs(position[0] - this->PressPosition[0]) <= 3 &&
                       std::abs(position[1] - this->PressPosition[1]) <= 3;
    this->Pressed = false;
    if (click && this->Click) this->Click(position[0], position[1]);
  }

private:
  int PressPosition[2] = {0, 0};
  bool Pressed = false;
};
vtkStandardNewMacro(ClickPickingStyle);

QString pointText(const std::optional<Eigen::Vector3d>& point) {
  if (!point) return QString();
  return QStringLiteral("%1, %2, %3").arg(point->x(), 0, 'f', 2).arg(point->y(), 0, 'f', 2).arg(point->z(), 0, 'f', 2);
}

/// "x, y, z" (commas and/or spaces) as a point; false when it is not three finite numbers.
bool parsePoint(const QString& text, Eigen::Vector3d& point) {
  const QStringList words = text.split(QRegularExpression("[,;\\s]+"), Qt::SkipEmptyParts);
  if (words.size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    bool ok = false;
    point[i] = words[i].toDouble(&ok);
    if (!ok || !std::isfinite(point[i])) return false;
  }
  return true;
}

void setMatrix(vtkMatrix4x4* matrix, const Eigen::Matrix4d& transform) {
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 4; ++column) matrix->SetElement(row, column, transform(row, column));
  }
}

Eigen::Vector3d mapped(const Eigen::Matrix4d& transform, const Eigen::Vector3d& point) {
  return transform.topLeftCorner<3, 3>() * point + transform.topRightCorner<3, 1>();
}

/// Point scalars the renderer uses as colours as they are: 8-bit RGB(A) (our reconstructions' "RGB").
bool hasDirectColours(vtkPolyData* polyData) {
  vtkDataArray* scalars = polyData ? polyData->GetPointData()->GetScalars() : nullptr;
  return scalars && vtkUnsignedCharArray::SafeDownCast(scalars) &&
         (scalars->GetNumberOfComponents() == 3 || scalars->GetNumberOfComponents() == 4);
}

}  // namespace

class qTissueMosaicRegistrationWidgetPrivate {
  Q_DECLARE_PUBLIC(qTissueMosaicRegistrationWidget);

public:
  explicit qTissueMosaicRegistrationWidgetPrivate(qTissueMosaicRegistrationWidget& object) : q_ptr(&object) {}

  void setupUi();
  void setupScene();
  QGroupBox* modelsBox();
  QGroupBox* landmarksBox();
  QGroupBox* registrationBox();
  QGroupBox* resultsBox();
  QGroupBox* exportBox();

  /// Shows the logic's error text when a call failed (clears it otherwise); returns `ok`.
  bool report(bool ok);
  void render();
  void updateModelPipeline();
  void updateTargetPipeline();
  void updateTransform();
  void updateLandmarks();
  void updateTable();
  void updateResults();
  void updateDistanceColours();
  void resetCamera();
  void onTableItemChanged(QTableWidgetItem* item);
  void deleteSelectedRows();
  bool pickModel(int x, int y);
  bool pickTarget(int x, int y);
  /// A file dialog, then `action(path)`; nothing when cancelled.
  void withSaveFile(const QString& title, const QString& filter, const std::function<bool(const QString&)>& action);

  qTissueMosaicRegistrationWidget* q_ptr;
  vtkNew<vtkTissueMosaicRegistrationLogic> Logic;

  // 3D view: everything in the CT/MR model's frame; the model (and its landmarks) through ModelToTarget.
  QVTKOpenGLNativeWidget* View = nullptr;
  vtkNew<vtkGenericOpenGLRenderWindow> RenderWindow;
  vtkNew<vtkRenderer> Renderer;
  vtkNew<vtkMatrix4x4> ModelToTarget;
  vtkNew<vtkVertexGlyphFilter> ModelVertices;  ///< draws a model without cells as points
  vtkNew<vtkPolyDataMapper> ModelMapper;
  vtkNew<vtkActor> ModelActor;
  vtkNew<vtkPolyDataMapper> TargetMapper;
  vtkNew<vtkActor> TargetActor;
  vtkNew<vtkLookupTable> DistanceColours;
  vtkNew<vtkVertexGlyphFilter> DistanceVertices;
  vtkNew<vtkPolyDataMapper> DistanceMapper;
  vtkNew<vtkActor> DistanceActor;
  vtkNew<vtkScalarBarActor> ScalarBar;
  vtkNew<vtkSphereSource> Sphere;
  vtkNew<vtkPolyData> ModelLandmarkPoints;   ///< model frame
  vtkNew<vtkPolyData> TargetLandmarkPoints;  ///< CT/MR frame
  vtkNew<vtkGlyph3DMapper> ModelLandmarkMapper;
  vtkNew<vtkGlyph3DMapper> TargetLandmarkMapper;
  vtkNew<vtkActor> ModelLandmarkActor;
  vtkNew<vtkActor> TargetLandmarkActor;
  vtkNew<vtkPolyData> LabelPoints;
  vtkNew<vtkLabeledDataMapper> LabelMapper;
  vtkNew<vtkActor2D> LabelActor;
  vtkNew<vtkPointPicker> PointPicker;
  vtkNew<vtkCellPicker> CellPicker;
  vtkNew<ClickPickingStyle> InteractorStyle;
  qTissueMosaicRegistrationWidget::PickMode Mode = qTissueMosaicRegistrationWidget::PickNone;

  // Controls
  QComboBox* ModelFrame = nullptr;
  QComboBox* TargetFrame = nullptr;
  QLabel* ModelInfo = nullptr;
  QLabel* TargetInfo = nullptr;
  QPushButton* PickModelButton = nullptr;
  QPushButton* PickTargetButton = nullptr;
  QTableWidget* Table = nullptr;
  QCheckBox* Scale = nullptr;
  QSpinBox* IcpIterations = nullptr;
  QDoubleSpinBox* IcpInlierFraction = nullptr;
  QDoubleSpinBox* IcpMaxDistance = nullptr;
  QDoubleSpinBox* BinWidth = nullptr;
  QMap<QString, QLabel*> Numbers;
  QLabel* TransformLabel = nullptr;
  QCheckBox* ColourByDistance = nullptr;
  HistogramPlot* Histogram = nullptr;
  QLabel* Status = nullptr;
  bool UpdatingTable = false;
};

// ---- construction -----------------------------------------------------------------------------------------------

void qTissueMosaicRegistrationWidgetPrivate::setupUi() {
  Q_Q(qTissueMosaicRegistrationWidget);
  this->View = new QVTKOpenGLNativeWidget(q);
  this->View->setObjectName("registrationView");
  this->View->setMinimumSize(320, 240);
  this->View->setRenderWindow(this->RenderWindow);

  auto* controls = new QWidget;
  auto* column = new QVBoxLayout(controls);
  column->addWidget(this->modelsBox());
  column->addWidget(this->landmarksBox());
  column->addWidget(this->registrationBox());
  column->addWidget(this->resultsBox());
  column->addWidget(this->exportBox());
  this->Status = new QLabel;
  this->Status->setObjectName("statusLabel");
  this->Status->setWordWrap(true);
  this->Status->setStyleSheet("color: #c00000");
  column->addWidget(this->Status);
  column->addStretch(1);
  auto* scroll = new QScrollArea;
  scroll->setWidget(controls);
  scroll->setWidgetResizable(true);
  scroll->setMinimumWidth(controls->sizeHint().width() + 20);

  auto* splitter = new QSplitter(Qt::Horizontal);
  splitter->addWidget(this->View);
  splitter->addWidget(scroll);
  splitter->setStretchFactor(0, 1);
  auto* layout = new QHBoxLayout(q);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(splitter);
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::modelsBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  auto* box = new QGroupBox(QObject::tr("Models"));
  auto* grid = new QGridLayout(box);
  const auto frameCombo = [](const char* name) {
    auto* combo = new QComboBox;
    combo->setObjectName(name);
    combo->addItem(QObject::tr("frame from file"), static_cast<int>(ModelFrameChoice::FromFile));
    combo->addItem("LPS", static_cast<int>(ModelFrameChoice::LPS));
    combo->addItem("RAS", static_cast<int>(ModelFrameChoice::RAS));
    combo->setToolTip(QObject::tr("Frame of the file's coordinates: what the file declares (Slicer's SPACE mark; "
                                  "LPS when it declares none), or LPS / RAS explicitly."));
    return combo;
  };
  auto* loadModel = new QPushButton(QObject::tr("Load model..."));
  loadModel->setToolTip(QObject::tr("The reconstructed model (.ply .vtp .vtk .stl .obj)"));
  this->ModelFrame = frameCombo("modelFrameCombo");
  this->ModelInfo = new QLabel(QObject::tr("no model"));
  auto* loadTarget = new QPushButton(QObject::tr("Load CT/MR..."));
  loadTarget->setToolTip(QObject::tr("The CT/MR surface model, with triangles (.stl .vtp .vtk .ply .obj)"));
  this->TargetFrame = frameCombo("targetFrameCombo");
  this->TargetInfo = new QLabel(QObject::tr("no CT/MR model"));
  grid->addWidget(loadModel, 0, 0);
  grid->addWidget(this->ModelFrame, 0, 1);
  grid->addWidget(this->ModelInfo, 1, 0, 1, 2);
  grid->addWidget(loadTarget, 2, 0);
  grid->addWidget(this->TargetFrame, 2, 1);
  grid->addWidget(this->TargetInfo, 3, 0, 1, 2);
  const QString filter = QObject::tr("Surface models (*.ply *.vtp *.vtk *.stl *.obj)");
  QObject::connect(loadModel, &QPushButton::clicked, q, [q, filter] {
    const QString path = QFileDialog::getOpenFileName(q, QObject::tr("Load the reconstructed model"), QString(), filter);
    if (!path.isEmpty()) q->loadModelFile(path);
  });
  QObject::connect(loadTarget, &QPushButton::clicked, q, [q, filter] {
    const QString path = QFileDialog::getOpenFileName(q, QObject::tr("Load the CT/MR model"), QString(), filter);
    if (!path.isEmpty()) q->loadTargetFile(path);
  });
  return box;
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::landmarksBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  auto* box = new QGroupBox(QObject::tr("Landmarks"));
  auto* layout = new QVBoxLayout(box);
  auto* pickRow = new QHBoxLayout;
  this->PickModelButton = new QPushButton(QObject::tr("Pick on model"));
  this->PickTargetButton = new QPushButton(QObject::tr("Pick on CT/MR"));
  for (QPushButton* button : {this->PickModelButton, this->PickTargetButton}) {
    button->setCheckable(true);
    button->setToolTip(QObject::tr("Then click in the 3D view (dragging still rotates). Each pick completes the "
                                   "first pair that lacks this point, or starts a new pair."));
    pickRow->addWidget(button);
  }
  layout->addLayout(pickRow);
  QObject::connect(this->PickModelButton, &QPushButton::toggled, q, [q](bool on) {
    if (on) q->setPickMode(qTissueMosaicRegistrationWidget::PickOnModel);
    else if (q->pickMode() == qTissueMosaicRegistrationWidget::PickOnModel) q->setPickMode(qTissueMosaicRegistrationWidget::PickNone);
  });
  QObject::connect(this->PickTargetButton, &QPushButton::toggled, q, [q](bool on) {
    if (on) q->setPickMode(qTissueMosaicRegistrationWidget::PickOnTarget);
    else if (q->pickMode() == qTissueMosaicRegistrationWidget::PickOnTarget) q->setPickMode(qTissueMosaicRegistrationWidget::PickNone);
  });

  this->Table = new QTableWidget(0, 4);
  this->Table->setObjectName("landmarkTable");
  this->Table->setHorizontalHeaderLabels({QObject::tr("Label"), QObject::tr("Model (LPS mm)"),
                                          QObject::tr("CT/MR (LPS mm)"), QObject::tr("Residual (mm)")});
  this->Table->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  this->Table->setSelectionBehavior(QAbstractItemView::SelectRows);
  this->Table->setToolTip(QObject::tr("Edit a label or a position (\"x, y, z\" in mm) by double-clicking it. "
                                      "Residual: distance between the CT/MR point and the model point moved by "
                                      "the current transform."));
  this->Table->setMinimumHeight(140);
  layout->addWidget(this->Table);
  QObject::connect(this->Table, &QTableWidget::itemChanged, q,
                   [this](QTableWidgetItem* item) { this->onTableItemChanged(item); });

  auto* buttons = new QHBoxLayout;
  auto* remove = new QPushButton(QObject::tr("Delete"));
  auto* clear = new QPushButton(QObject::tr("Clear"));
  auto* load = new QPushButton(QObject::tr("Load..."));
  load->setToolTip(QObject::tr("A .mrk.json with two lists, the model's then the CT/MR model's (as exported)"));
  buttons->addWidget(remove);
  buttons->addWidget(clear);
  buttons->addWidget(load);
  layout->addLayout(buttons);
  QObject::connect(remove, &QPushButton::clicked, q, [this] { this->deleteSelectedRows(); });
  QObject::connect(clear, &QPushButton::clicked, q, [this, q] {
    this->Logic->ClearLandmarks();
    this->updateLandmarks();
    emit q->landmarksChanged();
  });
  QObject::connect(load, &QPushButton::clicked, q, [q] {
    const QString path = QFileDialog::getOpenFileName(q, QObject::tr("Load landmark pairs"), QString(),
                                                      QObject::tr("Markups (*.mrk.json *.json)"));
    if (!path.isEmpty()) q->loadLandmarksFile(path);
  });
  return box;
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::registrationBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  const tissuemosaic::IcpParameters defaults;
  auto* box = new QGroupBox(QObject::tr("Registration"));
  auto* form = new QFormLayout(box);
  this->Scale = new QCheckBox(QObject::tr("with uniform scale"));
  this->Scale->setToolTip(QObject::tr("Similarity instead of rigid fit (the scale of the reconstruction is off)"));
  auto* registerButton = new QPushButton(QObject::tr("Register landmarks"));
  form->addRow(this->Scale, registerButton);
  this->IcpIterations = new QSpinBox;
  this->IcpIterations->setRange(1, 1000);
  this->IcpIterations->setValue(defaults.maxIterations);
  form->addRow(QObject::tr("ICP max iterations"), this->IcpIterations);
  this->IcpInlierFraction = new QDoubleSpinBox;
  this->IcpInlierFraction->setRange(0.05, 1.0);
  this->IcpInlierFraction->setSingleStep(0.05);
  this->IcpInlierFraction->setValue(defaults.inlierFraction);
  this->IcpInlierFraction->setToolTip(QObject::tr("Share of the closest correspondences used per step (trimmed "
                                                  "ICP), so that tissue the CT/MR model lacks does not pull"));
  form->addRow(QObject::tr("ICP inlier fraction"), this->IcpInlierFraction);
  this->IcpMaxDistance = new QDoubleSpinBox;
  this->IcpMaxDistance->setRange(0, 1000);
  this->IcpMaxDistance->setSuffix(" mm");
  this->IcpMaxDistance->setSpecialValueText(QObject::tr("no limit"));
  this->IcpMaxDistance->setToolTip(QObject::tr("Correspondences farther than this are never used"));
  form->addRow(QObject::tr("ICP max distance"), this->IcpMaxDistance);
  auto* icpButton = new QPushButton(QObject::tr("Refine with ICP"));
  form->addRow(icpButton);
  QObject::connect(registerButton, &QPushButton::clicked, q, [q] { q->registerLandmarks(); });
  QObject::connect(icpButton, &QPushButton::clicked, q, [q] { q->refineIcp(); });
  return box;
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::resultsBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  auto* box = new QGroupBox(QObject::tr("Results"));
  auto* layout = new QVBoxLayout(box);
  auto* form = new QFormLayout;
  const std::pair<const char*, const char*> rows[] = {
      {"landmarkRmse", "Landmark RMSE (mm)"}, {"scale", "Scale"},
      {"icpIterations", "ICP iterations"},    {"icpInlierRmse", "ICP inlier RMSE (mm)"},
      {"points", "Model points"},             {"rmse", "Distance RMSE (mm)"},
      {"mean", "Mean (mm)"},                  {"median", "Median (mm)"},
      {"p95", "95th percentile (mm)"},        {"max", "Max (mm)"}};
  for (const auto& [name, title] : rows) {
    auto* label = new QLabel("-");
    label->setObjectName(QString(name) + "Value");
    label->setTextInteractionFlags(Qt::TextSelectableByMouse);
    this->Numbers.insert(name, label);
    form->addRow(QObject::tr(title), label);
  }
  layout->addLayout(form);
  this->TransformLabel = new QLabel;
  this->TransformLabel->setObjectName("transformLabel");
  this->TransformLabel->setFont(QFontDatabase::systemFont(QFontDatabase::FixedFont));
  this->TransformLabel->setTextInteractionFlags(Qt::TextSelectableByMouse);
  this->TransformLabel->setToolTip(QObject::tr("T_target_model: model (LPS mm) -> CT/MR (LPS mm)"));
  layout->addWidget(new QLabel(QObject::tr("Transform model -> CT/MR (LPS):")));
  layout->addWidget(this->TransformLabel);
  auto* colourRow = new QHBoxLayout;
  this->ColourByDistance = new QCheckBox(QObject::tr("Colour model by distance"));
  this->ColourByDistance->setChecked(true);
  this->BinWidth = new QDoubleSpinBox;
  this->BinWidth->setObjectName("binWidthSpinBox");
  this->BinWidth->setRange(0.01, 10);
  this->BinWidth->setSingleStep(0.05);
  this->BinWidth->setValue(this->Logic->GetHistogramBinWidthMm());
  this->BinWidth->setPrefix(QObject::tr("bin "));
  this->BinWidth->setSuffix(" mm");
  colourRow->addWidget(this->ColourByDistance);
  colourRow->addWidget(this->BinWidth);
  layout->addLayout(colourRow);
  this->Histogram = new HistogramPlot(box);
  this->Histogram->setObjectName("histogramPlot");
  layout->addWidget(this->Histogram);
  QObject::connect(this->ColourByDistance, &QCheckBox::toggled, q, [this] {
    this->updateDistanceColours();
    this->render();
  });
  QObject::connect(this->BinWidth, QOverload<double>::of(&QDoubleSpinBox::valueChanged), q, [this](double mm) {
    this->report(this->Logic->SetHistogramBinWidthMm(mm));
    this->updateResults();
  });
  auto* update = new QPushButton(QObject::tr("Update distances"));
  update->setToolTip(QObject::tr("Recompute the distances of the current model (after the reconstruction grew)"));
  layout->addWidget(update);
  QObject::connect(update, &QPushButton::clicked, q, [q] { q->updateDistances(); });
  return box;
}

QGroupBox* qTissueMosaicRegistrationWidgetPrivate::exportBox() {
  Q_Q(qTissueMosaicRegistrationWidget);
  auto* box = new QGroupBox(QObject::tr("Export"));
  auto* grid = new QGridLayout(box);
  auto* transform = new QPushButton(QObject::tr("Transform (.tfm)..."));
  transform->setToolTip(QObject::tr("ITK transform for Slicer: holds CT/MR -> model (the resampling convention); "
                                    "put the model under it in Slicer to move it onto the CT/MR model"));
  auto* model = new QPushButton(QObject::tr("Registered model..."));
  auto* landmarks = new QPushButton(QObject::tr("Landmarks (.mrk.json)..."));
  auto* distances = new QPushButton(QObject::tr("Distance report (CSV + PNG)..."));
  grid->addWidget(transform, 0, 0);
  grid->addWidget(model, 0, 1);
  grid->addWidget(landmarks, 1, 0);
  grid->addWidget(distances, 1, 1);
  QObject::connect(transform, &QPushButton::clicked, q, [this, q] {
    this->withSaveFile(QObject::tr("Save the transform"), QObject::tr("ITK transform (*.tfm)"),
                       [q](const QString& path) { return q->exportTransform(path); });
  });
  QObject::connect(model, &QPushButton::clicked, q, [this, q] {
    this->withSaveFile(QObject::tr("Save the registered model"), QObject::tr("Models (*.vtp *.ply *.vtk)"),
                       [q](const QString& path) { return q->exportRegisteredModel(path); });
  });
  QObject::connect(landmarks, &QPushButton::clicked, q, [this, q] {
    this->withSaveFile(QObject::tr("Save the landmark pairs"), QObject::tr("Markups (*.mrk.json)"),
                       [q](const QString& path) { return q->exportLandmarks(path); });
  });
  QObject::connect(distances, &QPushButton::clicked, q, [this, q] {
    this->withSaveFile(QObject::tr("Save the distance report (the PNG plot goes next to it)"),
                       QObject::tr("CSV (*.csv)"), [q](const QString& path) {
                         const QFileInfo csv(path);
                         const QString png = csv.dir().filePath(csv.completeBaseName() + ".png");
                         return q->exportDistanceReport(path, png);
                       });
  });
  return box;
}

void qTissueMosaicRegistrationWidgetPrivate::setupScene() {
  this->RenderWindow->AddRenderer(this->Renderer);
  this->Renderer->SetBackground(0.12, 0.13, 0.16);

  this->ModelMapper->SetInputConnection(this->ModelVertices->GetOutputPort());
  this->ModelActor->SetMapper(this->ModelMapper);
  this->ModelActor->SetUserMatrix(this->ModelToTarget);
  this->ModelActor->GetProperty()->SetPointSize(3);
  this->ModelActor->GetProperty()->SetColor(0.95, 0.6, 0.45);
  this->ModelActor->VisibilityOff();

  this->TargetActor->SetMapper(this->TargetMapper);
  this->TargetActor->GetProperty()->SetColor(0.9, 0.86, 0.75);
  this->TargetActor->GetProperty()->SetOpacity(0.5);
  this->TargetMapper->ScalarVisibilityOff();
  this->TargetActor->VisibilityOff();

  // Blue (on the surface) to red (far from it).
  this->DistanceColours->SetHueRange(0.667, 0.0);
  this->DistanceColours->Build();
  this->DistanceMapper->SetLookupTable(this->DistanceColours);
  this->DistanceMapper->UseLookupTableScalarRangeOn();
  this->DistanceMapper->SetScalarModeToUsePointFieldData();
  this->DistanceMapper->SelectColorArray(tissuemosaic::kDistanceArrayName);
  this->DistanceMapper->ScalarVisibilityOn();
  this->DistanceActor->SetMapper(this->DistanceMapper);
  this->DistanceActor->GetProperty()->SetPointSize(3);
  this->DistanceActor->VisibilityOff();
  this->ScalarBar->SetLookupTable(this->DistanceColours);
  this->ScalarBar->SetTitle("distance (mm)");
  this->ScalarBar->SetNumberOfLabels(5);
  this->ScalarBar->SetPosition(0.86, 0.1);
  this->ScalarBar->SetWidth(0.12);
  this->ScalarBar->SetHeight(0.8);
  this->ScalarBar->SetMaximumWidthInPixels(90);
  this->ScalarBar->UnconstrainedFontSizeOn();
  this->ScalarBar->GetTitleTextProperty()->SetFontSize(14);
  this->ScalarBar->GetLabelTextProperty()->SetFontSize(12);
  this->ScalarBar->VisibilityOff();

  this->Sphere->SetRadius(1.0);
  this->Sphere->SetThetaResolution(16);
  this->Sphere->SetPhiResolution(16);
  for (auto [mapper, points] : {std::pair{this->ModelLandmarkMapper.Get(), this->ModelLandmarkPoints.Get()},
                                std::pair{this->TargetLandmarkMapper.Get(), this->TargetLandmarkPoints.Get()}}) {
    points->SetPoints(vtkNew<vtkPoints>());
    mapper->SetInputData(points);
    mapper->SetSourceConnection(this->Sphere->GetOutputPort());
    mapper->ScalingOff();
    mapper->ScalarVisibilityOff();
  }
  this->ModelLandmarkActor->SetMapper(this->ModelLandmarkMapper);
  this->ModelLandmarkActor->SetUserMatrix(this->ModelToTarget);
  this->ModelLandmarkActor->GetProperty()->SetColor(1.0, 0.85, 0.1);
  this->ModelLandmarkActor->PickableOff();
  this->TargetLandmarkActor->SetMapper(this->TargetLandmarkMapper);
  this->TargetLandmarkActor->GetProperty()->SetColor(0.2, 0.9, 0.3);
  this->TargetLandmarkActor->PickableOff();

  this->LabelPoints->SetPoints(vtkNew<vtkPoints>());
  this->LabelMapper->SetInputData(this->LabelPoints);
  this->LabelMapper->SetLabelModeToLabelFieldData();
  this->LabelMapper->SetFieldDataName("label");
  this->LabelMapper->GetLabelTextProperty()->SetFontSize(14);
  this->LabelMapper->GetLabelTextProperty()->SetColor(1, 1, 1);
  this->LabelActor->SetMapper(this->LabelMapper);
  this->LabelActor->PickableOff();

  for (vtkActor* actor : {this->ModelActor.Get(), this->TargetActor.Get(), this->DistanceActor.Get(),
                          this->ModelLandmarkActor.Get(), this->TargetLandmarkActor.Get()}) {
    this->Renderer->AddActor(actor);
  }
  this->Renderer->AddActor2D(this->ScalarBar);
  this->Renderer->AddActor2D(this->LabelActor);

  this->PointPicker->PickFromListOn();
  this->PointPicker->AddPickList(this->ModelActor);
  this->PointPicker->AddPickList(this->DistanceActor);
  this->PointPicker->SetTolerance(0.005);  // fraction of the window diagonal

  this->InteractorStyle->Click = [this](int x, int y) {
    Q_Q(qTissueMosaicRegistrationWidget);
    if (this->Mode != qTissueMosaicRegistrationWidget::PickNone) q->pickAt(x, y);
  };
  if (vtkRenderWindowInteractor* interactor = this->RenderWindow->GetInteractor()) {
    interactor->SetInteractorStyle(this->InteractorStyle);
  }
}

// ---- refreshing the view and the controls ----------------------------------------------------------------------

bool qTissueMosaicRegistrationWidgetPrivate::report(bool ok) {
  this->Status->setText(ok ? QString() : QString::fromStdString(this->Logic->GetLastErrorText()));
  return ok;
}

void qTissueMosaicRegistrationWidgetPrivate::render() {
  // Before the view is shown it has no OpenGL context; it renders when it first paints.
  if (this->View->isVisible()) this->RenderWindow->Render();
}

void qTissueMosaicRegistrationWidgetPrivate::updateModelPipeline() {
  vtkPolyData* model = this->Logic->GetModel();
  if (!model) {
    this->ModelActor->VisibilityOff();
    this->ModelInfo->setText(QObject::tr("no model"));
    return;
  }
  // Point clouds without vertex cells are drawn through vertex glyphs (same point order, so picked ids match).
  if (model->GetNumberOfCells() == 0) {
    this->ModelVertices->SetInputData(model);
    this->ModelMapper->SetInputConnection(this->ModelVertices->GetOutputPort());
  } else {
    this->ModelMapper->SetInputData(model);
  }
  // Our reconstructions' 8-bit "RGB" colours are drawn as they are (also when a live model gets them later);
  // other scalars (e.g. a distance map read back) would be mapped through a meaningless range: solid colour.
  vtkDataArray* scalars = model->GetPointData()->GetScalars();
  this->ModelMapper->SetScalarVisibility(!scalars || hasDirectColours(model));
  this->ModelMapper->SetColorModeToDefault();
  this->ModelInfo->setText(QObject::tr("model: %1 points, %2 polygons")
                               .arg(model->GetNumberOfPoints())
                               .arg(model->GetNumberOfPolys()));
}

void qTissueMosaicRegistrationWidgetPrivate::updateTargetPipeline() {
  vtkPolyData* target = this->Logic->GetTarget();
  this->TargetActor->SetVisibility(target != nullptr);
  if (!target) {
    this->TargetInfo->setText(QObject::tr("no CT/MR model"));
    return;
  }
  this->TargetMapper->SetInputData(target);
  this->TargetInfo->setText(QObject::tr("CT/MR: %1 points, %2 polygons")
                                .arg(target->GetNumberOfPoints())
                                .arg(target->GetNumberOfPolys()));
}

void qTissueMosaicRegistrationWidgetPrivate::updateTransform() {
  const Eigen::Matrix4d& transform = this->Logic->GetTargetFromModel();
  setMatrix(this->ModelToTarget, transform);
  QStringList rows;
  for (int row = 0; row < 4; ++row) {
    rows << QStringLiteral("%1 %2 %3 %4")
                .arg(transform(row, 0), 10, 'f', 5)
                .arg(transform(row, 1), 10, 'f', 5)
                .arg(transform(row, 2), 10, 'f', 5)
                .arg(transform(row, 3), 10, 'f', 5);
  }
  this->TransformLabel->setText(rows.join('\n'));
}

void qTissueMosaicRegistrationWidgetPrivate::updateLandmarks() {
  // Glyph size: 1% of the CT/MR model (else the model), visible without hiding the surface.
  vtkPolyData* scene = this->Logic->GetTarget() ? this->Logic->GetTarget() : this->Logic->GetModel();
  const double diagonal = scene && scene->GetNumberOfPoints() > 0 ? scene->GetLength() : 100.0;
  this->Sphere->SetRadius(std::max(0.1, 0.01 * diagonal));

  vtkNew<vtkPoints> modelPoints, targetPoints, labelPoints;
  vtkNew<vtkStringArray> labels;
  labels->SetName("label");
  const Eigen::Matrix4d& transform = this->Logic->GetTargetFromModel();
  for (int i = 0; i < this->Logic->GetNumberOfLandmarkPairs(); ++i) {
    const auto& pair = this->Logic->GetLandmarkPair(i);
    if (pair.modelLps) modelPoints->InsertNextPoint(pair.modelLps->data());
    if (pair.targetLps) targetPoints->InsertNextPoint(pair.targetLps->data());
    const Eigen::Vector3d at = pair.targetLps ? *pair.targetLps : mapped(transform, *pair.modelLps);
    labelPoints->InsertNextPoint(at.data());
    labels->InsertNextValue(pair.label);
  }
  this->ModelLandmarkPoints->SetPoints(modelPoints);
  this->TargetLandmarkPoints->SetPoints(targetPoints);
  this->LabelPoints->SetPoints(labelPoints);
  this->LabelPoints->GetPointData()->Initialize();
  this->LabelPoints->GetPointData()->AddArray(labels);
  this->updateTable();
  this->render();
}

void qTissueMosaicRegistrationWidgetPrivate::updateTable() {
  this->UpdatingTable = true;
  const int rows = this->Logic->GetNumberOfLandmarkPairs();
  this->Table->setRowCount(rows);
  for (int row = 0; row < rows; ++row) {
    const auto& pair = this->Logic->GetLandmarkPair(row);
    const double residual = this->Logic->GetLandmarkResidualMm(row);
    const QString texts[] = {QString::fromStdString(pair.label), pointText(pair.modelLps), pointText(pair.targetLps),
                             std::isfinite(residual) ? QString::number(residual, 'f', 2) : QString()};
    for (int column = 0; column < 4; ++column) {
      QTableWidgetItem* item = this->Table->item(row, column);
      if (!item) {
        item = new QTableWidgetItem;
        this->Table->setItem(row, column, item);
      }
      item->setText(texts[column]);
      if (column == qTissueMosaicRegistrationWidget::ResidualColumn) item->setFlags(item->flags() & ~Qt::ItemIsEditable);
    }
  }
  this->UpdatingTable = false;
}

void qTissueMosaicRegistrationWidgetPrivate::updateResults() {
  const auto& landmarks = this->Logic->GetLandmarkRegistration();
  const auto& icp = this->Logic->GetIcpResult();
  const bool evaluated = this->Logic->HasEvaluation();
  const tissuemosaic::DistanceStatistics& statistics = this->Logic->GetDistanceStatistics();
  const auto number = [](double value) { return QString::number(value, 'f', 3); };
  const QString none = "-";
  this->Numbers["landmarkRmse"]->setText(landmarks ? number(landmarks->rmseMm) : none);
  this->Numbers["scale"]->setText(landmarks ? QString::number(landmarks->scale, 'f', 5) : none);
  this->Numbers["icpIterations"]->setText(
      icp ? QStringLiteral("%1 (%2)").arg(icp->iterations).arg(icp->converged ? "converged" : "iteration limit")
          : none);
  this->Numbers["icpInlierRmse"]->setText(icp ? number(icp->inlierRmseMm) : none);
  this->Numbers["points"]->setText(evaluated ? QString::number(statistics.count) : none);
  this->Numbers["rmse"]->setText(evaluated ? number(statistics.rmseMm) : none);
  this->Numbers["mean"]->setText(evaluated ? number(statistics.meanMm) : none);
  this->Numbers["median"]->setText(evaluated ? number(statistics.medianMm) : none);
  this->Numbers["p95"]->setText(evaluated ? number(statistics.p95Mm) : none);
  this->Numbers["max"]->setText(evaluated ? number(statistics.maxMm) : none);

  QVector<double> percent;
  if (evaluated && statistics.count > 0) {
    for (std::size_t count : this->Logic->GetDistanceHistogram().counts) {
      percent.push_back(100.0 * static_cast<double>(count) / static_cast<double>(statistics.count));
    }
  }
  this->Histogram->setHistogram(percent, this->Logic->GetDistanceHistogram().binWidthMm, statistics.meanMm,
                                statistics.p95Mm);
  this->updateDistanceColours();
}

void qTissueMosaicRegistrationWidgetPrivate::updateDistanceColours() {
  vtkPolyData* registered = this->Logic->GetRegisteredModel();
  const bool show = registered && this->ColourByDistance->isChecked();
  if (registered) {
    if (registered->GetNumberOfCells() == 0) {
      this->DistanceVertices->SetInputData(registered);
      this->DistanceMapper->SetInputConnection(this->DistanceVertices->GetOutputPort());
    } else {
      this->DistanceMapper->SetInputData(registered);
    }
    // Up to the 95th percentile: the few far points (tissue the CT/MR model lacks) would wash out the rest;
    // everything beyond shows in the top colour.
    const tissuemosaic::DistanceStatistics& statistics = this->Logic->GetDistanceStatistics();
    const double top = statistics.p95Mm > 0 ? statistics.p95Mm : std::max(statistics.maxMm, 1e-3);
    this->DistanceColours->SetTableRange(0, top);
  }
  this->DistanceActor->SetVisibility(show);
  this->ScalarBar->SetVisibility(show);
  this->ModelActor->SetVisibility(this->Logic->GetModel() != nullptr && !show);
}

void qTissueMosaicRegistrationWidgetPrivate::resetCamera() {
  this->Renderer->ResetCamera();
  this->updateLandmarks();  // glyph size follows the scene
}

// ---- landmark table ---------------------------------------------------------------------------------------------

void qTissueMosaicRegistrationWidgetPrivate::onTableItemChanged(QTableWidgetItem* item) {
  Q_Q(qTissueMosaicRegistrationWidget);
  if (this->UpdatingTable || !item) return;
  const int row = item->row();
  bool ok = false;
  Eigen::Vector3d point;
  switch (item->column()) {
    case qTissueMosaicRegistrationWidget::LabelColumn:
      ok = this->report(this->Logic->SetLandmarkLabel(row, item->text().trimmed().toStdString()));
      break;
    case qTissueMosaicRegistrationWidget::ModelColumn:
    case qTissueMosaicRegistrationWidget::TargetColumn:
      if (!parsePoint(item->text(), point)) {
        this->Status->setText(QObject::tr("a position is three numbers \"x, y, z\" in mm, not \"%1\"").arg(item->text()));
        break;
      }
      ok = this->report(item->column() == qTissueMosaicRegistrationWidget::ModelColumn
                            ? this->Logic->SetModelLandmark(row, point)
                            : this->Logic->SetTargetLandmark(row, point));
      break;
    default:
      break;
  }
  // Shows the stored value: the new one, or the old one back after a refused edit.
  QMetaObject::invokeMethod(q, [this] { this->updateLandmarks(); }, Qt::QueuedConnection);
  if (ok) emit q->landmarksChanged();
}

void qTissueMosaicRegistrationWidgetPrivate::deleteSelectedRows() {
  Q_Q(qTissueMosaicRegistrationWidget);
  QList<int> rows;
  for (const QModelIndex& index : this->Table->selectionModel()->selectedRows()) rows << index.row();
  std::sort(rows.begin(), rows.end(), std::greater<int>());
  for (int row : rows) this->Logic->RemoveLandmarkPair(row);
  if (rows.isEmpty()) return;
  this->updateLandmarks();
  emit q->landmarksChanged();
}

// ---- picking ----------------------------------------------------------------------------------------------------

bool qTissueMosaicRegistrationWidgetPrivate::pickModel(int x, int y) {
  vtkPolyData* model = this->Logic->GetModel();
  if (!model) return false;
  Eigen::Matrix4d targetFromModel = this->Logic->GetTargetFromModel();
  if (model->GetNumberOfPolys() > 0) {
    // A surface: the point where the ray meets it, taken back into the model's frame.
    this->CellPicker->InitializePickList();
    this->CellPicker->PickFromListOn();
    this->CellPicker->AddPickList(this->ModelActor);
    this->CellPicker->AddPickList(this->DistanceActor);
    if (!this->CellPicker->Pick(x, y, 0, this->Renderer) || this->CellPicker->GetCellId() < 0) return false;
    const double* world = this->CellPicker->GetPickPosition();
    const Eigen::Vector3d modelPoint = mapped(targetFromModel.inverse(), Eigen::Vector3d(world[0], world[1], world[2]));
    return this->report(this->Logic->AddModelLandmark(modelPoint) >= 0);
  }
  // A point cloud: the scanned point nearest the ray (ids are the model's: both actors keep its point order).
  if (!this->PointPicker->Pick(x, y, 0, this->Renderer)) return false;
  const vtkIdType id = this->PointPicker->GetPointId();
  if (id < 0 || id >= model->GetNumberOfPoints()) return false;
  double point[3];
  model->GetPoint(id, point);
  return this->report(this->Logic->AddModelLandmark(Eigen::Vector3d(point[0], point[1], point[2])) >= 0);
}

bool qTissueMosaicRegistrationWidgetPrivate::pickTarget(int x, int y) {
  if (!this->Logic->GetTarget()) return false;
  this->CellPicker->InitializePickList();
  this->CellPicker->PickFromListOn();
  this->CellPicker->AddPickList(this->TargetActor);
  if (!this->CellPicker->Pick(x, y, 0, this->Renderer) || this->CellPicker->GetCellId() < 0) return false;
  const double* world = this->CellPicker->GetPickPosition();
  return this->report(this->Logic->AddTargetLandmark(Eigen::Vector3d(world[0], world[1], world[2])) >= 0);
}

void qTissueMosaicRegistrationWidgetPrivate::withSaveFile(const QString& title, const QString& filter,
                                                          const std::function<bool(const QString&)>& action) {
  Q_Q(qTissueMosaicRegistrationWidget);
  const QString path = QFileDialog::getSaveFileName(q, title, QString(), filter);
  if (!path.isEmpty()) action(path);
}

// ---- public API -------------------------------------------------------------------------------------------------

qTissueMosaicRegistrationWidget::qTissueMosaicRegistrationWidget(QWidget* parent)
    : QWidget(parent), d_ptr(new qTissueMosaicRegistrationWidgetPrivate(*this)) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->setupUi();
  d->setupScene();
  this->updateFromLogic();
}

qTissueMosaicRegistrationWidget::~qTissueMosaicRegistrationWidget() = default;

vtkTissueMosaicRegistrationLogic* qTissueMosaicRegistrationWidget::registrationLogic() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Logic;
}

void qTissueMosaicRegistrationWidget::updateFromLogic() {
  Q_D(qTissueMosaicRegistrationWidget);
  d->updateModelPipeline();
  d->updateTargetPipeline();
  d->updateTransform();
  d->updateResults();
  d->updateLandmarks();  // renders
}

void qTissueMosaicRegistrationWidget::setReconstructedModel(vtkPolyData* modelLps) {
  Q_D(qTissueMosaicRegistrationWidget);
  const bool first = d->Logic->GetModel() == nullptr;
  if (modelLps == d->Logic->GetModel()) return;
  d->Logic->SetModel(modelLps);
  d->report(true);
  this->updateFromLogic();
  if (first) d->resetCamera();
  emit registrationChanged();
}

bool qTissueMosaicRegistrationWidget::loadModelFile(const QString& path) {
  Q_D(qTissueMosaicRegistrationWidget);
  const auto frame = static_cast<ModelFrameChoice>(d->ModelFrame->currentData().toInt());
  if (!d->report(d->Logic->LoadModel(path.toStdString(), frame))) return false;
  this->updateFromLogic();
  d->resetCamera();
  emit registrationChanged();
  return true;
}

bool qTissueMosaicRegistrationWidget::loadTargetFile(const QString& path) {
  Q_D(qTissueMosaicRegistrationWidget);
  const auto frame = static_cast<ModelFrameChoice>(d->TargetFrame->currentData().toInt());
  if (!d->report(d->Logic->LoadTarget(path.toStdString(), frame))) return false;
  this->updateFromLogic();
  d->resetCamera();
  emit registrationChanged();
  return true;
}

void qTissueMosaicRegistrationWidget::setModelFrameChoice(int choice) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->ModelFrame->setCurrentIndex(d->ModelFrame->findData(choice));
}

void qTissueMosaicRegistrationWidget::setTargetFrameChoice(int choice) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->TargetFrame->setCurrentIndex(d->TargetFrame->findData(choice));
}

int qTissueMosaicRegistrationWidget::addLandmarkPair(const Eigen::Vector3d& modelLps, const Eigen::Vector3d& targetLps) {
  Q_D(qTissueMosaicRegistrationWidget);
  const int row = d->Logic->AddLandmarkPair(modelLps, targetLps);
  if (!d->report(row >= 0)) return -1;
  d->updateLandmarks();
  emit landmarksChanged();
  return row;
}

bool qTissueMosaicRegistrationWidget::removeLandmarkPair(int row) {
  Q_D(qTissueMosaicRegistrationWidget);
  if (!d->report(d->Logic->RemoveLandmarkPair(row))) return false;
  d->updateLandmarks();
  emit landmarksChanged();
  return true;
}

bool qTissueMosaicRegistrationWidget::loadLandmarksFile(const QString& path) {
  Q_D(qTissueMosaicRegistrationWidget);
  if (!d->report(d->Logic->LoadLandmarkPairs(path.toStdString()))) return false;
  d->updateLandmarks();
  emit landmarksChanged();
  return true;
}

QTableWidget* qTissueMosaicRegistrationWidget::landmarkTable() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Table;
}

void qTissueMosaicRegistrationWidget::setPickMode(PickMode mode) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->Mode = mode;
  const QSignalBlocker blockModel(d->PickModelButton), blockTarget(d->PickTargetButton);
  d->PickModelButton->setChecked(mode == PickOnModel);
  d->PickTargetButton->setChecked(mode == PickOnTarget);
}

qTissueMosaicRegistrationWidget::PickMode qTissueMosaicRegistrationWidget::pickMode() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Mode;
}

bool qTissueMosaicRegistrationWidget::pickAt(int displayX, int displayY) {
  Q_D(qTissueMosaicRegistrationWidget);
  bool picked = false;
  if (d->Mode == PickOnModel) picked = d->pickModel(displayX, displayY);
  if (d->Mode == PickOnTarget) picked = d->pickTarget(displayX, displayY);
  if (!picked) return false;
  d->updateLandmarks();
  emit landmarksChanged();
  return true;
}

void qTissueMosaicRegistrationWidget::setScaleEnabled(bool withScale) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->Scale->setChecked(withScale);
}

bool qTissueMosaicRegistrationWidget::scaleEnabled() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Scale->isChecked();
}

bool qTissueMosaicRegistrationWidget::registerLandmarks() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (!d->report(d->Logic->RegisterLandmarks(d->Scale->isChecked()))) return false;
  this->updateFromLogic();
  emit registrationChanged();
  return true;
}

bool qTissueMosaicRegistrationWidget::refineIcp() {
  Q_D(qTissueMosaicRegistrationWidget);
  tissuemosaic::IcpParameters parameters;
  parameters.maxIterations = d->IcpIterations->value();
  parameters.inlierFraction = d->IcpInlierFraction->value();
  if (d->IcpMaxDistance->value() > 0) parameters.maxDistanceMm = d->IcpMaxDistance->value();
  if (!d->report(d->Logic->RefineIcp(parameters))) return false;
  this->updateFromLogic();
  emit registrationChanged();
  return true;
}

void qTissueMosaicRegistrationWidget::setIcpMaxIterations(int iterations) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->IcpIterations->setValue(iterations);
}

void qTissueMosaicRegistrationWidget::setIcpInlierFraction(double fraction) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->IcpInlierFraction->setValue(fraction);
}

bool qTissueMosaicRegistrationWidget::updateDistances() {
  Q_D(qTissueMosaicRegistrationWidget);
  if (!d->report(d->Logic->Evaluate())) return false;
  this->updateFromLogic();
  emit registrationChanged();
  return true;
}

QString qTissueMosaicRegistrationWidget::shownNumber(const QString& name) const {
  Q_D(const qTissueMosaicRegistrationWidget);
  const QLabel* label = d->Numbers.value(name, nullptr);
  return label ? label->text() : QString();
}

QString qTissueMosaicRegistrationWidget::shownTransform() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->TransformLabel->text();
}

QString qTissueMosaicRegistrationWidget::errorText() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Status->text();
}

QVector<double> qTissueMosaicRegistrationWidget::histogramPercent() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Histogram->percent();
}

double qTissueMosaicRegistrationWidget::histogramBinWidthMm() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Histogram->binWidthMm();
}

void qTissueMosaicRegistrationWidget::setColourByDistance(bool enabled) {
  Q_D(qTissueMosaicRegistrationWidget);
  d->ColourByDistance->setChecked(enabled);
}

bool qTissueMosaicRegistrationWidget::colourByDistance() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->ColourByDistance->isChecked();
}

QVTKOpenGLNativeWidget* qTissueMosaicRegistrationWidget::view() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->View;
}

vtkRenderer* qTissueMosaicRegistrationWidget::renderer() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->Renderer;
}

vtkScalarBarActor* qTissueMosaicRegistrationWidget::scalarBar() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->ScalarBar;
}

vtkActor* qTissueMosaicRegistrationWidget::distanceActor() const {
  Q_D(const qTissueMosaicRegistrationWidget);
  return d->DistanceActor;
}

bool qTissueMosaicRegistrationWidget::exportTransform(const QString& tfmPath) {
  Q_D(qTissueMosaicRegistrationWidget);
  return d->report(d->Logic->WriteTransform(tfmPath.toStdString()));
}

bool qTissueMosaicRegistrationWidget::exportRegisteredModel(const QString& path) {
  Q_D(qTissueMosaicRegistrationWidget);
  return d->report(d->Logic->WriteRegisteredModel(path.toStdString()));
}

bool qTissueMosaicRegistrationWidget::exportLandmarks(const QString& mrkJsonPath) {
  Q_D(qTissueMosaicRegistrationWidget);
  return d->report(d->Logic->WriteLandmarks(mrkJsonPath.toStdString()));
}

bool qTissueMosaicRegistrationWidget::exportDistanceReport(const QString& csvPath, const QString& pngPath) {
  Q_D(qTissueMosaicRegistrationWidget);
  return d->report(d->Logic->WriteDistanceCsv(csvPath.toStdString()) &&
                   d->Logic->WriteHistogramPng(pngPath.toStdString()));
}
