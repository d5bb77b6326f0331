// The worker that runs a pipeline stage beside the calling thread: tasks run in order on one long-lived thread, a
// task's exception reaches its caller, and a result left unread still holds the caller until its task is done (a
// task may use the caller's locals).
#include "Core/BackgroundWorker.h"
#include "Core/Error.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

using namespace tissuemosaic;

TEST(BackgroundWorker, RunsTasksInOrderOnOneOtherThread) {
  BackgroundWorker worker;
  std::vector<int> order;
  std::vector<std::thread::id> threads(3);
  std::vector<PendingResult<int>> results;
  for (int i = 0; i < 3; ++i) {
    results.push_back(worker.run([&order, &threads, i] {
      std::this_thread::sleep_for(std::chrono::milliseconds(5 * (3 - i)));  // the first task is the slowest
      order.push_back(i);
      threads[i] = std::this_thread::get_id();
      return 10 * i;
    }));
  }
  for (int i = 0; i < 3; ++i) EXPECT_EQ(results[i].get(), 10 * i);
  EXPECT_EQ(order, (std::vector<int>{0, 1, 2}));
  EXPECT_NE(threads[0], std::this_thread::get_id());
  EXPECT_EQ(threads[0], threads[1]);
  EXPECT_EQ(threads[1], threads[2]);
}

TEST(BackgroundWorker, PassesATasksErrorToItsCaller) {
  BackgroundWorker worker;
  PendingResult<int> failed = worker.run([]() -> int { throw Error("the stage failed"); });
  EXPECT_THROW(failed.get(), Error);
  EXPECT_EQ(worker.run([] { return 4; }).get(), 4);  // the worker goes on
}

TEST(BackgroundWorker, AnUnreadResultWaitsForItsTask) {
  BackgroundWorker worker;
  std::atomic<bool> finished{false};
  {
    PendingResult<void> unread = worker.run([&finished] {
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
      finished = true;
    });
  }
  EXPECT_TRUE(finished.load());
}
