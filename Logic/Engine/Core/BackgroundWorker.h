#pragma once
/// @file BackgroundWorker.h
/// @brief One long-lived thread that runs tasks in turn, for a stage that runs beside another within one frame
/// (stereo beside tracking, the surface beside the matching). A thread per task would cost its start-up and, on
/// CUDA, a new per-thread stream each time.
#include <condition_variable>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <thread>
#include <type_traits>

namespace tissuemosaic {

/// The future of a task that may use the caller's locals: leaving the scope waits for the task (also when an
/// exception leaves it), so the task never outlives what it refers to.
template <class T>
class PendingResult {
public:
  explicit PendingResult(std::future<T> future) : future_(std::move(future)) {}
  ~PendingResult() {
    if (future_.valid()) future_.wait();
  }
  PendingResult(const PendingResult&) = delete;
  PendingResult& operator=(const PendingResult&) = delete;
  PendingResult(PendingResult&&) = default;
  bool pending() const { return future_.valid(); }
  /// The task's result, or its exception; once.
  T get() { return future_.get(); }

private:
  std::future<T> future_;
};

class BackgroundWorker {
public:
  /// The thread starts with the first task, so that it inherits the scheduling priority of the thread that uses
  /// the worker rather than of the one that built it.
  BackgroundWorker() = default;
  ~BackgroundWorker();
  BackgroundWorker(const BackgroundWorker&) = delete;
  BackgroundWorker& operator=(const BackgroundWorker&) = delete;

  /// Queues `task`; its result (or exception) arrives through the returned PendingResult.
  template <class Task>
  PendingResult<std::invoke_result_t<Task>> run(Task task) {
    using Result = std::invoke_result_t<Task>;
    auto packaged = std::make_shared<std::packaged_task<Result()>>(std::move(task));
    PendingResult<Result> result(packaged->get_future());
    enqueue([packaged] { (*packaged)(); });
    return result;
  }

private:
  void enqueue(std::function<void()> job);
  void loop();

  std::mutex mutex_;
  std::condition_variable wake_;
  std::deque<std::function<void()>> jobs_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace tissuemosaic
