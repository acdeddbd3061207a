#include "server/live/render_pool.h"

#include <pthread.h>

#include <algorithm>
#include <atomic>
#include <iostream>
#include <optional>
#include <utility>

#include "sim/render/egl_context.h"

namespace incise::server::live {

struct RenderPool::Lane {
  explicit Lane(Client& c) : client(&c) {}
  Client* client;
  std::unique_ptr<ContextState> state;  // the render thread's only
  bool failed = false;                  // the render thread's only
  bool leaving = false;                 // guarded by the worker's mutex
  bool gone = false;                    // guarded by the worker's mutex
};

struct RenderPool::Worker {
  std::mutex mutex;
  std::condition_variable wake;
  std::condition_variable left;
  std::vector<std::shared_ptr<Lane>> lanes;
  bool poked = false;
  bool stop = false;
  std::thread thread;
};

RenderPool::RenderPool(int threads) {
  const int count = std::clamp(threads, 1, 64);
  for (int i = 0; i < count; ++i)
    workers_.push_back(std::make_unique<Worker>());
  for (auto& worker : workers_) {
    worker->thread = std::thread([this, w = worker.get()] { run(*w); });
  }
}

RenderPool::~RenderPool() {
  for (auto& worker : workers_) {
    {
      std::lock_guard lock(worker->mutex);
      worker->stop = true;
    }
    worker->wake.notify_all();
  }
  for (auto& worker : workers_)
    worker->thread.join();
}

RenderPool::Membership RenderPool::join(Client& client) {
  std::size_t best = 0;
  std::size_t fewest = SIZE_MAX;
  for (std::size_t i = 0; i < workers_.size(); ++i) {
    std::lock_guard lock(workers_[i]->mutex);
    if (workers_[i]->lanes.size() < fewest) {
      fewest = workers_[i]->lanes.size();
      best = i;
    }
  }
  Membership membership;
  membership.pool_ = this;
  membership.worker_ = best;
  membership.lane_ = std::make_shared<Lane>(client);
  {
    std::lock_guard lock(workers_[best]->mutex);
    workers_[best]->lanes.push_back(membership.lane_);
  }
  membership.poke();
  return membership;
}

std::vector<int> RenderPool::clients() const {
  std::vector<int> counts;
  for (const auto& worker : workers_) {
    std::lock_guard lock(worker->mutex);
    counts.push_back(static_cast<int>(worker->lanes.size()));
  }
  return counts;
}

void RenderPool::run(Worker& worker) {
  pthread_setname_np(pthread_self(), kThreadName);
  // The context is made when the first client arrives (a server that never renders opens none),
  // and outlives every state made in it: states are dropped on this thread before it goes.
  std::optional<render::EglContext> context;
  std::string unavailable;
  std::vector<std::shared_ptr<Lane>> due;
  std::vector<std::shared_ptr<Lane>> leaving;
  bool any_rendering = false;  // a client that has not failed: visit every kIdleWait
  while (true) {
    {
      std::unique_lock lock(worker.mutex);
      const auto woken = [&worker] { return worker.stop || worker.poked; };
      if (any_rendering) {
        worker.wake.wait_for(lock, kIdleWait, woken);
      } else {
        worker.wake.wait(lock, woken);
      }
      if (worker.stop) break;
      worker.poked = false;
      std::erase_if(worker.lanes, [&leaving](const std::shared_ptr<Lane>& lane) {
        if (!lane->leaving) return false;
        leaving.push_back(lane);
        return true;
      });
      due = worker.lanes;
    }
    if (!leaving.empty()) {
      // Their GL objects go with their context current, outside the lock: the simulation threads
      // poke under it at 125 Hz and must not wait for a teardown.
      for (const auto& lane : leaving)
        lane->state.reset();
      {
        std::lock_guard lock(worker.mutex);
        for (const auto& lane : leaving)
          lane->gone = true;
      }
      worker.left.notify_all();
      leaving.clear();
    }
    any_rendering = false;
    if (due.empty()) continue;
    if (!context && unavailable.empty()) {
      try {
        context.emplace();
      } catch (const std::exception& e) {
        unavailable = std::string("rendering unavailable: ") + e.what();
        std::cerr << "incise-server: " << unavailable << "\n";
      }
    }
    // Nothing may escape this thread (an exception leaving it ends the process): a client that
    // fails is told once and skipped from then on; the others go on.
    for (const auto& lane : due) {
      if (lane->failed) continue;
      std::string why = unavailable;
      if (why.empty()) {
        try {
          lane->client->render(lane->state);
          any_rendering = true;
          continue;
        } catch (const std::exception& e) {
          why = std::string("rendering stopped: ") + e.what();
        } catch (...) {
          why = "rendering stopped: unknown error";
        }
      }
      lane->state.reset();
      lane->failed = true;
      try {
        lane->client->failed(why);
      } catch (...) {
        // Told as far as it could be: the client stays failed and skipped.
      }
    }
    due.clear();
  }
  std::lock_guard lock(worker.mutex);
  for (auto& lane : worker.lanes) {
    lane->state.reset();
    lane->gone = true;
  }
  worker.left.notify_all();
}

RenderPool::Membership::Membership(Membership&& other) noexcept
    : pool_(std::exchange(other.pool_, nullptr)),
      worker_(other.worker_),
      lane_(std::move(other.lane_)) {}

RenderPool::Membership& RenderPool::Membership::operator=(Membership&& other) noexcept {
  if (this != &other) {
    leave();
    pool_ = std::exchange(other.pool_, nullptr);
    worker_ = other.worker_;
    lane_ = std::move(other.lane_);
  }
  return *this;
}

RenderPool::Membership::~Membership() {
  leave();
}

void RenderPool::Membership::poke() {
  if (pool_ == nullptr) return;
  Worker& worker = *pool_->workers_[worker_];
  {
    std::lock_guard lock(worker.mutex);
    worker.poked = true;
  }
  worker.wake.notify_all();
}

void RenderPool::Membership::leave() {
  if (pool_ == nullptr) return;
  Worker& worker = *pool_->workers_[worker_];
  std::unique_lock lock(worker.mutex);
  lane_->leaving = true;
  worker.poked = true;
  worker.wake.notify_all();
  worker.left.wait(lock, [this] { return lane_->gone; });
  lock.unlock();
  pool_ = nullptr;
  lane_.reset();
}

namespace {
std::atomic<int> g_shared_threads{0};
}  // namespace

int RenderPool::default_threads() {
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  return std::clamp(cores / 2, 1, 8);
}

void RenderPool::configure_shared(int threads) {
  g_shared_threads.store(threads);
}

// Never destroyed: its threads would tear their EGL contexts down during the static
// destructors, after Mesa's own exit handlers; at exit they wait with no clients.
RenderPool& RenderPool::shared() {
  static RenderPool& pool = *[] {
    const int configured = g_shared_threads.load();
    return new RenderPool(configured > 0 ? configured : default_threads());
  }();
  return pool;
}

}  // namespace incise::server::live
