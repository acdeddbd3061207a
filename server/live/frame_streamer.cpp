#include "server/live/frame_streamer.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <iostream>
#include <map>
#include <span>
#include <tuple>

#include "server/live/session_scene.h"
#include "sim/render/cut_opening.h"
#include "sim/render/frame_encoder.h"
#include "sim/render/scene_renderer.h"

namespace incise::server::live {
namespace {

// The marked cut line's ink dots [m].
constexpr double kMarkRadius = 0.0015;
// How far the picture opens a cut at the surface [m] (render/cut_opening.h): the gape of an
// incision in living tissue, which the simulation (no pre-stress) does not open by itself.
constexpr double kCutGape = 0.0025;

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

// A surgical scene's instrument as the renderer draws it: the pose simulated, its working end.
render::ToolView drawn(const sim::surgery::ToolView& tool) {
  render::ToolView view;
  view.tip = tool.tip;
  view.shaft_direction = -tool.direction;
  view.shaft_length = tool.shaft_length;
  view.shaft_radius = tool.shaft_radius;
  view.in_contact = tool.touching;
  view.side = tool.side;
  switch (tool.kind) {
    case sim::surgery::ToolKind::scalpel:
      view.shape = render::ToolShape::scalpel;
      view.blade_length = tool.blade_length;
      break;
    case sim::surgery::ToolKind::grasper:
      view.shape = render::ToolShape::grasper;
      view.jaw_angle = tool.jaw_angle;
      view.jaw_length = tool.jaw_length;
      break;
    default:
      view.shape = render::ToolShape::probe;
      view.radius = tool.tip_radius > 0 ? tool.tip_radius : view.radius;
      break;
  }
  return view;
}

}  // namespace

void SnapshotPicture::prepare(const Snapshot& snapshot) {
  snapshot_ = &snapshot;
  sim::surface_vertices(*snapshot.surface, snapshot.positions, V_, N_);
  if (snapshot.cut_faces) {
    render::open_cut_walls(snapshot.surface->faces, *snapshot.cut_faces, kCutGape, V_, scratch_);
  }
  tools_.clear();
  if (!snapshot.cutting) {
    // The palpation block's probes, upright at each hand (its probes stand for any tool).
    for (int h = 0; h < snapshot.hands && h < 2; ++h) {
      render::ToolView& t = tools_.emplace_back();
      t.tip = h == 0 ? snapshot.tool_tip : snapshot.second_tool_tip;
      t.radius = snapshot.tool_radius;
      t.in_contact = h == 0 ? snapshot.contact : snapshot.second_force_n.squaredNorm() > 0;
      t.shaft_direction = snapshot.shaft_direction[static_cast<std::size_t>(h)];
    }
  } else {
    // Without the scopes (make_snapshot leaves them out): a scope is the camera.
    for (const sim::surgery::ToolView& instrument : snapshot.instruments)
      tools_.push_back(drawn(instrument));
  }
  marks_.clear();
  for (const sim::Vec3& p : snapshot.marks)
    marks_.push_back({p, kMarkRadius});
  marks_.insert(marks_.end(), zones_.begin(), zones_.end());
}

void SnapshotPicture::encode(render::SceneRenderer& renderer, render::FrameEncoder& encoder,
                             const render::Camera& camera, std::vector<std::uint8_t>& jpeg) const {
  render::TissueView tissue{&V_, &N_, &snapshot_->surface->faces};
  tissue.cut_faces = snapshot_->cut_faces.get();
  tissue.face_labels = snapshot_->face_labels.get();
  tissue.rest = snapshot_->surface_rest.get();
  encoder.render_jpeg(renderer, camera, tissue, tools_, jpeg, marks_);
}

render::Camera picture_camera(const Snapshot& snapshot, const render::Camera& session,
                              const render::Camera& outside, bool outside_view, double aspect) {
  if (outside_view) return outside;
  if (snapshot.scope) return scope_view(*snapshot.scope, aspect);
  return session;
}

namespace {

// A look with a vessel pattern: vessels of colour `vessel`, `strength` in [0, 1], `spacing` apart.
render::SurfaceLook with_vessels(render::SurfaceLook look, float strength, float spacing_m,
                                 const Eigen::Vector3f& vessel) {
  look.vessels = strength;
  look.vessel_spacing_m = spacing_m;
  look.vessel_albedo = vessel;
  return look;
}

// The look of a tissue by its name (SurgicalSceneSetup::tissue_names); nullopt: the default.
// Glisson's capsule over the parenchyma shows a fine net of vessels; the fibrocartilage of a
// meniscus is white with a few vessels at its rim; the ACL's synovial sheath is vascular.
std::optional<render::SurfaceLook> tissue_look(const std::string& name) {
  struct Named {
    const char* name;
    render::SurfaceLook look;
    float vessels, spacing_m;
    Eigen::Vector3f vessel;
  };
  static const Named kLooks[] = {
      {"liver", {{0.72f, 0.30f, 0.24f}, 0.30f, 40.0f}, 0.45f, 0.012f, {0.38f, 0.05f, 0.10f}},
      {"gallbladder bed",
       {{0.62f, 0.52f, 0.30f}, 0.30f, 40.0f},
       0.35f,
       0.010f,
       {0.30f, 0.22f, 0.10f}},
      {"meniscus", {{0.93f, 0.92f, 0.90f}, 0.35f, 40.0f}, 0.15f, 0.006f, {0.78f, 0.42f, 0.42f}},
      {"ligament", {{0.92f, 0.87f, 0.78f}, 0.35f, 40.0f}, 0.35f, 0.004f, {0.72f, 0.25f, 0.24f}},
  };
  for (const Named& n : kLooks) {
    if (name == n.name) return with_vessels(n.look, n.vessels, n.spacing_m, n.vessel);
  }
  return std::nullopt;
}

}  // namespace

render::SceneStyle scene_style(const sim::surgery::SurgicalSceneSetup& setup) {
  render::SceneStyle style;
  for (const auto& [label, name] : setup.tissue_names) {
    if (const auto look = tissue_look(name)) style.tissue_by_label[label] = *look;
  }
  // The synovium lining the joint and the peritoneum over the abdominal wall and the neighbours
  // carry the vessels a scope's view is full of.
  style.lining = with_vessels(style.lining, 0.40f, 0.010f, {0.45f, 0.06f, 0.08f});
  style.organ = with_vessels(style.organ, 0.30f, 0.018f, {0.40f, 0.08f, 0.12f});
  style.fat = with_vessels(style.fat, 0.25f, 0.015f, {0.60f, 0.20f, 0.12f});
  return style;
}

std::vector<render::MarkView> task_zones(const curriculum::Task& task) {
  std::vector<render::MarkView> zones;
  const auto centre = [](const curriculum::Zone& z) {
    return sim::Vec3(z.center_m[0], z.center_m[1], z.center_m[2]);
  };
  for (const curriculum::Zone& target : task.targets) {
    if (target.visible)
      zones.push_back({centre(target), target.radius_m, render::MarkKind::target});
  }
  for (const curriculum::ProtectedZone& zone : task.protected_zones) {
    if (!zone.zone.visible) continue;
    zones.push_back({centre(zone.zone), zone.zone.radius_m,
                     zone.never ? render::MarkKind::never_zone : render::MarkKind::protected_zone});
  }
  return zones;
}

std::vector<render::StaticSurface> static_surfaces(const sim::surgery::SurgicalSceneSetup& setup,
                                                   const render::SceneStyle& style) {
  using Kind = sim::surgery::SurroundingKind;
  std::vector<render::StaticSurface> out;
  for (const sim::surgery::Surrounding& s : setup.surroundings) {
    render::StaticSurface surface;
    surface.V = &s.vertices;
    surface.F = &s.triangles;
    switch (s.kind) {
      case Kind::bone:
        surface.look = style.bone;
        break;
      case Kind::wall:
        surface.look = style.lining;
        break;
      case Kind::organ:
        surface.look = style.organ;
        break;
      case Kind::fat:
        surface.look = style.fat;
        break;
    }
    surface.inside_only = s.inside_only;
    out.push_back(surface);
  }
  return out;
}

// What a streamer keeps in its render thread's context: one renderer in the scene's style with its
// surroundings, and one encoder per frame size in use. Viewers choose their size, so the set is
// capped: the least recently used encoder goes when a new size needs room (each holds a
// framebuffer and buffers).
struct FrameStreamer::Pictures : RenderPool::ContextState {
  Pictures(const sim::surgery::SurgicalSceneSetup* scene, std::vector<render::MarkView> zones)
      : renderer(scene ? scene_style(*scene) : render::SceneStyle{}) {
    if (scene) renderer.set_surroundings(static_surfaces(*scene, renderer.style()));
    picture.set_zones(std::move(zones));
  }
  struct Encoder {
    std::unique_ptr<render::FrameEncoder> encoder;
    std::int64_t last_used = 0;
  };
  struct Job {
    std::shared_ptr<FrameSink> sink;
    FrameSink::Request request;
    std::uint32_t frame_number;
  };
  render::SceneRenderer renderer;
  std::map<std::pair<int, int>, Encoder> encoders;
  std::int64_t pass = 0;
  std::vector<std::uint8_t> jpeg;
  SnapshotPicture picture;
  std::vector<Job> jobs;
};

FrameStreamer::FrameStreamer(const StreamSource& source, render::Camera camera,
                             render::Camera outside,
                             std::shared_ptr<const sim::surgery::SurgicalSceneSetup> scene,
                             std::vector<render::MarkView> zones, RenderPool& pool)
    : source_(source),
      camera_(std::move(camera)),
      outside_(std::move(outside)),
      scene_(std::move(scene)),
      zones_(std::move(zones)),
      membership_(pool.join(*this)) {}

// Leaving first: the render thread may be in a pass over this streamer's members.
FrameStreamer::~FrameStreamer() {
  membership_ = {};
}

void FrameStreamer::add(const std::shared_ptr<FrameSink>& sink) {
  {
    std::lock_guard lock(mutex_);
    sinks_.push_back({sink});
  }
  poke();
}

void FrameStreamer::poke() {
  membership_.poke();
}

std::string FrameStreamer::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

// The viewers see it as render_error, and the session runs on without pictures.
void FrameStreamer::failed(const std::string& why) {
  std::lock_guard lock(mutex_);
  error_ = why;
  std::cerr << "incise-server: " << why << "\n";
}

void FrameStreamer::render(std::unique_ptr<RenderPool::ContextState>& state) {
  if (!state) state = std::make_unique<Pictures>(scene_.get(), zones_);
  Pictures& pictures = static_cast<Pictures&>(*state);
  auto& renderer = pictures.renderer;
  auto& encoders = pictures.encoders;
  auto& jpeg = pictures.jpeg;
  auto& picture = pictures.picture;
  auto& jobs = pictures.jobs;
  const auto snapshot = source_.snapshot();
  if (!snapshot) return;
  const auto now = SteadyClock::now();
  // Collect the viewers that want this snapshot, without holding the lock while rendering.
  jobs.clear();
  {
    std::lock_guard lock(mutex_);
    std::erase_if(sinks_, [](const Entry& e) { return e.sink.expired(); });
    for (auto& entry : sinks_) {
      auto sink = entry.sink.lock();
      if (!sink) continue;
      const std::uint64_t version = sink->settings_version();
      if (entry.last_tick == snapshot->tick && entry.last_version == version) continue;
      const auto request = sink->frame_wanted(now);
      if (!request) continue;
      entry.last_tick = snapshot->tick;
      entry.last_version = version;
      jobs.push_back({std::move(sink), *request, entry.next_frame++});
    }
  }
  if (jobs.empty()) return;
  const std::int64_t pass = ++pictures.pass;
  picture.prepare(*snapshot);
  // Viewers asking for the same size share one rendering.
  std::map<std::tuple<int, int, bool>, std::shared_ptr<const std::vector<std::uint8_t>>> rendered;
  for (auto& job : jobs) {
    const std::pair size{job.request.width, job.request.height};
    auto& jpeg_of_size = rendered[{size.first, size.second, job.request.outside}];
    if (!jpeg_of_size) {
      auto it = encoders.find(size);
      if (it == encoders.end()) {
        if (encoders.size() >= kMaxEncoders) {
          encoders.erase(
              std::min_element(encoders.begin(), encoders.end(), [](const auto& a, const auto& b) {
                return a.second.last_used < b.second.last_used;
              }));
        }
        it = encoders
                 .emplace(size,
                          Pictures::Encoder{
                              std::make_unique<render::FrameEncoder>(size.first, size.second), 0})
                 .first;
      }
      it->second.last_used = pass;
      const render::Camera camera =
          picture_camera(*snapshot, camera_, outside_, job.request.outside,
                         static_cast<double>(size.first) / size.second);
      picture.encode(renderer, *it->second.encoder, camera, jpeg);
      ++frames_rendered_;
      jpeg_of_size = std::make_shared<const std::vector<std::uint8_t>>(jpeg);
    }
    job.sink->deliver(job.frame_number,
                      frame_message(job.frame_number, size.first, size.second, snapshot->sim_time_s,
                                    *jpeg_of_size),
                      snapshot->published_at);
  }
  jobs.clear();  // the sinks are not held between passes
}

}  // namespace incise::server::live
