#pragma once
/// @class qTissueMosaicStallProbe
/// @brief Measures how long the event loop is kept from running: a timer asks to fire every `intervalMs`; the
/// time between two firings minus the interval is how long the loop was busy elsewhere (a stall). The longest
/// stall is what a user feels as a frozen interface.
#include <QElapsedTimer>
#include <QObject>
#include <QTimer>

/// CPU time of the calling thread (ns): an event's own work, without the time it waited for a CPU.
qint64 qTissueMosaicThreadCpuNs();

class qTissueMosaicStallProbe : public QObject {
  Q_OBJECT
public:
  explicit qTissueMosaicStallProbe(QObject* parent = nullptr, int intervalMs = 5);
  void start();
  void stop();
  bool isActive() const { return this->Timer.isActive(); }
  /// Longest gap beyond the interval since start(), in milliseconds.
  double longestStallMs() const { return this->LongestMs; }
  /// The CPU time the probing (GUI) thread itself spent during that longest stall: on a busy machine the rest of
  /// the stall is waiting for a CPU, not work of this thread.
  double longestStallBusyMs() const { return this->LongestBusyMs; }
  /// The most CPU time the thread spent between two ticks: the longest stall it would cause on an idle machine.
  double longestBusyMs() const { return this->MostBusyMs; }
  /// Firings since start().
  long long ticks() const { return this->Ticks; }

signals:
  /// Emitted at the end of every stall longer than the interval (how long it was, in milliseconds).
  void stalled(double stallMs);

private:
  void tick();

  QTimer Timer;
  QElapsedTimer Clock;
  qint64 LastNs = 0;
  qint64 LastCpuNs = 0;
  double LongestMs = 0, LongestBusyMs = 0, MostBusyMs = 0;
  long long Ticks = 0;
  int IntervalMs;
};
