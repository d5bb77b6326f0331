#include "qTissueMosaicPresetControls.h"

#include "qTissueMosaicWheelGuard.h"

#include <QBoxLayout>
#include <QComboBox>
#include <QDir>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QLabel>
#include <QPushButton>
#include <QSignalBlocker>

#include <algorithm>

// Q_INIT_RESOURCE must be called outside any namespace; the resources live in a static library, so nothing
// registers them unless we do.
static void initPresetResources() { Q_INIT_RESOURCE(Presets); }

namespace tissuemosaic::widgets {

const char* const kCustomPresetLabel = "(custom)";

namespace {

/// "presetComboBox" for an empty prefix, else prefix + "PresetComboBox".
QString prefixedName(const QString& prefix, const QString& name) {
  return prefix.isEmpty() ? name : prefix + name.left(1).toUpper() + name.mid(1);
}

const char* const kParameterFileFilter = "Parameter files (*.yml *.yaml *.xml)";

}  // namespace

PresetRow addPresetRow(QWidget* owner, QBoxLayout* layout, const PresetRowDescription& description) {
  const QString& prefix = description.objectNamePrefix;
  PresetRow row;
  auto* rowLayout = new QHBoxLayout();
  row.label = new QLabel(QObject::tr("Preset:"), owner);
  row.label->setObjectName(prefixedName(prefix, "presetLabel"));
  rowLayout->addWidget(row.label);
  row.comboBox = new QComboBox(owner);
  row.comboBox->setObjectName(prefixedName(prefix, "presetComboBox"));
  row.comboBox->setToolTip(QObject::tr("Replace all values with a preset from Resources/Presets."));
  guardWheel(row.comboBox);
  rowLayout->addWidget(row.comboBox, 1);
  row.loadButton = new QPushButton(QObject::tr("Load..."), owner);
  row.loadButton->setObjectName(prefixedName(prefix, "loadButton"));
  row.loadButton->setToolTip(description.loadToolTip);
  row.saveButton = new QPushButton(QObject::tr("Save..."), owner);
  row.saveButton->setObjectName(prefixedName(prefix, "saveButton"));
  row.saveButton->setToolTip(description.saveToolTip);
  rowLayout->addWidget(row.loadButton);
  rowLayout->addWidget(row.saveButton);
  layout->addLayout(rowLayout);

  QObject::connect(row.loadButton, &QPushButton::clicked, owner,
                   [owner, title = description.loadDialogTitle, load = description.load] {
                     const QString path =
                         QFileDialog::getOpenFileName(owner, title, QString(), QObject::tr(kParameterFileFilter));
                     if (!path.isEmpty()) load(path);
                   });
  QObject::connect(row.saveButton, &QPushButton::clicked, owner,
                   [owner, title = description.saveDialogTitle, save = description.save] {
                     const QString path =
                         QFileDialog::getSaveFileName(owner, title, QString(), QObject::tr(kParameterFileFilter));
                     if (!path.isEmpty()) save(path);
                   });
  return row;
}

void setPresetRowVisible(const PresetRow& row, bool visible) {
  row.label->setVisible(visible);
  row.comboBox->setVisible(visible);
  row.loadButton->setVisible(visible);
  row.saveButton->setVisible(visible);
}

QLabel* addErrorLabel(QWidget* owner, QBoxLayout* layout, const QString& objectNamePrefix) {
  auto* label = new QLabel(owner);
  label->setObjectName(prefixedName(objectNamePrefix, "errorLabel"));
  label->setWordWrap(true);
  label->setStyleSheet("QLabel { color: #c00000; font-weight: bold; }");
  label->hide();
  layout->addWidget(label);
  return label;
}

void showError(QLabel* errorLabel, const QString& message) {
  errorLabel->setText(message);
  errorLabel->setVisible(!message.isEmpty());
}

std::vector<std::pair<QString, std::string>> presetTexts() {
  initPresetResources();
  std::vector<std::pair<QString, std::string>> texts;
  const QDir directory(":/Presets");
  for (const QFileInfo& file : directory.entryInfoList({"*.yml"}, QDir::Files, QDir::Name)) {
    QFile resource(file.absoluteFilePath());
    if (!resource.open(QIODevice::ReadOnly)) {
      qWarning("preset %s cannot be read", qPrintable(file.fileName()));
      continue;
    }
    texts.emplace_back(file.completeBaseName().replace('-', ' '), resource.readAll().toStdString());
  }
  return texts;
}

void fillPresetComboBox(QComboBox* comboBox, const QStringList& names) {
  comboBox->addItem(kCustomPresetLabel);
  if (names.contains("paper defaults")) comboBox->addItem("paper defaults");
  for (const QString& name : names) {
    if (name != "paper defaults") comboBox->addItem(name);
  }
}

QStringList presetNames(const QComboBox* comboBox) {
  QStringList names;
  for (int i = 1; i < comboBox->count(); ++i) names << comboBox->itemText(i);
  return names;
}

void selectPreset(QComboBox* comboBox, const QString& name) {
  const QSignalBlocker blocker(comboBox);
  comboBox->setCurrentIndex(name.isEmpty() ? 0 : std::max(0, comboBox->findText(name)));
}

}  // namespace tissuemosaic::widgets
