#include "qTissueMosaicIgtLinkWidget.h"

#include "IgtLinkPublisher.h"
#include "Reconstruction/ReconstructionPipeline.h"

#include <QCheckBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QSpinBox>
#include <QTimer>

#include <atomic>
#include <memory>
#include <mutex>

namespace {

/// A running server and its publisher; the worker thread holds a shared_ptr while it publishes, so switching the
/// server off never pulls it from under a call.
struct Link {
  Link(int port, const tissuemosaic::igtlink::IgtLinkServer::Options& serverOptions,
       const tissuemosaic::igtlink::IgtLinkPublisherOptions& options)
      : server(port, serverOptions), publisher(server, options) {}
  tissuemosaic::igtlink::IgtLinkServer server;
  tissuemosaic::igtlink::IgtLinkPublisher publisher;
};

}  // namespace

class qTissueMosaicIgtLinkWidgetPrivate {
public:
  QSpinBox* portBox = nullptr;
  QLineEdit* bindEdit = nullptr;
  QCheckBox* onBox = nullptr;
  QCheckBox* videoBox = nullptr;
  QLabel* clientsLabel = nullptr;
  QLabel* errorLabel = nullptr;
  QTimer* refresh = nullptr;
  /// Shared with the observer's copies, which outlive nothing but may run on the worker thread.
  std::shared_ptr<std::shared_ptr<Link>> current = std::make_shared<std::shared_ptr<Link>>();
  std::shared_ptr<std::mutex> currentMutex = std::make_shared<std::mutex>();

  std::shared_ptr<Link> link() const {
    std::lock_guard<std::mutex> lock(*currentMutex);
    return *current;
  }
  void updateLabels() {
    const std::shared_ptr<Link> running = link();
    clientsLabel->setText(running ? QObject::tr("listening on %1 port %2, %3 client(s) connected")
                                        .arg(QString::fromStdString(running->server.boundAddress()))
                                        .arg(running->server.port())
                                        .arg(running->server.clientCount())
                                  : QObject::tr("off"));
  }
};

qTissueMosaicIgtLinkWidget::qTissueMosaicIgtLinkWidget(QWidget* parent)
    : QWidget(parent), d_ptr(new qTissueMosaicIgtLinkWidgetPrivate) {
  Q_D(qTissueMosaicIgtLinkWidget);
  auto* layout = new QFormLayout(this);
  d->onBox = new QCheckBox(tr("Send the scan to 3D Slicer"), this);
  d->onBox->setObjectName("igtlServerCheckBox");
  d->onBox->setToolTip(tr("An OpenIGTLink server: in Slicer, add a client connector (OpenIGTLinkIF) to this "
                          "computer and port. TRANSFORM LeftCameraToModel per frame, POLYDATA TissueModel "
                          "(colour array 'Colors'), STATUS TissueMosaic."));
  d->portBox = new QSpinBox(this);
  d->portBox->setObjectName("igtlPortSpinBox");
  d->portBox->setRange(0, 65535);
  d->portBox->setValue(tissuemosaic::igtlink::IgtLinkServer::kSlicerDefaultPort);
  // Loopback by default: only this computer's programs connect (docs/OPENIGTLINK.md, "Who can connect").
  d->bindEdit = new QLineEdit(QString::fromLatin1(tissuemosaic::igtlink::IgtLinkServer::kLoopback), this);
  d->bindEdit->setObjectName("igtlBindLineEdit");
  d->bindEdit->setToolTip(tr("The address the server listens on: 127.0.0.1 lets in only this computer's programs; "
                             "a network interface's address, or 0.0.0.0 for all of them, lets in that network. "
                             "At most 8 clients at once."));
  d->videoBox = new QCheckBox(tr("Also send the left video (IMAGE LeftVideo)"), this);
  d->videoBox->setObjectName("igtlVideoCheckBox");
  d->clientsLabel = new QLabel(this);
  d->clientsLabel->setObjectName("igtlClientsLabel");
  d->errorLabel = new QLabel(this);
  d->errorLabel->setObjectName("igtlErrorLabel");
  d->errorLabel->setWordWrap(true);
  d->errorLabel->setStyleSheet("color: #b00020");
  layout->addRow(d->onBox);
  layout->addRow(tr("Port"), d->portBox);
  layout->addRow(tr("Address"), d->bindEdit);
  layout->addRow(d->videoBox);
  layout->addRow(tr("Clients"), d->clientsLabel);
  layout->addRow(d->errorLabel);
  connect(d->onBox, &QCheckBox::toggled, this, [this](bool on) { this->setServerOn(on); });
  d->refresh = new QTimer(this);
  connect(d->refresh, &QTimer::timeout, this, [d] { d->updateLabels(); });
  d->refresh->start(500);
  d->updateLabels();
}

