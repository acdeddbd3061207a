#pragma once
// The render threads that every picture of the process shares (docs/architecture.md, "Threads").
// Each thread owns one EGL context; a client (a session's or a replay's FrameStreamer) joins the
// thread with the fewest clients and stays on it, because what it keeps on the GPU (its
// renderer's buffers, its encoders' framebuffers) belongs to that context. A thread visits its
// clients in turn: when one is poked, and every kIdleWait besides, so that a viewer whose rate
// falls due gets its frame.
//
// So the number of render threads and EGL contexts is the pool's size, however many sessions and
// replays are open: on Mesa's llvmpipe each context also starts its own rasterizer threads, and
// one render thread per replay let a single trainee open dozens of them (issue 24).
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace incise::server::live {

class RenderPool {
 public:
  // What a client keeps in its thread's context between passes.
  class ContextState {
   public:
    virtual ~ContextState() = default;
  };
  class Client {
   public:
    virtual ~Client() = default;
    // On the client's render thread, its context current. state is null on the first pass (and
    // after a failure); the client creates what it keeps there. May throw: the pool then drops
    // the state and calls failed() instead of render() from then on.
    virtual void render(std::unique_ptr<ContextState>& state) = 0;
    // Rendering is not possible (no EGL display) or stopped (an error in render). Called once.
    virtual void failed(const std::string& why) = 0;
    // Both are called on the render thread, which must not end a membership (its own or another
    // of its thread's): leaving waits for that thread, which would then wait for itself.
  };

  struct Lane;
  // A client's place on a render thread; leaving it (destruction) waits for a pass in progress
  // and destroys the client's state on its thread. The client must outlive its membership.
  class Membership {
   public:
    Membership() = default;
    Membership(Membership&& other) noexcept;
    Membership& operator=(Membership&& other) noexcept;
    ~Membership();
    // Asks for a pass soon (a new snapshot, an acknowledged frame).
    void poke();

   private:
    friend class RenderPool;
    void leave();
    RenderPool* pool_ = nullptr;
    std::size_t worker_ = 0;
    std::shared_ptr<Lane> lane_;
  };

  static constexpr auto kIdleWait = std::chrono::milliseconds(2);
  static constexpr const char* kThreadName = "incise-render";  // in top -H, /proc/PID/task/*/comm

  explicit RenderPool(int threads);
  ~RenderPool();  // joins the threads; every membership must have ended
  RenderPool(const RenderPool&) = delete;
  RenderPool& operator=(const RenderPool&) = delete;

  Membership join(Client& client);
  int threads() const { return static_cast<int>(workers_.size()); }
  // Clients on each thread now.
  std::vector<int> clients() const;

  // Half the cores, between 1 and 8: llvmpipe rasterises with threads of its own.
  static int default_threads();
  // The process's pool, started on first use with the size given to configure_shared (before
  // that use, else it is ignored; the server's --render-threads) or default_threads().
  static RenderPool& shared();
  static void configure_shared(int threads);

 private:
  struct Worker;
  void run(Worker& worker);

  std::vector<std::unique_ptr<Worker>> workers_;
};

}  // namespace incise::server::live
