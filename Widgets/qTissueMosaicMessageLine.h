#pragma once
/// @class qTissueMosaicMessageLine
/// @brief One line of feedback placed right under the controls it is about (an error where the action was, not at
/// the bottom of the panel): red for an error, amber for a warning, green for a confirmation; hidden when empty.
#include <QLabel>

class qTissueMosaicMessageLine : public QLabel {
  Q_OBJECT
public:
  enum Kind { Error, Warning, Done };
  explicit qTissueMosaicMessageLine(QWidget* parent = nullptr);

  void showMessage(const QString& text, Kind kind);
  void showError(const QString& text) { this->showMessage(text, Error); }
  void showWarning(const QString& text) { this->showMessage(text, Warning); }
  void showDone(const QString& text) { this->showMessage(text, Done); }
  void clearMessage() { this->showMessage(QString(), Done); }
  Kind kind() const { return this->Current; }
  bool isError() const { return !this->text().isEmpty() && this->Current == Error; }

  /// A library's error text in plain words: the first letter capitalised, a full stop at the end.
  static QString sentence(const QString& text);

private:
  Kind Current = Done;
};
