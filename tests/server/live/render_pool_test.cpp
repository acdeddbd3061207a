// The render pool (server/live/render_pool.h): however many clients join, the pool's threads and
// EGL contexts are all there are; each client is rendered on its thread with the context current,
// keeps its state there until it leaves, and a client that fails does not stop the others.
#include "server/live/render_pool.h"

#include <EGL/egl.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "server/live/frame_streamer.h"
#include "tests/support/wait_for.h"

namespace incise::server::live {
namespace {

using namespace std::chrono_literals;

using incise::test::wait_for;

// The threads of this process now.
int threads_now() {
  int count = 0;
  for ([[maybe_unused]] const auto& task : std::filesystem::directory_iterator("/proc/self/task"))
    ++count;
  return count;
}

struct CountedState : RenderPool::ContextState {
  explicit CountedState(std::atomic<int>& alive) : alive_(alive) { ++alive_; }
  ~CountedState() override { --alive_; }
  std::atomic<int>& alive_;
};

class CountingClient : public RenderPool::Client {
 public:
  explicit CountingClient(std::atomic<int>& alive, bool throws = false)
      : alive_(alive), throws_(throws) {}
  void render(std::unique_ptr<RenderPool::ContextState>& state) override {
    if (eglGetCurrentContext() == EGL_NO_CONTEXT) without_context.store(true);
    if (!state) state = std::make_unique<CountedState>(alive_);
    ++passes;
    if (throws_) throw std::runtime_error("a bad picture");
  }
  void failed(const std::string& why) override {
    std::lock_guard lock(mutex);
    failures.push_back(why);
  }
  std::atomic<int> passes{0};
  std::atomic<bool> without_context{false};
  std::mutex mutex;
  std::vector<std::string> failures;

 private:
  std::atomic<int>& alive_;
  bool throws_;
};

TEST(RenderPool, ClientsShareItsThreadsEvenly) {
  RenderPool pool(2);
  EXPECT_EQ(pool.threads(), 2);
  std::atomic<int> alive{0};
  std::vector<std::unique_ptr<CountingClient>> clients;
  std::vector<RenderPool::Membership> memberships;
  for (int i = 0; i < 7; ++i) {
    clients.push_back(std::make_unique<CountingClient>(alive));
    memberships.push_back(pool.join(*clients.back()));
  }
  const auto counts = pool.clients();
  ASSERT_EQ(counts.size(), 2u);
  EXPECT_EQ(counts[0] + counts[1], 7);
  EXPECT_LE(std::abs(counts[0] - counts[1]), 1);
  // Every client is rendered, again and again (every kIdleWait), with a context current.
  ASSERT_TRUE(wait_for([&] {
    for (const auto& c : clients)
      if (c->passes.load() < 3) return false;
    return true;
  }));
  for (const auto& c : clients)
    EXPECT_FALSE(c->without_context.load());
  EXPECT_EQ(alive.load(), 7);
}

TEST(RenderPool, LeavingWaitsForItsPassAndDropsItsStateOnItsThread) {
  RenderPool pool(1);
  std::atomic<int> alive{0};
  CountingClient staying(alive);
  CountingClient leaving(alive);
  auto stays = pool.join(staying);
  {
    auto goes = pool.join(leaving);
    ASSERT_TRUE(wait_for([&] { return leaving.passes.load() > 0; }));
    EXPECT_EQ(alive.load(), 2);
  }                            // leaves here
  EXPECT_EQ(alive.load(), 1);  // its state is gone once leave returned
  const int passes = leaving.passes.load();
  const int other = staying.passes.load();
  ASSERT_TRUE(wait_for([&] { return staying.passes.load() > other + 5; }));
  EXPECT_EQ(leaving.passes.load(), passes);  // never rendered again
  EXPECT_EQ(pool.clients(), std::vector<int>{1});
}

TEST(RenderPool, AFailingClientIsToldOnceAndTheOthersGoOn) {
  RenderPool pool(1);
  std::atomic<int> alive{0};
  CountingClient bad(alive, /*throws=*/true);
  CountingClient good(alive);
  auto a = pool.join(bad);
  auto b = pool.join(good);
  ASSERT_TRUE(wait_for([&] { return good.passes.load() > 10; }));
  EXPECT_EQ(bad.passes.load(), 1);
  std::lock_guard lock(bad.mutex);
  EXPECT_EQ(bad.failures, std::vector<std::string>{"rendering stopped: a bad picture"});
  EXPECT_EQ(alive.load(), 1);  // the failed client's state was dropped
}

class EmptySource : public StreamSource {
 public:
  std::shared_ptr<const Snapshot> snapshot() const override { return nullptr; }
  nlohmann::json status() const override { return nlohmann::json::object(); }
};

// Twenty streamers (twenty replays open at once) on a pool of two: not one thread more, neither
// render threads nor llvmpipe's (each context starts its own).
TEST(RenderPool, StreamersDoNotStartThreadsOfTheirOwn) {
  RenderPool pool(2);
  std::atomic<int> alive{0};
  CountingClient first(alive);
  CountingClient second(alive);
  auto a = pool.join(first);
  auto b = pool.join(second);
  // Both threads have rendered, so both contexts (and llvmpipe's threads) exist.
  ASSERT_TRUE(wait_for([&] { return first.passes.load() > 0 && second.passes.load() > 0; }));
  const int before = threads_now();
  EmptySource source;
  std::vector<std::unique_ptr<FrameStreamer>> streamers;
  for (int i = 0; i < 20; ++i) {
    streamers.push_back(std::make_unique<FrameStreamer>(source, render::Camera{}, render::Camera{},
                                                        nullptr, std::vector<render::MarkView>{},
                                                        pool));
  }
  std::this_thread::sleep_for(100ms);
  EXPECT_EQ(threads_now(), before);
  EXPECT_EQ(pool.clients(), (std::vector<int>{11, 11}));
  streamers.clear();
  EXPECT_EQ(pool.clients(), (std::vector<int>{1, 1}));
}

}  // namespace
}  // namespace incise::server::live
