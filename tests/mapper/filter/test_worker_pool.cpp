// WorkerPool: every share of a run is called once, on as many threads as the pool has, run after run.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

#include "ogf/filter/worker_pool.hpp"

namespace ogf::filter {
namespace {

TEST(WorkerPool, EachRunCallsEveryShareOnceOnItsOwnThread) {
  for (const int threads : {1, 2, 5}) {
    WorkerPool pool(threads);
    ASSERT_EQ(pool.threads(), static_cast<std::size_t>(threads));
    for (int run = 0; run < 200; ++run) {
      std::vector<std::atomic<int>> calls(pool.threads());
      std::mutex mutex;
      std::set<std::thread::id> ids;
      pool.run([&](std::size_t w) {
        calls[w].fetch_add(1);
        const std::lock_guard lock(mutex);
        ids.insert(std::this_thread::get_id());
      });
      for (std::size_t w = 0; w < calls.size(); ++w) {
        ASSERT_EQ(calls[w].load(), 1) << threads << " threads, run " << run << ", share " << w;
      }
      ASSERT_EQ(ids.size(), pool.threads());
      ASSERT_EQ(ids.count(std::this_thread::get_id()), 1U);  // share 0 on the calling thread
    }
  }
}

TEST(WorkerPool, ARunReturnsOnlyWhenEveryShareHasFinished) {
  WorkerPool pool(3);
  std::atomic<int> finished{0};
  for (int run = 0; run < 50; ++run) {
    pool.run([&](std::size_t w) {
      if (w != 0) {
        std::this_thread::sleep_for(std::chrono::microseconds(200));
      }
      finished.fetch_add(1);
    });
    ASSERT_EQ(finished.load(), 3 * (run + 1));
  }
}

TEST(WorkerPool, AnExceptionOfTheCallingThreadsShareComesAfterTheWorkersFinish) {
  WorkerPool pool(2);
  std::atomic<bool> workerDone{false};
  EXPECT_THROW(pool.run([&](std::size_t w) {
    if (w == 0) {
      throw std::runtime_error("share 0");
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    workerDone = true;
  }),
               std::runtime_error);
  EXPECT_TRUE(workerDone.load());
  std::atomic<int> calls{0};
  pool.run([&](std::size_t) { calls.fetch_add(1); });  // the pool still works
  EXPECT_EQ(calls.load(), 2);
}

TEST(EvenSplit, PartsCoverTheRangeInOrderWithSizesWithinOne) {
  for (const std::size_t n : {0UL, 1UL, 7UL, 1000UL}) {
    for (const std::size_t parts : {1UL, 2UL, 3UL, 8UL}) {
      const EvenSplit split{n, parts};
      EXPECT_EQ(split.begin(0), 0U);
      EXPECT_EQ(split.begin(parts), n);
      for (std::size_t p = 0; p < parts; ++p) {
        const std::size_t size = split.begin(p + 1) - split.begin(p);
        EXPECT_LE(size, n / parts + 1);
        EXPECT_GE(size, n / parts);
      }
    }
  }
}

}  // namespace
}  // namespace ogf::filter