qTissueMosaicIgtLinkWidget::~qTissueMosaicIgtLinkWidget() { this->setServerOn(false); }

bool qTissueMosaicIgtLinkWidget::setServerOn(bool on) {
  Q_D(qTissueMosaicIgtLinkWidget);
  d->errorLabel->clear();
  std::shared_ptr<Link> next;
  if (on) {
    tissuemosaic::igtlink::IgtLinkPublisherOptions options;
    options.sendVideo = d->videoBox->isChecked();
    try {
      tissuemosaic::igtlink::IgtLinkServer::Options server;
      server.bindAddress = d->bindEdit->text().trimmed().toStdString();
      next = std::make_shared<Link>(d->portBox->value(), server, options);
    } catch (const std::exception& e) {
      d->errorLabel->setText(QString::fromStdString(e.what()));
      emit message(QString::fromStdString(e.what()), true);
    }
  }
  {
    std::lock_guard<std::mutex> lock(*d->currentMutex);
    d->current->swap(next);
  }
  next.reset();  // the old server stops here (or when the worker lets go of it)
  const bool isOn = static_cast<bool>(d->link());
  const QSignalBlocker blocker(d->onBox);
  d->onBox->setChecked(isOn);
  d->portBox->setEnabled(!isOn);
  d->bindEdit->setEnabled(!isOn);
  d->videoBox->setEnabled(!isOn);
  d->updateLabels();
  if (isOn)
    emit message(tr("OpenIGTLink server listening on %1 port %2")
                     .arg(QString::fromStdString(d->link()->server.boundAddress()))
                     .arg(d->link()->server.port()),
                 false);
  return isOn == on;
}

bool qTissueMosaicIgtLinkWidget::isServerOn() const { return static_cast<bool>(d_func()->link()); }

int qTissueMosaicIgtLinkWidget::port() const {
  const std::shared_ptr<Link> running = d_func()->link();
  return running ? running->server.port() : d_func()->portBox->value();
}

void qTissueMosaicIgtLinkWidget::setPort(int port) { d_func()->portBox->setValue(port); }

int qTissueMosaicIgtLinkWidget::clientCount() const {
  const std::shared_ptr<Link> running = d_func()->link();
  return running ? running->server.clientCount() : 0;
}

vtkTissueMosaicReconstructionLogic::ScanObserver qTissueMosaicIgtLinkWidget::scanObserver() const {
  auto current = d_func()->current;
  auto mutex = d_func()->currentMutex;
  auto link = [current, mutex] {
    std::lock_guard<std::mutex> lock(*mutex);
    return *current;
  };
  vtkTissueMosaicReconstructionLogic::ScanObserver observer;
  observer.frameProcessed = [link](const tissuemosaic::FrameResult& result, double timeS,
                                   const tissuemosaic::ReconstructionPipeline& pipeline) {
    const std::shared_ptr<Link> running = link();
    if (!running) return;
    running->publisher.frameProcessed(result.frameIndex, timeS, result.tracked, result.T_world_camera,
                                      result.trackingMessage, result.leftRectified);
    if (result.keyFrame && running->publisher.modelDue())
      running->publisher.modelUpdated(pipeline.liveModelSnapshot().cloud, timeS);  // where the tissue is now
  };
  observer.scanEnded = [link](const tissuemosaic::ModelPoints* model, double timeS, const std::string& how) {
    const std::shared_ptr<Link> running = link();
    if (!running) return;
    running->publisher.finished(model ? std::optional<tissuemosaic::ColoredPointCloud>(model->cloud) : std::nullopt,
                                timeS, "scan " + how, 2.0);
  };
  return observer;
}
