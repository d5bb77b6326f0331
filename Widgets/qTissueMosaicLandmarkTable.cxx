#include "qTissueMosaicLandmarkTable.h"

#include "vtkTissueMosaicRegistrationLogic.h"

#include <vtkSmartPointer.h>

#include <QHeaderView>
#include <QRegularExpression>

#include <algorithm>
#include <cmath>
#include <functional>

namespace {

QString pointText(const std::optional<Eigen::Vector3d>& point) {
  if (!point) return QString();
  return QStringLiteral("%1, %2, %3").arg(point->x(), 0, 'f', 2).arg(point->y(), 0, 'f', 2).arg(point->z(), 0, 'f', 2);
}

}  // namespace

class qTissueMosaicLandmarkTable::Private {
public:
  vtkSmartPointer<vtkTissueMosaicRegistrationLogic> Logic;
  bool Updating = false;
};

qTissueMosaicLandmarkTable::qTissueMosaicLandmarkTable(vtkTissueMosaicRegistrationLogic* logic, QWidget* parent)
    : QTableWidget(0, 4, parent), d(new Private) {
  d->Logic = logic;
  this->setObjectName("landmarkTable");
  this->setHorizontalHeaderLabels({tr("Label"), tr("Model (LPS mm)"), tr("CT/MR (LPS mm)"), tr("Residual")});
  this->horizontalHeaderItem(ResidualColumn)->setToolTip(tr("Residual in mm"));
  // The two positions share what the label and residual leave: the table never scrolls sideways in the panel.
  QHeaderView* header = this->horizontalHeader();
  header->setSectionResizeMode(LabelColumn, QHeaderView::ResizeToContents);
  header->setSectionResizeMode(ModelColumn, QHeaderView::Stretch);
  header->setSectionResizeMode(TargetColumn, QHeaderView::Stretch);
  header->setSectionResizeMode(ResidualColumn, QHeaderView::ResizeToContents);
  this->verticalHeader()->hide();
  this->setHorizontalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  this->setSelectionBehavior(QAbstractItemView::SelectRows);
  this->setToolTip(tr("Edit a label or a position (\"x, y, z\" in mm) by double-clicking it. Residual: distance (mm) "
                      "between the CT/MR point and the model point moved by the current transform."));
  this->setMinimumHeight(120);
  connect(this, &QTableWidget::itemChanged, this, &qTissueMosaicLandmarkTable::onItemChanged);
  this->updateFromLogic();
}

qTissueMosaicLandmarkTable::~qTissueMosaicLandmarkTable() { delete d; }

bool qTissueMosaicLandmarkTable::parsePoint(const QString& text, double point[3]) {
  const QStringList words = text.split(QRegularExpression("[,;\\s]+"), Qt::SkipEmptyParts);
  if (words.size() != 3) return false;
  for (int i = 0; i < 3; ++i) {
    bool ok = false;
    point[i] = words[i].toDouble(&ok);
    if (!ok || !std::isfinite(point[i])) return false;
  }
  return true;
}

void qTissueMosaicLandmarkTable::updateFromLogic() {
  d->Updating = true;
  const int rows = d->Logic->GetNumberOfLandmarkPairs();
  this->setRowCount(rows);
  for (int row = 0; row < rows; ++row) {
    const auto& pair = d->Logic->GetLandmarkPair(row);
    const double residual = d->Logic->GetLandmarkResidualMm(row);
    const QString texts[] = {QString::fromStdString(pair.label), pointText(pair.modelLps), pointText(pair.targetLps),
                             std::isfinite(residual) ? QString::number(residual, 'f', 2) : QString()};
    for (int column = 0; column < 4; ++column) {
      QTableWidgetItem* item = this->item(row, column);
      if (!item) {
        item = new QTableWidgetItem;
        this->setItem(row, column, item);
      }
      item->setText(texts[column]);
      if (column == ResidualColumn) {
        item->setFlags(item->flags() & ~Qt::ItemIsEditable);
        item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
      }
    }
  }
  d->Updating = false;
}

void qTissueMosaicLandmarkTable::onItemChanged(QTableWidgetItem* item) {
  if (d->Updating || !item) return;
  const int row = item->row();
  bool ok = false;
  double point[3];
  QString refused;
  switch (item->column()) {
    case LabelColumn:
      ok = d->Logic->SetLandmarkLabel(row, item->text().trimmed().toStdString());
      break;
    case ModelColumn:
    case TargetColumn:
      if (!parsePoint(item->text(), point)) {
        refused = tr("A position is three numbers \"x, y, z\" in mm, not \"%1\".").arg(item->text());
        break;
      }
      ok = item->column() == ModelColumn ? d->Logic->SetModelLandmark(row, Eigen::Vector3d(point[0], point[1], point[2]))
                                         : d->Logic->SetTargetLandmark(row, Eigen::Vector3d(point[0], point[1], point[2]));
      break;
    default:
      return;
  }
  if (!ok && refused.isEmpty()) refused = QString::fromStdString(d->Logic->GetLastErrorText());
  // Shows the stored value: the new one, or the old one back after a refused edit (not from inside the item's
  // own change signal).
  QMetaObject::invokeMethod(this, [this] { this->updateFromLogic(); }, Qt::QueuedConnection);
  if (ok) emit landmarksChanged();
  else emit editRefused(refused);
}

bool qTissueMosaicLandmarkTable::deleteSelectedRows() {
  QList<int> rows;
  for (const QModelIndex& index : this->selectionModel()->selectedRows()) rows << index.row();
  std::sort(rows.begin(), rows.end(), std::greater<int>());
  for (int row : rows) d->Logic->RemoveLandmarkPair(row);
  if (rows.isEmpty()) return false;
  this->updateFromLogic();
  emit landmarksChanged();
  return true;
}
