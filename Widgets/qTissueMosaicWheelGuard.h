#pragma once
/// @file qTissueMosaicWheelGuard.h
/// @brief Spin boxes and combo boxes that ignore the mouse wheel unless they have the keyboard focus (Qt's
/// Qt::StrongFocus pattern): a user scrolling a long panel must not change the values the pointer passes over.
/// The wheel event then goes on to the scroll area, which scrolls.
class QWidget;

namespace tissuemosaic::widgets {

/// Gives `widget` Qt::StrongFocus (click or tab to focus, not the wheel) and makes it ignore wheel events while
/// it has no focus.
void guardWheel(QWidget* widget);
/// guardWheel for every spin box and combo box inside `parent` (its descendants).
void guardWheelOfChildren(QWidget* parent);

}  // namespace tissuemosaic::widgets
