#pragma once
/// @file qTissueMosaicPresetControls.h
/// @brief What the parameter panels (stereo, reconstruction) share: the row "Preset: [presets] Load... Save...",
/// the red line that says why an edit was refused, the presets compiled in from Resources/Presets/*.yml, and the
/// rule that an edit is stored only when validate() and the logic both accept it.
#include <QObject>
#include <QString>
#include <QStringList>
#include <QtGlobal>

#include <exception>
#include <functional>
#include <map>
#include <string>
#include <utility>
#include <vector>

class QBoxLayout;
class QComboBox;
class QLabel;
class QPushButton;
class QWidget;

namespace tissuemosaic::widgets {

/// The combo box item that stands for values matching no preset.
extern const char* const kCustomPresetLabel;

/// The preset row's controls. Object names: `prefix` + "PresetComboBox", "LoadButton", "SaveButton",
/// "PresetLabel", or "presetComboBox", ... when prefix is empty.
struct PresetRow {
  QLabel* label = nullptr;
  QComboBox* comboBox = nullptr;
  QPushButton* loadButton = nullptr;
  QPushButton* saveButton = nullptr;
};

/// How a panel names and describes its preset row, and what its buttons do with the chosen file.
struct PresetRowDescription {
  QString objectNamePrefix;
  QString loadToolTip, saveToolTip;
  QString loadDialogTitle, saveDialogTitle;  ///< e.g. "Load stereo parameters"
  std::function<void(const QString& path)> load, save;
};

/// Adds the preset row to layout; the buttons open file dialogs and hand the chosen path to load or save.
PresetRow addPresetRow(QWidget* owner, QBoxLayout* layout, const PresetRowDescription& description);

/// Shows or hides the whole row (hidden where a larger panel offers its own).
void setPresetRowVisible(const PresetRow& row, bool visible);

/// Adds the (hidden) error line to layout, named `prefix` + "ErrorLabel" ("errorLabel" when prefix is empty).
QLabel* addErrorLabel(QWidget* owner, QBoxLayout* layout, const QString& objectNamePrefix);
/// Shows message in the error line; an empty message hides it.
void showError(QLabel* errorLabel, const QString& message);

/// The texts of Resources/Presets/*.yml by display name (the file name without extension, '-' as ' ').
std::vector<std::pair<QString, std::string>> presetTexts();
/// Fills the preset combo box: kCustomPresetLabel, then "paper defaults" (what a new user should see), then the
/// other names in order.
void fillPresetComboBox(QComboBox* comboBox, const QStringList& names);
/// The same with the names of a preset map (readPresets).
template <class Parameters>
void fillPresetComboBox(QComboBox* comboBox, const std::map<QString, Parameters>& presets) {
  QStringList names;
  for (const auto& preset : presets) names << preset.first;
  fillPresetComboBox(comboBox, names);
}
/// The preset names of a combo box filled by fillPresetComboBox (kCustomPresetLabel left out).
QStringList presetNames(const QComboBox* comboBox);
/// Selects `name` in the combo box without emitting a signal (kCustomPresetLabel when empty).
void selectPreset(QComboBox* comboBox, const QString& name);

/// The presets parsed by parse(text, parameters, errorText) -> bool; an unusable preset is skipped with a warning
/// that names `what` (e.g. "stereo").
template <class Parameters, class Parse>
std::map<QString, Parameters> readPresets(const char* what, Parse parse) {
  std::map<QString, Parameters> presets;
  for (const auto& [name, text] : presetTexts()) {
    Parameters parameters;
    std::string errorText;
    if (!parse(text, parameters, errorText)) {
      qWarning("%s preset %s is unusable: %s", what, qPrintable(name), errorText.c_str());
      continue;
    }
    presets[name] = parameters;
  }
  return presets;
}

/// The name of the last preset for which isCurrent(preset) holds, or an empty string.
template <class Parameters, class IsCurrent>
QString matchingPreset(const std::map<QString, Parameters>& presets, IsCurrent isCurrent) {
  QString match;
  for (const auto& preset : presets) {
    if (isCurrent(preset.second)) match = preset.first;
  }
  return match;
}

/// Stores parameters through store(parameters, errorText) -> bool when parameters.validate() accepts them; else,
/// or when store refuses, shows "Not applied: <reason>" and returns false. A success clears the error line.
template <class Parameters, class Store>
bool storeValidated(const Parameters& parameters, QLabel* errorLabel, Store store) {
  std::string reason;
  try {
    parameters.validate();
  } catch (const std::exception& error) {
    reason = error.what();
  }
  if (reason.empty() && store(parameters, reason)) {
    showError(errorLabel, QString());
    return true;
  }
  showError(errorLabel, QObject::tr("Not applied: %1").arg(QString::fromStdString(reason)));
  return false;
}

}  // namespace tissuemosaic::widgets
