#pragma once
/// @class qTissueMosaicStereoParametersWidget
/// @brief Panel that edits every field of tissuemosaic::StereoParameters, with presets: the disparity range
/// (automatic, fixed min..max, or a working distance in mm, with the disparities it implies for the rig), the
/// method (the paper's section II or AD-Census), the fields both use, and each method's own group (the other
/// method's is disabled). Editing min/max disparity fixes the range; editing the working distance uses it.
///
/// The panel shows one parameters object: its own, or, after setStereoLogic(), the logic's. Every edit is
/// validated at once (StereoParameters::validate); an invalid combination (e.g. min disparity > max, an even
/// window) is refused: the object keeps its last valid value, and the refused fields turn red with the reason
/// under them until it is fixed. Spin boxes ignore the mouse wheel unless focused.
/// Presets come from Resources/Presets/*.yml (compiled in as Qt resources).
#include "Core/StereoRig.h"
#include "Stereo/StereoParameters.h"

#include <QScopedPointer>
#include <QStringList>
#include <QWidget>

class qTissueMosaicStereoParametersWidgetPrivate;
class vtkTissueMosaicStereoLogic;

class qTissueMosaicStereoParametersWidget : public QWidget {
  Q_OBJECT
public:
  explicit qTissueMosaicStereoParametersWidget(QWidget* parent = nullptr);
  ~qTissueMosaicStereoParametersWidget() override;

  /// The last valid parameters (the logic's when a logic is set).
  tissuemosaic::StereoParameters parameters() const;
  /// Shows the given parameters; refused (false, message shown) when they are invalid.
  bool setParameters(const tissuemosaic::StereoParameters& parameters);

  /// The panel edits this logic's parameters from now on (nullptr: its own copy). Not owned beyond a reference.
  void setStereoLogic(vtkTissueMosaicStereoLogic* logic);
  vtkTissueMosaicStereoLogic* stereoLogic() const;

  /// Preset names, e.g. "paper defaults", "fast" (from the file names).
  QStringList presetNames() const;
  /// The message shown for the last refused edit; empty when the panel is valid.
  QString errorText() const;
  /// True while the spin boxes show values that were refused (marked red at the fields): the object still holds
  /// its last valid values, so a scan would not use what is on screen.
  bool hasRefusedValues() const;
  /// Shows or hides the preset, load and save controls (hidden when a larger panel offers its own).
  void setPresetControlsVisible(bool visible);
  /// The rig the working distance is converted through (copied; nullptr: none known). A stereo logic's own
  /// geometry, when it has one, comes first.
  void setRigGeometry(const tissuemosaic::RectifiedGeometry* geometry);
  /// What the working distance means in disparities, as the panel shows it.
  QString workingDistanceText() const;

public slots:
  /// Shows the parameters object in the spin boxes (re-reading the logic's, when set). Emits no edits.
  void updateGUIFromParameters();
  /// Validates the spin box values; stores them (and emits parametersChanged) when valid, else shows why not.
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
  QScopedPointer<qTissueMosaicStereoParametersWidgetPrivate> d_ptr;

private:
  Q_DECLARE_PRIVATE(qTissueMosaicStereoParametersWidget);
  Q_DISABLE_COPY(qTissueMosaicStereoParametersWidget);
};
