#pragma once
/// @class qTissueMosaicLandmarkTable
/// @brief The landmark pairs of a registration (vtkTissueMosaicRegistrationLogic) as a table: label, model point
/// (model frame), CT/MR point (both "x, y, z" in LPS mm) and the residual |CT - T * model| under the current
/// transform. Labels and positions are edited in place (double-click); a refused edit puts the stored value back
/// and editRefused() says why.
#include <QTableWidget>

class vtkTissueMosaicRegistrationLogic;

class qTissueMosaicLandmarkTable : public QTableWidget {
  Q_OBJECT
public:
  enum Column { LabelColumn = 0, ModelColumn, TargetColumn, ResidualColumn };

  /// Shows `logic`'s pairs (referenced).
  explicit qTissueMosaicLandmarkTable(vtkTissueMosaicRegistrationLogic* logic, QWidget* parent = nullptr);
  ~qTissueMosaicLandmarkTable() override;

  /// "x, y, z" (commas and/or spaces) as a point; false when it is not three finite numbers.
  static bool parsePoint(const QString& text, double point[3]);

public slots:
  /// Shows the logic's pairs and residuals.
  void updateFromLogic();
  /// Deletes the pairs of the selected rows; true when any was deleted.
  bool deleteSelectedRows();

signals:
  /// An edit or a deletion changed the logic's pairs.
  void landmarksChanged();
  /// An edit was refused: why, in plain words.
  void editRefused(const QString& reason);

private:
  void onItemChanged(QTableWidgetItem* item);

  class Private;
  Private* d;
};
