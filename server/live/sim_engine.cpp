#include "server/live/sim_engine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "sim/interact/sphere_tool.h"

namespace incise::server::live {
namespace {

sim::Vec3 to_vec(const devices::Vec3& v) {
  return {v.x, v.y, v.z};
}
devices::Vec3 to_device(const sim::Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

}  // namespace

SimEngine::SimEngine(const SessionScene& scene, double tick_s, int hands)
    : tick_s_(tick_s), hands_(hands) {
  if (hands < 1 || hands > kMaxHands) {
    throw std::invalid_argument("a session has 1 or 2 hands, not " + std::to_string(hands));
  }
  world_ = std::make_unique<SurgeryWorld>(scene.shared_setup(), tick_s);
}

const sim::Points& SimEngine::positions() const {
  return world_->scene().tissue().mesh().x;
}

std::shared_ptr<const sim::BoundarySurface> SimEngine::surface() const {
  return world_->surface();
}

sim::tools::DamageMetrics SimEngine::damage() const {
  return world_->scene().damage();
}

bool SimEngine::state_finite() const {
  return world_->scene().state_finite();
}

double SimEngine::tool_radius(int hand) const {
  for (const auto& tool : world_->setup().spec.tools) {
    if (tool.device == hand && tool.kind == sim::surgery::ToolKind::probe) return tool.probe.radius;
  }
  return sim::SphereTool{}.radius;
}

void SimEngine::tick(const devices::DeviceState& input) {
  tick(std::span<const devices::DeviceState>(&input, 1));
}

void SimEngine::tick(std::span<const devices::DeviceState> inputs) {
  const int n = std::min(hands_, static_cast<int>(inputs.size()));
  const auto count = static_cast<std::size_t>(n);
  const sim::Vec3 parked(0, 0, kParkedToolHeight);
  std::array<devices::DeviceState, kMaxHands> from;
  for (std::size_t i = 0; i < count; ++i)
    from[i] = hand_[i].has_input ? hand_[i].last_input : inputs[i];
  // A later hand that has not reported yet (parked, never moved) stays out of the scene: a tool
  // made at the park would sweep in from there onto the first surface on the way when the hand's
  // first state arrives, instead of entering where the hand is (surgical_scene_tool.h).
  std::size_t in_scene = count;
  while (in_scene > 1 && !hand_[in_scene - 1].has_input &&
         to_vec(inputs[in_scene - 1].position) == parked) {
    --in_scene;
  }
  world_->tick(std::span<const devices::DeviceState>(from.data(), in_scene),
               inputs.first(in_scene));
  for (std::size_t i = 0; i < count; ++i) {
    Hand& hand = hand_[i];
    hand.contact = world_->contact(static_cast<int>(i));
    const sim::Vec3 to = to_vec(inputs[i].position);
    if (hand.has_input) hand.path_length_m += (to - hand.tip).norm();
    hand.tip = to;
    // A hand at the parked position has not reported yet (a two-handed session's second device
    // comes a little later): its first real state must not sweep it in from the park.
    hand.has_input = to != parked;
    hand.last_input = inputs[i];
  }
  const sim::ToolContact& primary = hand_[0].contact;
  metrics_.path_length_m = hand_[0].path_length_m;
  const double force = primary.force_on_tool.norm();
  metrics_.peak_force_n = std::max(metrics_.peak_force_n, force);
  metrics_.force_squared_time += force * force * tick_s_;
  if (primary.nodes_in_contact > 0) ++metrics_.contact_ticks;
  ++ticks_;
  if (!world_->events().empty()) {
    scene_events_.add(world_->events(), time_s(), world_->setup().spec.tools, damage());
  }
}

devices::ForceModel SimEngine::force_model(int hand) const {
  const Hand& h = hand_[static_cast<std::size_t>(hand)];
  devices::ForceModel model;
  model.device_index = static_cast<std::uint8_t>(hand);
  model.reference_position = to_device(h.tip);
  // Whatever the simulation did, the agent gets a model its decoder accepts: a non-finite contact
  // sends no force at all, the force is clamped to kMaxForceN and each stiffness entry to the
  // protocol's bound.
  sim::Vec3 force = h.contact.force_on_tool;
  sim::Mat3 stiffness = h.contact.stiffness;
  if (!force.allFinite() || !stiffness.allFinite()) {
    force.setZero();
    stiffness.setZero();
  }
  const double magnitude = force.norm();
  if (magnitude > kMaxForceN) force *= kMaxForceN / magnitude;
  model.force = to_device(force);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      model.stiffness[static_cast<std::size_t>(3 * r + c)] =
          std::clamp(stiffness(r, c), -devices::kMaxModelStiffness, devices::kMaxModelStiffness);
  model.sim_time_s = time_s();
  return model;
}

SimEngine::Checkpoint SimEngine::checkpoint() const {
  return {hand_, metrics_, ticks_, std::make_shared<const SurgeryWorld>(*world_), scene_events_};
}

void SimEngine::restore(const Checkpoint& c) {
  if (!c.world) throw std::invalid_argument("restore: the checkpoint holds no world");
  *world_ = *c.world;
  scene_events_ = c.scene_events;
  hand_ = c.hands;
  metrics_ = c.metrics;
  ticks_ = c.ticks;
}

std::string SimEngine::state_hash() const {
  const auto& x = positions();
  std::uint64_t h = 14695981039346656037ull;
  const auto* bytes = reinterpret_cast<const unsigned char*>(x.data());
  const std::size_t n = static_cast<std::size_t>(x.size()) * sizeof(double);
  for (std::size_t i = 0; i < n; ++i) {
    h ^= bytes[i];
    h *= 1099511628211ull;
  }
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

std::shared_ptr<Snapshot> make_snapshot(const SimEngine& engine) {
  auto s = std::make_shared<Snapshot>();
  s->tick = engine.ticks();
  s->sim_time_s = engine.time_s();
  s->surface = engine.surface();
  s->cut_faces = engine.world().cut_faces();
  s->face_labels = engine.world().face_labels();
  s->surface_rest = engine.world().surface_rest();
  s->positions = engine.positions();
  s->tool_tip = engine.tool_tip();
  s->tool_radius = engine.tool_radius();
  s->hands = engine.hands();
  if (engine.hands() > 1) {
    s->second_tool_tip = engine.tool_tip(1);
    s->second_force_n = engine.contact(1).force_on_tool;
  }
  s->contact = engine.contact().nodes_in_contact > 0;
  s->force_n = engine.contact().force_on_tool;
  s->peak_force_n = engine.metrics().peak_force_n;
  s->path_length_m = engine.metrics().path_length_m;
  const auto damage = engine.damage();
  s->damage_index = damage.damage_index;
  s->peak_strain = damage.peak_strain;
  const SurgeryWorld& world = engine.world();
  s->cutting = !world.setup().tools_stand_for_any;
  s->marks = world.marked_line();
  // The tool points along R e_z (tip forwards); its shaft runs back the other way. The block's
  // probes stand upright, whatever their devices' orientation.
  if (!world.setup().tools_stand_for_any) {
    for (int h = 0; h < engine.hands(); ++h) {
      s->shaft_direction[static_cast<std::size_t>(h)] =
          -(tool_input(engine.last_input(h)).orientation * sim::Vec3::UnitZ());
    }
    const sim::surgery::SurgicalScene& scene = world.scene();
    for (int t = 0; t < scene.num_tools(); ++t) {
      sim::surgery::ToolView view = scene.tool_view(t);
      if (view.kind != sim::surgery::ToolKind::scope && view.has_input) {
        s->instruments.push_back(std::move(view));
      }
    }
    s->scope = scene.scope_camera();
    s->inverted_tets_pulled = scene.inverted_tets_pulled();
  }
  s->cut_area_m2 = damage.cut_area;
  s->cut_mean_distance_m = damage.cut_mean_distance;
  s->never_event = damage.never_event;
  s->published_at = std::chrono::steady_clock::now();
  return s;
}

}  // namespace incise::server::live
