// FanOut (sim/core/fan_out.h): every task runs once, on the threads asked
// for, and a failure stops the tasks not yet started and is rethrown.
#include "sim/core/fan_out.h"

#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace ipmc {
namespace {

TEST(FanOutTest, EveryTaskRunsOnceOnAtMostTheThreadsAskedFor) {
  for (int threads : {1, 2, 3, 8}) {
    std::vector<int> runs(20, 0);
    std::mutex mutex;
    std::set<std::thread::id> ids;
    FanOut(runs.size(), threads, [&](std::size_t i) {
      std::lock_guard<std::mutex> lock(mutex);
      ++runs[i];
      ids.insert(std::this_thread::get_id());
    });
    EXPECT_EQ(runs, std::vector<int>(20, 1)) << threads << " threads";
    EXPECT_LE(ids.size(), static_cast<std::size_t>(threads));
    if (threads == 1) {
      EXPECT_EQ(*ids.begin(), std::this_thread::get_id());
    }
  }
  FanOut(0, 4, [](std::size_t) { ADD_FAILURE() << "no task to run"; });
  EXPECT_THROW(FanOut(1, 0, [](std::size_t) {}), std::invalid_argument);
}

TEST(FanOutTest, AFailureStopsTheTasksNotStartedAndIsRethrown) {
  // One thread: tasks run in index order, so those after the failing one
  // never start.
  std::vector<int> started;
  try {
    FanOut(6, 1, [&](std::size_t i) {
      started.push_back(static_cast<int>(i));
      if (i == 2) throw std::runtime_error("task 2");
    });
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "task 2");
  }
  EXPECT_EQ(started, (std::vector<int>{0, 1, 2}));

  // Two tasks failing on two threads: the lower index is rethrown.
  std::atomic<int> waiting{2};
  try {
    FanOut(2, 2, [&](std::size_t i) {
      --waiting;
      while (waiting > 0) std::this_thread::yield();  // both have started
      throw std::runtime_error("task " + std::to_string(i));
    });
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(error.what(), "task 0");
  }
}

}  // namespace
}  // namespace ipmc
