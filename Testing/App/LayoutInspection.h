#pragma once
// What a user sees of a window's layout, checked widget by widget: text cut off by its label, button, check box
// or combo box; sibling widgets of one layout that overlap or reach outside their parent; a scroll area whose
// content is wider than its viewport (horizontal scrolling, or content cut at the right when that scroll bar is
// off); a table whose columns or rows do not all show whole.
#include <QString>
#include <QStringList>

class QWidget;

namespace tissuemosaic::test {

/// Every problem found among the visible widgets inside `root` (root included), one line each, naming the widget
/// by its object name path and saying what is wrong with figures.
QStringList layoutProblems(QWidget* root);

/// "moduleTabs/qt_tabwidget_stackedwidget/.../startButton (QPushButton "Start")": for messages.
QString describe(const QWidget* widget);

}  // namespace tissuemosaic::test
