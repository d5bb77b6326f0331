#include "qTissueMosaicStallProbe.h"

#include <algorithm>

#include <time.h>

qint64 qTissueMosaicThreadCpuNs() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<qint64>(now.tv_sec) * 1000000000 + now.tv_nsec;
}

qTissueMosaicStallProbe::qTissueMosaicStallProbe(QObject* parent, int intervalMs)
    : QObject(parent), IntervalMs(intervalMs) {
  this->Timer.setTimerType(Qt::PreciseTimer);
  this->Timer.setInterval(intervalMs);
  connect(&this->Timer, &QTimer::timeout, this, &qTissueMosaicStallProbe::tick);
}

void qTissueMosaicStallProbe::start() {
  this->LongestMs = this->LongestBusyMs = this->MostBusyMs = 0;
  this->Ticks = 0;
  this->Clock.start();
  this->LastNs = this->Clock.nsecsElapsed();
  this->LastCpuNs = qTissueMosaicThreadCpuNs();
  this->Timer.start();
}

void qTissueMosaicStallProbe::stop() { this->Timer.stop(); }

void qTissueMosaicStallProbe::tick() {
  const qint64 now = this->Clock.nsecsElapsed();
  const qint64 cpuNow = qTissueMosaicThreadCpuNs();
  const double gapMs = (now - this->LastNs) * 1e-6;
  const double busyMs = (cpuNow - this->LastCpuNs) * 1e-6;
  this->LastNs = now;
  this->LastCpuNs = cpuNow;
  ++this->Ticks;
  const double stallMs = gapMs - this->IntervalMs;
  if (stallMs > this->LongestMs) {
    this->LongestMs = stallMs;
    this->LongestBusyMs = busyMs;
  }
  this->MostBusyMs = std::max(this->MostBusyMs, busyMs);
  if (stallMs > this->IntervalMs) emit stalled(stallMs);
}
