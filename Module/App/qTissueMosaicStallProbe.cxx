#include "qTissueMosaicStallProbe.h"

#include <algorithm>

qTissueMosaicStallProbe::qTissueMosaicStallProbe(QObject* parent, int intervalMs)
    : QObject(parent), IntervalMs(intervalMs) {
  this->Timer.setTimerType(Qt::PreciseTimer);
  this->Timer.setInterval(intervalMs);
  connect(&this->Timer, &QTimer::timeout, this, &qTissueMosaicStallProbe::tick);
}

void qTissueMosaicStallProbe::start() {
  this->LongestMs = 0;
  this->Ticks = 0;
  this->Clock.start();
  this->LastNs = this->Clock.nsecsElapsed();
  this->Timer.start();
}

void qTissueMosaicStallProbe::stop() { this->Timer.stop(); }

void qTissueMosaicStallProbe::tick() {
  const qint64 now = this->Clock.nsecsElapsed();
  const double gapMs = (now - this->LastNs) * 1e-6;
  this->LastNs = now;
  ++this->Ticks;
  const double stallMs = gapMs - this->IntervalMs;
  this->LongestMs = std::max(this->LongestMs, stallMs);
  if (stallMs > this->IntervalMs) emit stalled(stallMs);
}
