#pragma once
/// @file qTissueMosaicParameterFields.h
/// @brief The one form both parameter panels (stereo, reconstruction) give their spin boxes: a list of rows, each a
/// row of the engine's parameter tables (Core/ParameterTable.h: key, limits, unit, doc) with the panel's label,
/// group, step and decimals (tableRow), and the spin boxes made from it, grouped into form layouts. Limits, suffix
/// and tooltip come from the engine's table, so a spin box holds exactly what validate() takes. Integer fields get a QSpinBox, real ones a QDoubleSpinBox; every spin box ignores the mouse
/// wheel unless focused (qTissueMosaicWheelGuard.h). A refused edit (validate() said no) is shown at the field: the
/// spin boxes whose values differ from the stored parameters turn red, and the message line of their group says
/// why, until the values are valid again.
#include "qTissueMosaicMessageLine.h"
#include "qTissueMosaicWheelGuard.h"

#include "Core/ParameterTable.h"

#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QObject>
#include <QSignalBlocker>
#include <QSpinBox>

#include <cmath>
#include <functional>
#include <map>
#include <string>
#include <type_traits>
#include <vector>

namespace tissuemosaic::widgets {

/// One spin box of a parameter panel.
template <class Parameters>
struct ParameterField {
  const char* key;    ///< the parameter file's key; the spin box is named key + "SpinBox"
  const char* label;  ///< the form's label
  int group;          ///< index of the form layout it goes into
  std::function<double(const Parameters&)> get;
  std::function<void(Parameters&, double)> set;
  bool integer;       ///< QSpinBox (else QDoubleSpinBox)
  double minimum, maximum, step;
  int decimals;
  std::string suffix;
  const char* toolTip;
};

/// The spin box of table row `key` of the struct `Part`, the member `part` of the panel's `Parameters`.
template <class Parameters, class Part>
ParameterField<Parameters> tableRow(const parameters::Table<Part>& table, Part Parameters::*part, const char* key,
                                    const char* label, int group, double step, int decimals) {
  const parameters::Field<Part>& row = table.field(key);
  return {row.key, label, group,
          [get = row.get, part](const Parameters& p) { return get(p.*part); },
          [set = row.set, part](Parameters& p, double value) { set(p.*part, value); },
          row.integer(), row.minimum, row.maximum, step, decimals,
          *row.unit ? std::string(" ") + row.unit : std::string(), row.doc};
}

/// The same for a panel that edits `Parameters` itself.
template <class Parameters>
ParameterField<Parameters> tableRow(const parameters::Table<Parameters>& table, const char* key, const char* label,
                                    int group, double step, int decimals) {
  const parameters::Field<Parameters>& row = table.field(key);
  return {row.key, label, group, row.get, row.set, row.integer(), row.minimum, row.maximum, step, decimals,
          *row.unit ? std::string(" ") + row.unit : std::string(), row.doc};
}

/// The spin boxes of a field table, parallel to it.
template <class Parameters>
class ParameterSpinBoxes {
public:
  using Field = ParameterField<Parameters>;

  /// Makes one spin box per field in forms[field.group] (a message line is added at the end of each form);
  /// every change of a value calls onEdit.
  void create(QWidget* owner, const std::vector<Field>& fields, const std::vector<QFormLayout*>& forms,
              const std::function<void()>& onEdit) {
    Fields = &fields;
    for (QFormLayout* form : forms) {
      auto* line = new qTissueMosaicMessageLine(owner);
      line->setObjectName(QString("groupMessage%1").arg(GroupLines.size()));
      form->addRow(line);
      GroupLines.push_back(line);
    }
    for (const Field& field : fields) {
      QAbstractSpinBox* box;
      if (field.integer) {
        auto* spinBox = new QSpinBox(owner);
        spinBox->setRange(static_cast<int>(field.minimum), static_cast<int>(field.maximum));
        spinBox->setSingleStep(static_cast<int>(field.step));
        spinBox->setSuffix(QString::fromStdString(field.suffix));
        QObject::connect(spinBox, QOverload<int>::of(&QSpinBox::valueChanged), owner, [onEdit] { onEdit(); });
        box = spinBox;
      } else {
        auto* spinBox = new QDoubleSpinBox(owner);
        spinBox->setDecimals(field.decimals);
        spinBox->setRange(field.minimum, field.maximum);
        spinBox->setSingleStep(field.step);
        spinBox->setSuffix(QString::fromStdString(field.suffix));
        QObject::connect(spinBox, QOverload<double>::of(&QDoubleSpinBox::valueChanged), owner, [onEdit] { onEdit(); });
        box = spinBox;
      }
      box->setObjectName(QString(field.key) + "SpinBox");
      box->setToolTip(QObject::tr(field.toolTip));
      guardWheel(box);
      // Insert above the group's message line.
      QFormLayout* form = forms[static_cast<std::size_t>(field.group)];
      form->insertRow(form->rowCount() - 1, QObject::tr(field.label), box);
      SpinBoxes.push_back(box);
    }
  }

