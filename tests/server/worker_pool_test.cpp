// A worker pool's bounds: server/worker_pool.h.
#include "server/worker_pool.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

namespace incise::server {
namespace {

using namespace std::chrono_literals;

TEST(WorkerPool, AFullQueueRefusesAtOnceAndEveryAcceptedJobRuns) {
  WorkerPool workers("test", 1, 3);
  std::promise<void> release;
  const auto gate = release.get_future().share();
  std::atomic<int> ran = 0;
  std::atomic<bool> started = false;
  // The one worker is busy with the first job; three more may wait.
  ASSERT_TRUE(workers.try_post([&] {
    started = true;
    gate.wait();
    ++ran;
  }));
  while (!started)
    std::this_thread::sleep_for(1ms);
  for (int i = 0; i < 3; ++i)
    EXPECT_TRUE(workers.try_post([&] { ++ran; })) << i;
  EXPECT_FALSE(workers.try_post([&] { ++ran; }));
  release.set_value();
  for (int i = 0; i < 2000 && ran < 4; ++i)
    std::this_thread::sleep_for(1ms);
  EXPECT_EQ(ran, 4);
  // With the queue drained there is room again.
  EXPECT_TRUE(workers.try_post([&] { ++ran; }));
  workers.stop();
  EXPECT_LE(ran, 5);
}

TEST(WorkerPool, AThrowingJobDoesNotStopTheWorker) {
  WorkerPool workers("test", 1, 4);
  std::promise<void> done;
  ASSERT_TRUE(workers.try_post([] { throw std::runtime_error("boom"); }));
  ASSERT_TRUE(workers.try_post([&] { done.set_value(); }));
  EXPECT_EQ(done.get_future().wait_for(5s), std::future_status::ready);
}

}  // namespace
}  // namespace incise::server
