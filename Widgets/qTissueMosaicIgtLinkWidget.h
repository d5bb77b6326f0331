#pragma once
/// @class qTissueMosaicIgtLinkWidget
/// @brief The OpenIGTLink panel (docs/OPENIGTLINK.md): a server that sends the running scan to 3D Slicer. Port,
/// on/off, "send video", and the clients connected now. While on, scanObserver() (given to the reconstruction
/// logic) publishes every frame from the worker thread: TRANSFORM LeftCameraToModel per tracked frame, POLYDATA
/// TissueModel after key frames (rate-limited, within the point budget), STATUS TissueMosaic, IMAGE LeftVideo.
#include "vtkTissueMosaicReconstructionLogic.h"

#include <QScopedPointer>
#include <QWidget>

class qTissueMosaicIgtLinkWidgetPrivate;

class qTissueMosaicIgtLinkWidget : public QWidget {
  Q_OBJECT
public:
  explicit qTissueMosaicIgtLinkWidget(QWidget* parent = nullptr);
  ~qTissueMosaicIgtLinkWidget() override;

  /// Starts (true) or stops the server on the port shown; false with the reason in the panel (port in use).
  bool setServerOn(bool on);
  bool isServerOn() const;
  /// The port the server listens on (the spin box's value; 0 there: any free port, shown once listening).
  int port() const;
  void setPort(int port);
  int clientCount() const;
  /// For vtkTissueMosaicReconstructionLogic::SetScanObserver: forwards to the server while it is on, else nothing.
  vtkTissueMosaicReconstructionLogic::ScanObserver scanObserver() const;

signals:
  void message(const QString& text, bool isError);

private:
  QScopedPointer<qTissueMosaicIgtLinkWidgetPrivate> d_ptr;
  Q_DECLARE_PRIVATE(qTissueMosaicIgtLinkWidget);
};
