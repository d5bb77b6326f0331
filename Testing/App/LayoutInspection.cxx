#include "LayoutInspection.h"

#include <QAbstractButton>
#include <QCheckBox>
#include <QComboBox>
#include <QHeaderView>
#include <QLabel>
#include <QLayout>
#include <QPushButton>
#include <QRadioButton>
#include <QScrollArea>
#include <QScrollBar>
#include <QStyle>
#include <QStyleOptionButton>
#include <QTableWidget>
#include <QTextDocument>

#include <algorithm>

namespace tissuemosaic::test {

namespace {

/// Pixels of slack: rounding in the style's own arithmetic.
constexpr int kSlackPx = 1;

QString plainText(const QString& text) {
  if (!Qt::mightBeRichText(text)) return text;
  QTextDocument document;
  document.setHtml(text);
  return document.toPlainText();
}

int widestLine(const QFontMetrics& metrics, const QString& text) {
  int widest = 0;
  for (const QString& line : text.split('\n')) widest = std::max(widest, metrics.horizontalAdvance(line));
  return widest;
}

void checkLabel(const QLabel* label, QStringList& problems) {
  const QString text = plainText(label->text());
  if (text.isEmpty() || !label->pixmap(Qt::ReturnByValue).isNull()) return;
  const QRect contents = label->contentsRect().adjusted(label->margin(), label->margin(), -label->margin(),
                                                        -label->margin());
  if (label->wordWrap()) {
    const int needed = label->heightForWidth(label->width());
    if (needed > label->height() + kSlackPx) {
      problems << QString("%1: wrapped text needs %2 px of height, has %3").arg(describe(label)).arg(needed).arg(label->height());
    }
    return;
  }
  const int needed = widestLine(label->fontMetrics(), text) + label->indent();
  if (needed > contents.width() + kSlackPx) {
    problems << QString("%1: text %2 px wide in %3 px").arg(describe(label)).arg(needed).arg(contents.width());
  }
}

void checkButton(const QAbstractButton* button, QStringList& problems) {
  if (button->text().isEmpty()) return;
  const QFontMetrics metrics = button->fontMetrics();
  int needed = widestLine(metrics, QString(button->text()).remove('&'));
  if (qobject_cast<const QCheckBox*>(button) || qobject_cast<const QRadioButton*>(button)) {
    const bool check = qobject_cast<const QCheckBox*>(button) != nullptr;
    needed += button->style()->pixelMetric(check ? QStyle::PM_IndicatorWidth : QStyle::PM_ExclusiveIndicatorWidth,
                                           nullptr, button) +
              button->style()->pixelMetric(check ? QStyle::PM_CheckBoxLabelSpacing : QStyle::PM_RadioButtonLabelSpacing,
                                           nullptr, button);
  } else if (qobject_cast<const QPushButton*>(button)) {
    needed += 2 * button->style()->pixelMetric(QStyle::PM_ButtonMargin, nullptr, button);
  }
  if (needed > button->width() + kSlackPx) {
    problems << QString("%1: text needs %2 px, the button is %3 px wide").arg(describe(button)).arg(needed).arg(button->width());
  }
}

void checkComboBox(const QComboBox* combo, QStringList& problems) {
  if (combo->currentText().isEmpty()) return;
  // The text area is what the style leaves beside the arrow.
  QStyleOptionComboBox option;
  option.initFrom(combo);
  option.editable = combo->isEditable();
  const QRect field = combo->style()->subControlRect(QStyle::CC_ComboBox, &option, QStyle::SC_ComboBoxEditField, combo);
  const int needed = combo->fontMetrics().horizontalAdvance(combo->currentText());
  if (needed > field.width() + kSlackPx) {
    problems << QString("%1: \"%2\" needs %3 px, the field is %4 px").arg(describe(combo), combo->currentText()).arg(needed).arg(field.width());
  }
}

void checkTable(const QTableWidget* table, QStringList& problems) {
  const QHeaderView* header = table->horizontalHeader();
  const int viewportWidth = table->viewport()->width();
  if (header->length() > viewportWidth + kSlackPx) {
    problems << QString("%1: columns %2 px wide in a %3 px view").arg(describe(table)).arg(header->length()).arg(viewportWidth);
  }
  for (int column = 0; column < table->columnCount(); ++column) {
    if (table->isColumnHidden(column)) continue;
    const int width = table->columnWidth(column);
    const int title = header->sectionSizeHint(column);
    if (title > width + kSlackPx) {
      problems << QString("%1: column %2's title needs %3 px, has %4").arg(describe(table)).arg(column).arg(title).arg(width);
    }
    for (int row = 0; row < table->rowCount(); ++row) {
      const QTableWidgetItem* item = table->item(row, column);
      if (!item || item->text().isEmpty()) continue;
      const int needed = table->fontMetrics().horizontalAdvance(item->text()) + 6;  // the item's own margins
      if (needed > width + kSlackPx) {
        problems << QString("%1: cell (%2, %3) \"%4\" needs %5 px, the column has %6")
                        .arg(describe(table)).arg(row).arg(column).arg(item->text()).arg(needed).arg(width);
      }
    }
  }
  const QHeaderView* rows = table->verticalHeader();
  if (rows->isVisible() && rows->sizeHint().width() > rows->width() + kSlackPx) {
    problems << QString("%1: row titles need %2 px, have %3").arg(describe(table)).arg(rows->sizeHint().width()).arg(rows->width());
  }
}

void checkScrollArea(const QScrollArea* scroll, QStringList& problems) {
  const QWidget* content = scroll->widget();
  if (!content) return;
  const int viewport = scroll->viewport()->width();
  if (content->width() > viewport + kSlackPx || content->minimumSizeHint().width() > viewport + kSlackPx) {
    // Name the widest controls inside: what to make narrower.
    QList<QPair<int, const QWidget*>> widest;
    for (const QWidget* child : content->findChildren<QWidget*>()) {
      if (child->isVisible() && child->layout() == nullptr) widest.append({child->minimumSizeHint().width(), child});
    }
    std::sort(widest.begin(), widest.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    QStringList names;
    for (int i = 0; i < std::min(4, static_cast<int>(widest.size())); ++i) {
      names << QString("%1 at least %2 px").arg(describe(widest[i].second)).arg(widest[i].first);
    }
    problems << QString("%1: content needs %2 px (is %3) in a %4 px wide view: it scrolls or is cut sideways; "
                        "widest: %5")
                    .arg(describe(scroll))
                    .arg(content->minimumSizeHint().width())
                    .arg(content->width())
                    .arg(viewport)
                    .arg(names.join("; "));
  }
}

/// Widgets a layout places: they must neither overlap nor leave their parent.
void checkLayout(const QWidget* parent, QStringList& problems) {
  QLayout* layout = parent->layout();
  if (!layout) return;
  QList<const QWidget*> placed;
  for (const QWidget* child : parent->findChildren<QWidget*>(QString(), Qt::FindDirectChildrenOnly)) {
    if (child->isVisible() && !child->isWindow() && layout->indexOf(const_cast<QWidget*>(child)) >= 0) placed << child;
    // Widgets of nested layouts belong to the same parent: find them too.
    else if (child->isVisible() && !child->isWindow()) {
      for (QLayout* nested : layout->findChildren<QLayout*>()) {
        if (nested->indexOf(const_cast<QWidget*>(child)) >= 0) {
          placed << child;
          break;
        }
      }
    }
  }
  const QRect inside = parent->rect();
  for (int i = 0; i < placed.size(); ++i) {
    const QRect a = placed[i]->geometry();
    if (!inside.adjusted(-kSlackPx, -kSlackPx, kSlackPx, kSlackPx).contains(a)) {
      problems << QString("%1: at (%2, %3) %4x%5, outside its parent's %6x%7")
                      .arg(describe(placed[i])).arg(a.x()).arg(a.y()).arg(a.width()).arg(a.height())
                      .arg(inside.width()).arg(inside.height());
    }
    for (int j = i + 1; j < placed.size(); ++j) {
      const QRect overlap = a.intersected(placed[j]->geometry());
      if (overlap.width() > kSlackPx && overlap.height() > kSlackPx) {
        problems << QString("%1 and %2 overlap by %3x%4 px")
                        .arg(describe(placed[i]), describe(placed[j])).arg(overlap.width()).arg(overlap.height());
      }
    }
  }
}

}  // namespace

QString describe(const QWidget* widget) {
  QStringList path;
  for (const QWidget* w = widget; w; w = w->parentWidget()) {
    if (!w->objectName().isEmpty() && !w->objectName().startsWith("qt_")) path.prepend(w->objectName());
  }
  QString text;
  if (const auto* label = qobject_cast<const QLabel*>(widget)) text = label->text();
  if (const auto* button = qobject_cast<const QAbstractButton*>(widget)) text = button->text();
  return QString("%1 (%2%3)")
      .arg(path.join('/'), widget->metaObject()->className(), text.isEmpty() ? QString() : " \"" + text.left(40) + "\"");
}

QStringList layoutProblems(QWidget* root) {
  QStringList problems;
  QList<QWidget*> widgets = root->findChildren<QWidget*>();
  widgets.prepend(root);
  for (QWidget* widget : widgets) {
    if (!widget->isVisible()) continue;
    if (const auto* label = qobject_cast<const QLabel*>(widget)) checkLabel(label, problems);
    if (const auto* button = qobject_cast<const QAbstractButton*>(widget)) checkButton(button, problems);
    if (const auto* combo = qobject_cast<const QComboBox*>(widget)) checkComboBox(combo, problems);
    if (const auto* table = qobject_cast<const QTableWidget*>(widget)) checkTable(table, problems);
    if (const auto* scroll = qobject_cast<const QScrollArea*>(widget)) checkScrollArea(scroll, problems);
    checkLayout(widget, problems);
  }
  return problems;
}

}  // namespace tissuemosaic::test
