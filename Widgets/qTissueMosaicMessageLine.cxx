#include "qTissueMosaicMessageLine.h"

qTissueMosaicMessageLine::qTissueMosaicMessageLine(QWidget* parent) : QLabel(parent) {
  this->setWordWrap(true);
  this->setTextInteractionFlags(Qt::TextSelectableByMouse);
  this->hide();
}

void qTissueMosaicMessageLine::showMessage(const QString& text, Kind kind) {
  static const char* const styles[] = {"QLabel { color: #c00000; font-weight: bold; }",
                                       "QLabel { color: #8a5a00; background: #fff3cd; padding: 2px; }",
                                       "QLabel { color: #2e7d32; }"};
  this->Current = kind;
  this->setText(text);
  if (this->styleSheet() != styles[kind]) this->setStyleSheet(styles[kind]);
  this->setVisible(!text.isEmpty());
}

QString qTissueMosaicMessageLine::sentence(const QString& text) {
  QString plain = text.trimmed();
  if (plain.isEmpty()) return plain;
  plain[0] = plain[0].toUpper();
  if (!plain.endsWith('.') && !plain.endsWith('!') && !plain.endsWith('?')) plain += '.';
  return plain;
}
