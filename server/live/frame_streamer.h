#pragma once
// Renders a session's snapshots for its viewers on a thread of the render pool (render_pool.h),
// and hands each viewer the newest frame at that viewer's size and rate. Flow control is the
// viewer's: it says when it wants a frame (its rate is due and fewer than 2 frames are
// unacknowledged), so a slow viewer simply gets fewer frames and nothing queues here.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "curriculum/curriculum.h"
#include "server/live/render_pool.h"
#include "server/live/snapshot.h"
#include "sim/render/camera.h"
#include "sim/render/scene_renderer.h"
#include "sim/surgery/scene_presets.h"

namespace incise::server::live {

using SteadyClock = std::chrono::steady_clock;

// The 16-byte little-endian header before each JPEG on the view socket (docs/api.md).
inline constexpr std::size_t kFrameHeaderSize = 16;

class FrameSink {
 public:
  struct Request {
    int width = 640;
    int height = 480;
    bool outside = false;  // the camera outside the body rather than the scope
  };
  virtual ~FrameSink() = default;
  // Called on the render thread: the size wanted if a frame is wanted now, else nullopt.
  virtual std::optional<Request> frame_wanted(SteadyClock::time_point now) = 0;
  // Changes whenever the viewer changes what it asks for (size, camera): the same instant is then
  // drawn again for it, so that a paused replay shows the new view (poke the streamer after).
  virtual std::uint64_t settings_version() const { return 0; }
  // Called on the render thread with the whole message (header + JPEG) for frame_number.
  virtual void deliver(std::uint32_t frame_number,
                       std::shared_ptr<const std::vector<std::uint8_t>> message,
                       SteadyClock::time_point published_at) = 0;
};

// A snapshot as the viewers see it, prepared once for all the viewers of that instant: the
// tissue's surface with its cut walls, the instruments with their working ends (the palpation
// block's probes, upright at the hands), the marked line's ink dots. Keeps its buffers from
// snapshot to snapshot.
class SnapshotPicture {
 public:
  // Drawn with every snapshot after the marked line's ink: a task's visible zones (task_zones).
  void set_zones(std::vector<render::MarkView> zones) { zones_ = std::move(zones); }
  // The snapshot must outlive the calls to encode that follow.
  void prepare(const Snapshot& snapshot);
  // Draws the prepared snapshot from camera and encodes it (FrameEncoder::render_jpeg).
  void encode(render::SceneRenderer& renderer, render::FrameEncoder& encoder,
              const render::Camera& camera, std::vector<std::uint8_t>& jpeg) const;

 private:
  const Snapshot* snapshot_ = nullptr;
  sim::Points V_, N_;
  std::vector<double> scratch_;
  std::vector<render::ToolView> tools_;
  std::vector<render::MarkView> marks_;
  std::vector<render::MarkView> zones_;
};

// The camera of a viewer's picture of a snapshot in an image of this aspect: the outside view if
// asked for; else the scope on a device once it has reported (scope_view); else the session's.
render::Camera picture_camera(const Snapshot& snapshot, const render::Camera& session,
                              const render::Camera& outside, bool outside_view, double aspect);

// How a scene is drawn: the default style, each tissue label of the scene in its tissue's look
// (SurgicalSceneSetup::tissue_names: the liver's red-brown and its capsule's vessels, the
// meniscus's and ligament's white with fine vessels) and the surroundings with their vessels
// (the synovium's and the peritoneum's).
render::SceneStyle scene_style(const sim::surgery::SurgicalSceneSetup& setup);

// The zones of a task the trainee is shown ("visible": true in the curriculum): its targets and
// its protected zones (never-zones apart), as translucent balls.
std::vector<render::MarkView> task_zones(const curriculum::Task& task);

// The scene's surroundings (SurgicalSceneSetup::surroundings) as the renderer takes them, each in
// style's look for its kind. They point into setup, which must outlive them.
std::vector<render::StaticSurface> static_surfaces(const sim::surgery::SurgicalSceneSetup& setup,
                                                   const render::SceneStyle& style);

class FrameStreamer final : private RenderPool::Client {
 public:
  // Joins pool (the process's shared one by default). source must outlive the streamer. camera:
  // the session's picture (a scope on a device replaces it once it reports); outside: the view
  // from outside the body; scene: the style and the surroundings drawn around the tissue (null:
  // the default style, none); zones: drawn in every picture (task_zones).
  FrameStreamer(const StreamSource& source, render::Camera camera, render::Camera outside,
                std::shared_ptr<const sim::surgery::SurgicalSceneSetup> scene = nullptr,
                std::vector<render::MarkView> zones = {}, RenderPool& pool = RenderPool::shared());
  ~FrameStreamer() override;  // leaves the pool once a pass in progress is over
  FrameStreamer(const FrameStreamer&) = delete;
  FrameStreamer& operator=(const FrameStreamer&) = delete;

  void add(const std::shared_ptr<FrameSink>& sink);
  // Asks the render thread for a pass (a new snapshot or a viewer acknowledged a frame).
  void poke();

  // Empty while rendering works; else why it stopped (e.g. no EGL display), for the metrics.
  std::string error() const;
  std::int64_t frames_rendered() const { return frames_rendered_.load(); }

 private:
  struct Pictures;  // the renderer and encoders, in the render thread's context
  void render(std::unique_ptr<RenderPool::ContextState>& state) override;
  void failed(const std::string& why) override;

  static constexpr std::size_t kMaxEncoders = 4;

  const StreamSource& source_;
  render::Camera camera_;
  render::Camera outside_;
  std::shared_ptr<const sim::surgery::SurgicalSceneSetup> scene_;
  std::vector<render::MarkView> zones_;
  mutable std::mutex mutex_;
  struct Entry {
    std::weak_ptr<FrameSink> sink;
    std::int64_t last_tick = -1;
    std::uint64_t last_version = 0;
    std::uint32_t next_frame = 1;
  };
  std::vector<Entry> sinks_;
  std::string error_;
  std::atomic<std::int64_t> frames_rendered_{0};
  RenderPool::Membership membership_;  // last: joined once everything above is in place
};

}  // namespace incise::server::live