  /// Shows the parameters (no change signals) and clears any refusal.
  void show(const Parameters& parameters) {
    for (std::size_t i = 0; i < SpinBoxes.size(); ++i) {
      const QSignalBlocker blocker(SpinBoxes[i]);
      setValue(i, (*Fields)[i].get(parameters));
    }
    markRefused(parameters, QString());
  }

  /// The spin boxes' values written into `parameters`.
  void read(Parameters& parameters) const {
    for (std::size_t i = 0; i < SpinBoxes.size(); ++i) (*Fields)[i].set(parameters, value(i));
  }

  /// An empty reason clears the marks. Else the spin boxes whose values differ from `stored` (the values that
  /// were refused) turn red with the reason as tooltip, and their groups' message lines show it.
  void markRefused(const Parameters& stored, const QString& reason) {
    std::vector<bool> groupRefused(GroupLines.size(), false);
    Refused = false;
    for (std::size_t i = 0; i < SpinBoxes.size(); ++i) {
      const Field& field = (*Fields)[i];
      const bool refused = !reason.isEmpty() && differs(i, field.get(stored));
      QAbstractSpinBox* box = SpinBoxes[i];
      const QString style = refused ? "QAbstractSpinBox { background: #ffd7d7; color: #8b0000; }" : QString();
      if (box->styleSheet() != style) box->setStyleSheet(style);
      box->setToolTip(refused ? reason : QObject::tr(field.toolTip));
      if (refused) groupRefused[static_cast<std::size_t>(field.group)] = true;
      Refused = Refused || refused;
    }
    for (std::size_t group = 0; group < GroupLines.size(); ++group) {
      if (groupRefused[group]) GroupLines[group]->showError(reason);
      else GroupLines[group]->clearMessage();
    }
  }

  /// True while values shown are not the stored ones (a refused edit).
  bool hasRefusedValues() const { return Refused; }
  /// Whether two parameter objects agree in every field of the table.
  bool sameValues(const Parameters& a, const Parameters& b) const {
    for (const Field& field : *Fields) {
      if (field.get(a) != field.get(b)) return false;
    }
    return true;
  }
  QAbstractSpinBox* spinBox(std::size_t i) const { return SpinBoxes[i]; }

private:
  /// Whether spin box i shows another value than `stored` (to its decimals: a float need not print exactly).
  bool differs(std::size_t i, double stored) const {
    if (auto* real = qobject_cast<QDoubleSpinBox*>(SpinBoxes[i])) {
      return std::abs(real->value() - stored) > 0.5 * std::pow(10.0, -real->decimals());
    }
    return value(i) != stored;
  }
  double value(std::size_t i) const {
    if (auto* integer = qobject_cast<QSpinBox*>(SpinBoxes[i])) return integer->value();
    return qobject_cast<QDoubleSpinBox*>(SpinBoxes[i])->value();
  }
  void setValue(std::size_t i, double value) {
    if (auto* integer = qobject_cast<QSpinBox*>(SpinBoxes[i])) integer->setValue(static_cast<int>(std::lround(value)));
    else qobject_cast<QDoubleSpinBox*>(SpinBoxes[i])->setValue(value);
  }

  const std::vector<Field>* Fields = nullptr;
  std::vector<QAbstractSpinBox*> SpinBoxes;  ///< parallel to *Fields
  std::vector<qTissueMosaicMessageLine*> GroupLines;
  bool Refused = false;
};

}  // namespace tissuemosaic::widgets
