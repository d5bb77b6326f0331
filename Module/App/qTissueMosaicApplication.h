#pragma once
/// @class qTissueMosaicApplication
/// @brief The QApplication of tissuemosaic-app, able to name what keeps the event loop busy: with
/// setSlowEventThresholdMs(ms), every event whose delivery takes longer is written to stderr with its start time,
/// duration, type and receiver. Events nest (a paint inside a window update), so an inner event appears before
/// the event that contains it. Used with --report-stalls to explain a stall, e.g. a render followed by the whole
/// window's composition.
#include <QApplication>
#include <QElapsedTimer>

class qTissueMosaicApplication : public QApplication {
public:
  qTissueMosaicApplication(int& argc, char** argv);

  /// Events longer than this are logged; 0 (the default) logs nothing and costs nothing.
  void setSlowEventThresholdMs(double milliseconds);

  bool notify(QObject* receiver, QEvent* event) override;

  /// Milliseconds since the application started: the clock of the slow-event log.
  double elapsedMs() const { return this->Clock.nsecsElapsed() * 1e-6; }

private:
  QElapsedTimer Clock;
  double ThresholdMs = 0;
};
