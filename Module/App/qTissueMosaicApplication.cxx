#include "qTissueMosaicApplication.h"
#include "qTissueMosaicStallProbe.h"

#include <QByteArray>
#include <QEvent>

#include <cstdio>



qTissueMosaicApplication::qTissueMosaicApplication(int& argc, char** argv) : QApplication(argc, argv) {
  this->Clock.start();
}

void qTissueMosaicApplication::setSlowEventThresholdMs(double milliseconds) { this->ThresholdMs = milliseconds; }

bool qTissueMosaicApplication::notify(QObject* receiver, QEvent* event) {
  if (this->ThresholdMs <= 0) return QApplication::notify(receiver, event);
  // The receiver may delete itself while handling the event: name it first.
  const QByteArray className = receiver->metaObject()->className();
  const QByteArray objectName = receiver->objectName().toLocal8Bit();
  const int type = event->type();
  const qint64 startNs = this->Clock.nsecsElapsed();
  const qint64 startCpuNs = qTissueMosaicThreadCpuNs();
  const bool handled = QApplication::notify(receiver, event);
  const double milliseconds = (this->Clock.nsecsElapsed() - startNs) * 1e-6;
  if (milliseconds > this->ThresholdMs) {
    std::fprintf(stderr, "tissuemosaic-app: slow event at %.1f ms: %.1f ms (%.1f ms CPU), QEvent type %d, %s \"%s\"\n",
                 startNs * 1e-6, milliseconds, (qTissueMosaicThreadCpuNs() - startCpuNs) * 1e-6, type, className.constData(),
                 objectName.constData());
  }
  return handled;
}
