// BoundedQueue and StageWorker: bounds, shutdown, order, error forwarding, and the same results
// inline and threaded.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

#include "rgbdi/common/bounded_queue.h"
#include "rgbdi/common/stage_worker.h"

using namespace rgbdi;

TEST(BoundedQueue, RejectsZeroCapacity) {
  EXPECT_THROW(BoundedQueue<int>(0), std::invalid_argument);
}

TEST(BoundedQueue, TryPushFailsWhenFullAndPopIsFifo) {
  BoundedQueue<int> q(2);
  int a = 1, b = 2, c = 3;
  EXPECT_TRUE(q.tryPush(a));
  EXPECT_TRUE(q.tryPush(b));
  EXPECT_FALSE(q.tryPush(c));
  EXPECT_EQ(c, 3);  // untouched when refused
  EXPECT_EQ(q.size(), 2u);
  EXPECT_EQ(q.highWater(), 2u);
  int out = 0;
  ASSERT_TRUE(q.pop(out));
  EXPECT_EQ(out, 1);
  ASSERT_TRUE(q.pop(out));
  EXPECT_EQ(out, 2);
}

TEST(BoundedQueue, PushBlocksUntilAConsumerMakesRoom) {
  BoundedQueue<int> q(1);
  ASSERT_TRUE(q.push(1));
  std::atomic<bool> pushed{false};
  std::thread producer([&] {
    q.push(2);
    pushed = true;
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_FALSE(pushed.load());  // still waiting: the queue is full
  int out = 0;
  ASSERT_TRUE(q.pop(out));
  producer.join();
  EXPECT_TRUE(pushed.load());
  EXPECT_EQ(q.size(), 1u);
  EXPECT_LE(q.highWater(), 1u);
}

TEST(BoundedQueue, ShutdownWakesWaitersDrainsAndRefusesPushes) {
  BoundedQueue<int> q(4);
  q.push(7);
  q.shutdown();
  EXPECT_FALSE(q.push(8));
  int out = 0;
  ASSERT_TRUE(q.pop(out));  // drains what was queued
  EXPECT_EQ(out, 7);
  EXPECT_FALSE(q.pop(out));  // then fails instead of blocking

  BoundedQueue<int> empty(1);
  std::thread consumer([&] {
    int v;
    EXPECT_FALSE(empty.pop(v));
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  empty.shutdown();
  consumer.join();
}

namespace {
std::vector<int> runStage(bool threaded) {
  std::vector<int> seen;
  StageWorker<int> w(
      "test", [&](int& v) { seen.push_back(v * v); }, threaded, 3);
  for (int i = 0; i < 200; ++i) w.submit(i);
  w.finish();
  return seen;
}
}  // namespace

TEST(StageWorker, InlineAndThreadedHandleTheSamePacketsInTheSameOrder) {
  const std::vector<int> inline_run = runStage(false);
  const std::vector<int> threaded_run = runStage(true);
  ASSERT_EQ(inline_run.size(), 200u);
  for (int i = 0; i < 200; ++i) EXPECT_EQ(inline_run[i], i * i);
  EXPECT_EQ(threaded_run, inline_run);
}

TEST(StageWorker, WaitHandledReturnsOnceThatManyPacketsAreDone) {
  std::atomic<int> done{0};
  StageWorker<int> w(
      "slow",
      [&](int&) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        ++done;
      },
      true, 8);
  for (int i = 0; i < 6; ++i) w.submit(i);
  w.waitHandled(4);
  EXPECT_GE(done.load(), 4);
  EXPECT_GE(w.handled(), 4u);
  w.finish();
  EXPECT_EQ(w.handled(), 6u);
  EXPECT_EQ(w.submitted(), 6u);
}

TEST(StageWorker, AHandlerFailureIsRethrownUpstreamAndLaterPacketsAreDiscarded) {
  for (bool threaded : {false, true}) {
    int handled_ok = 0;
    StageWorker<int> w(
        "failing",
        [&](int& v) {
          if (v == 3) throw std::runtime_error("packet 3 is bad");
          ++handled_ok;
        },
        threaded, 2);
    bool thrown = false;
    try {
      for (int i = 0; i < 50; ++i) w.submit(i);
      w.finish();
    } catch (const std::runtime_error& e) {
      thrown = true;
      EXPECT_STREQ(e.what(), "packet 3 is bad");
    }
    EXPECT_TRUE(thrown) << (threaded ? "threaded" : "inline");
    EXPECT_EQ(handled_ok, 3);
    EXPECT_THROW(w.finish(), std::runtime_error);
  }
}
