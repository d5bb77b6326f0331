#pragma once
/// @file StopSignal.h
/// @brief Ctrl-C (SIGINT) and SIGTERM as a request to stop cleanly: the command finishes the frame in hand and writes
/// its outputs, then exits with 128 + the signal's number (StoppedBySignal), as a shell reports a program that a signal
/// ended: scripts and batch runners must not take the partial outputs for a whole run. A second signal ends the
/// program at once (the default action).
#include <atomic>
#include <functional>
#include <string>
#include <thread>

namespace tissuemosaic::cli {

/// A command that stopped on a signal and wrote its (partial) outputs: main prints the message and exits with
/// exitStatus() (130 for SIGINT, 143 for SIGTERM). Not an Error: nothing went wrong but the run is not whole.
struct StoppedBySignal {
  int signal = 0;
  std::string message;  ///< e.g. "stopped by signal 15 (Terminated) after 12 frames: the outputs hold those frames"
  int exitStatus() const { return 128 + signal; }
};

class StopOnSignal {
public:
  /// onStop runs once, on a watcher thread, soon after the first signal (e.g. to interrupt a live source's wait).
  explicit StopOnSignal(std::function<void()> onStop);
  ~StopOnSignal();
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;
  bool requested() const;
  int signal() const;  ///< the signal that asked to stop (SIGINT, SIGTERM), 0 before one came
  /// Throws StoppedBySignal when a signal asked to stop: call it once the outputs are written. `what` says what was
  /// done, e.g. "after 12 frames".
  void throwIfRequested(const std::string& what) const;

private:
  std::function<void()> onStop_;
  std::atomic<bool> done_{false};
  std::thread watcher_;
};

}  // namespace tissuemosaic::cli
