#pragma once
/// @file StopSignal.h
/// @brief Ctrl-C (SIGINT) and SIGTERM as a request to stop cleanly: the command finishes the frame in hand and writes
/// its outputs. A second signal ends the program at once (the default action).
#include <atomic>
#include <functional>
#include <thread>

namespace tissuemosaic::cli {

class StopOnSignal {
public:
  /// onStop runs once, on a watcher thread, soon after the first signal (e.g. to interrupt a live source's wait).
  explicit StopOnSignal(std::function<void()> onStop);
  ~StopOnSignal();
  StopOnSignal(const StopOnSignal&) = delete;
  StopOnSignal& operator=(const StopOnSignal&) = delete;
  bool requested() const;

private:
  std::function<void()> onStop_;
  std::atomic<bool> done_{false};
  std::thread watcher_;
};

}  // namespace tissuemosaic::cli
