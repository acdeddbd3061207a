#include "server/live/frame_streamer.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <iostream>
#include <map>
#include <span>

#include "sim/render/egl_context.h"
#include "sim/render/frame_encoder.h"
#include "sim/render/scene_renderer.h"

namespace incise::server::live {
namespace {

// How often the render thread looks for due viewers when nothing pokes it.
constexpr auto kIdleWait = std::chrono::milliseconds(2);
// The marked cut line's ink dots [m].
constexpr double kMarkRadius = 0.0015;

std::shared_ptr<std::vector<std::uint8_t>> frame_message(std::uint32_t frame_number, int width,
                                                         int height, double sim_time_s,
                                                         const std::vector<std::uint8_t>& jpeg) {
  auto message = std::make_shared<std::vector<std::uint8_t>>(kFrameHeaderSize + jpeg.size());
  auto* p = message->data();
  const auto w = static_cast<std::uint16_t>(width);
  const auto h = static_cast<std::uint16_t>(height);
  std::memcpy(p, &frame_number, 4);
  std::memcpy(p + 4, &w, 2);
  std::memcpy(p + 6, &h, 2);
  std::memcpy(p + 8, &sim_time_s, 8);
  std::memcpy(p + kFrameHeaderSize, jpeg.data(), jpeg.size());
  return message;
}

}  // namespace

FrameStreamer::FrameStreamer(const StreamSource& source, render::Camera camera)
    : source_(source), camera_(std::move(camera)), thread_([this] { run(); }) {}

FrameStreamer::~FrameStreamer() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void FrameStreamer::add(const std::shared_ptr<FrameSink>& sink) {
  {
    std::lock_guard lock(mutex_);
    sinks_.push_back({sink});
  }
  poke();
}

void FrameStreamer::poke() {
  {
    std::lock_guard lock(mutex_);
    poked_ = true;
  }
  wake_.notify_all();
}

std::string FrameStreamer::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

void FrameStreamer::run() {
  // The GL objects must die before the context, on this thread: hence the nesting. Nothing may
  // escape this function (an exception leaving a thread ends the process), so every failure
  // becomes error_, shown to the viewers as render_error, and the session runs on without pictures.
  std::optional<render::EglContext> context;
  try {
    context.emplace();
    render_loop();
  } catch (const std::exception& e) {
    std::lock_guard lock(mutex_);
    error_ = std::string(context ? "rendering stopped: " : "rendering unavailable: ") + e.what();
    std::cerr << "incise-server: " << error_ << "\n";
  }
}

void FrameStreamer::render_loop() {
  render::SceneRenderer renderer;
  // One encoder per frame size in use. Viewers choose their size, so the set is capped: the least
  // recently used encoder goes when a new size needs room (each holds a framebuffer and buffers).
  struct Encoder {
    std::unique_ptr<render::FrameEncoder> encoder;
    std::int64_t last_used = 0;
  };
  std::map<std::pair<int, int>, Encoder> encoders;
  std::int64_t pass = 0;
  std::vector<std::uint8_t> jpeg;
  sim::Points V, N;
  std::vector<render::MarkView> marks;
  struct Job {
    std::shared_ptr<FrameSink> sink;
    FrameSink::Request request;
    std::uint32_t frame_number;
  };
  std::vector<Job> jobs;
  while (true) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait_for(lock, kIdleWait, [this] { return stop_ || poked_; });
      if (stop_) return;
      poked_ = false;
    }
    const auto snapshot = source_.snapshot();
    if (!snapshot) continue;
    const auto now = SteadyClock::now();
    // Collect the viewers that want this snapshot, without holding the lock while rendering.
    jobs.clear();
    {
      std::lock_guard lock(mutex_);
      std::erase_if(sinks_, [](const Entry& e) { return e.sink.expired(); });
      for (auto& entry : sinks_) {
        if (entry.last_tick == snapshot->tick) continue;
        auto sink = entry.sink.lock();
        if (!sink) continue;
        const auto request = sink->frame_wanted(now);
        if (!request) continue;
        entry.last_tick = snapshot->tick;
        jobs.push_back({std::move(sink), *request, entry.next_frame++});
      }
    }
    if (jobs.empty()) continue;
    ++pass;
    sim::surface_vertices(*snapshot->surface, snapshot->positions, V, N);
    const render::TissueView tissue{&V, &N, &snapshot->surface->faces};
    std::array<render::ToolView, 2> tools;
    tools[0].tip = snapshot->tool_tip;
    tools[0].radius = snapshot->tool_radius;
    tools[0].in_contact = snapshot->contact;
    tools[1].tip = snapshot->second_tool_tip;
    tools[1].radius = snapshot->tool_radius;
    tools[1].in_contact = snapshot->second_force_n.squaredNorm() > 0;
    for (std::size_t h = 0; h < tools.size(); ++h)
      tools[h].shaft_direction = snapshot->shaft_direction[h];
    marks.clear();
    for (const sim::Vec3& p : snapshot->marks)
      marks.push_back({p, kMarkRadius});
    const std::span<const render::ToolView> tool(tools.data(),
                                                 static_cast<std::size_t>(snapshot->hands));
    // Viewers asking for the same size share one rendering.
    std::map<std::pair<int, int>, std::shared_ptr<const std::vector<std::uint8_t>>> rendered;
    for (auto& job : jobs) {
      const std::pair size{job.request.width, job.request.height};
      auto& jpeg_of_size = rendered[size];
      if (!jpeg_of_size) {
        auto it = encoders.find(size);
        if (it == encoders.end()) {
          if (encoders.size() >= kMaxEncoders) {
            encoders.erase(std::min_element(encoders.begin(), encoders.end(),
                                            [](const auto& a, const auto& b) {
                                              return a.second.last_used < b.second.last_used;
                                            }));
          }
          it = encoders
                   .emplace(
                       size,
                       Encoder{std::make_unique<render::FrameEncoder>(size.first, size.second), 0})
                   .first;
        }
        it->second.last_used = pass;
        it->second.encoder->render_jpeg(renderer, camera_, tissue, tool, jpeg, marks);
        ++frames_rendered_;
        jpeg_of_size = std::make_shared<const std::vector<std::uint8_t>>(jpeg);
      }
      job.sink->deliver(job.frame_number,
                        frame_message(job.frame_number, size.first, size.second,
                                      snapshot->sim_time_s, *jpeg_of_size),
                        snapshot->published_at);
    }
  }
}

}  // namespace incise::server::live
