#pragma once
/// @class qTissueMosaicReconstructionParametersWidget
/// @brief Panel that edits the one tissuemosaic::ReconstructionParameters object of a reconstruction: the stereo
/// matcher (the stereo panel, paper II), tracking and key frames (III.A-C), key-frame refinement (III.D), fusion
/// (III.E), and the device; with presets (Resources/Presets/*.yml) and parameter files.
///
/// The panel shows one parameters object: its own, or, after setReconstructionLogic(), the logic's. Every edit is
/// validated at once by ReconstructionParameters::validate (the one source of the limits; the spin boxes accept
/// wider ranges so that they never clamp silently): an invalid value is refused, the object keeps its last valid
/// value and the panel shows the reason until it is fixed. The logic also refuses edits while a scan exists.
#include "Reconstruction/ReconstructionParameters.h"

#include <QScopedPointer>
#include <QStringList>
#include <QWidget>

class qTissueMosaicReconstructionParametersWidgetPrivate;
class qTissueMosaicStereoParametersWidget;
class vtkTissueMosaicReconstructionLogic;

class qTissueMosaicReconstructionParametersWidget : public QWidget {
  Q_OBJECT
public:
  explicit qTissueMosaicReconstructionParametersWidget(QWidget* parent = nullptr);
  ~qTissueMosaicReconstructionParametersWidget() override;

  /// The last valid parameters (the logic's when a logic is set).
  tissuemosaic::ReconstructionParameters parameters() const;
  /// Shows the given parameters; refused (false, message shown) when they are invalid or the logic refuses them.
  bool setParameters(const tissuemosaic::ReconstructionParameters& parameters);

  /// The panel edits this logic's parameters and device from now on (nullptr: its own copy).
  void setReconstructionLogic(vtkTissueMosaicReconstructionLogic* logic);
  vtkTissueMosaicReconstructionLogic* reconstructionLogic() const;

  /// vtkTissueMosaicReconstructionLogic::DeviceChoiceType (auto, cpu, cuda).
  int deviceChoice() const;
  void setDeviceChoice(int choice);

  /// Preset names, e.g. "paper defaults", "fast" (from the file names).
  QStringList presetNames() const;
  /// The message shown for the last refused edit (this panel's or the stereo panel's); empty when valid.
  QString errorText() const;
  /// True while some spin box (here or in the stereo panel) shows a value that was refused (marked red at the
  /// field): the parameters object, which a scan uses, still holds the last valid values.
  bool hasRefusedValues() const;
  /// The embedded stereo panel (paper II fields).
  qTissueMosaicStereoParametersWidget* stereoPanel() const;

public slots:
  /// Shows the parameters object in the controls (re-reading the logic's, when set). Emits no edits.
  void updateGUIFromParameters();
  /// Validates the controls' values; stores them (and emits parametersChanged) when valid, else shows why not.
  bool updateParametersFromGUI();
  bool applyPreset(const QString& name);
  bool loadParametersFile(const QString& path);
  bool saveParametersFile(const QString& path);

signals:
  /// The parameters object received new valid values from the panel.
  void parametersChanged();
  /// hasRefusedValues() changed.
  void validityChanged();

protected:
  QScopedPointer<qTissueMosaicReconstructionParametersWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qTissueMosaicReconstructionParametersWidget);
  Q_DISABLE_COPY(qTissueMosaicReconstructionParametersWidget);
};
