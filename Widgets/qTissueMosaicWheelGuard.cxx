#include "qTissueMosaicWheelGuard.h"

#include <QAbstractSpinBox>
#include <QComboBox>
#include <QEvent>
#include <QWidget>

namespace tissuemosaic::widgets {

namespace {

/// One filter for all guarded widgets: an unfocused widget lets the wheel event pass to its parent.
class WheelGuard : public QObject {
public:
  bool eventFilter(QObject* watched, QEvent* event) override {
    if (event->type() != QEvent::Wheel) return false;
    auto* widget = qobject_cast<QWidget*>(watched);
    if (!widget || widget->hasFocus()) return false;
    event->ignore();  // not accepted: QApplication hands it on to the parent (the scroll area)
    return true;      // and the widget itself never sees it
  }
};

WheelGuard* guard() {
  static WheelGuard* instance = new WheelGuard;  // lives as long as the application
  return instance;
}

}  // namespace

void guardWheel(QWidget* widget) {
  widget->setFocusPolicy(Qt::StrongFocus);
  widget->removeEventFilter(guard());
  widget->installEventFilter(guard());
}

void guardWheelOfChildren(QWidget* parent) {
  for (QAbstractSpinBox* spinBox : parent->findChildren<QAbstractSpinBox*>()) guardWheel(spinBox);
  for (QComboBox* comboBox : parent->findChildren<QComboBox*>()) guardWheel(comboBox);
}

}  // namespace tissuemosaic::widgets
