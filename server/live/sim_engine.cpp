#include "server/live/sim_engine.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace incise::server::live {
namespace {

sim::Vec3 to_vec(const devices::Vec3& v) {
  return {v.x, v.y, v.z};
}
devices::Vec3 to_device(const sim::Vec3& v) {
  return {v.x(), v.y(), v.z()};
}

int substeps_for(const sim::Scene& scene, double tick_s) {
  const double dt = scene.solver.dt;
  if (!(tick_s > 0) || !(dt > 0)) throw std::invalid_argument("tick and dt must be positive");
  const double n = tick_s / dt;
  const double rounded = std::round(n);
  if (rounded < 1 || std::abs(n - rounded) > 1e-9 * rounded) {
    throw std::invalid_argument("the tick " + std::to_string(tick_s) +
                                " s is not a whole number of solver.dt " + std::to_string(dt) +
                                " s");
  }
  return static_cast<int>(rounded);
}

// One strain threshold (kDamageStrain) for every tissue label of the mesh.
sim::tools::DamageSettings damage_settings(const sim::TetMesh& mesh) {
  std::vector<int> labels(mesh.labels.data(), mesh.labels.data() + mesh.labels.size());
  if (labels.empty()) labels.push_back(0);
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  sim::tools::DamageSettings settings;
  for (const int label : labels)
    settings.strain_thresholds.push_back({label, kDamageStrain});
  return settings;
}

}  // namespace

SimEngine::SimEngine(const SessionScene& scene, double tick_s, int hands)
    : tick_s_(tick_s), hands_(hands) {
  if (hands < 1 || hands > kMaxHands) {
    throw std::invalid_argument("a session has 1 or 2 hands, not " + std::to_string(hands));
  }
  if (const auto* surgery = scene.surgery()) {
    surgery_ = std::make_unique<SurgeryWorld>(*surgery, tick_s);
    substeps_ = surgery_->substeps();
    return;
  }
  const sim::Scene& block = *scene.block();
  substeps_ = substeps_for(block, tick_s);
  simulation_.emplace(block);
  surface_ =
      std::make_shared<const sim::BoundarySurface>(sim::boundary_surface(simulation_->mesh()));
  tool_ = block.tool.value_or(sim::SphereTool{});
  node_forces_ = sim::Points::Zero(simulation_->mesh().num_nodes(), 3);
  damage_.emplace(simulation_->mesh(), damage_settings(simulation_->mesh()));
}

const sim::Points& SimEngine::positions() const {
  return surgery_ ? surgery_->scene().tissue().mesh().x : simulation_->mesh().x;
}

std::shared_ptr<const sim::BoundarySurface> SimEngine::surface() const {
  return surgery_ ? surgery_->surface() : surface_;
}

sim::tools::DamageMetrics SimEngine::damage() const {
  return surgery_ ? surgery_->scene().damage() : damage_->metrics();
}

bool SimEngine::state_finite() const {
  return surgery_ ? surgery_->scene().state_finite() : simulation_->state_finite();
}

void SimEngine::tick(const devices::DeviceState& input) {
  tick(std::span<const devices::DeviceState>(&input, 1));
}

void SimEngine::tick(std::span<const devices::DeviceState> inputs) {
  const int n = std::min(hands_, static_cast<int>(inputs.size()));
  std::array<sim::Vec3, kMaxHands> from;
  std::array<sim::Vec3, kMaxHands> to;
  std::array<devices::DeviceState, kMaxHands> from_input;
  for (int h = 0; h < n; ++h) {
    const auto i = static_cast<std::size_t>(h);
    to[i] = to_vec(inputs[i].position);
    from[i] = hand_[i].has_input ? hand_[i].tip : to[i];
    from_input[i] = hand_[i].has_input ? hand_[i].last_input : inputs[i];
  }
  if (surgery_) {
    const auto count = static_cast<std::size_t>(n);
    surgery_->tick(std::span<const devices::DeviceState>(from_input.data(), count),
                   inputs.first(count));
    for (std::size_t i = 0; i < count; ++i)
      hand_[i].contact = surgery_->contact(static_cast<int>(i));
  } else {
    for (int s = 1; s <= substeps_; ++s) {
      const double a = static_cast<double>(s) / substeps_;
      node_forces_.setZero();
      for (int h = 0; h < n; ++h) {
        const auto i = static_cast<std::size_t>(h);
        const sim::Vec3 centre = (1 - a) * from[i] + a * to[i];
        hand_[i].contact = sim::apply_sphere_contact(tool_, centre, *surface_,
                                                     simulation_->mesh().x, node_forces_);
      }
      simulation_->step(node_forces_);
    }
  }
  const sim::Vec3 parked(0, 0, kParkedToolHeight);
  for (int h = 0; h < n; ++h) {
    const auto i = static_cast<std::size_t>(h);
    hand_[i].path_length_m += (to[i] - from[i]).norm();
    hand_[i].tip = to[i];
    // A hand at the parked position has not reported yet (a two-handed session's second device
    // comes a little later): its first real state must not sweep it in from the park.
    hand_[i].has_input = to[i] != parked;
    hand_[i].last_input = inputs[i];
  }
  const sim::ToolContact& primary = hand_[0].contact;
  metrics_.path_length_m = hand_[0].path_length_m;
  const double force = primary.force_on_tool.norm();
  metrics_.peak_force_n = std::max(metrics_.peak_force_n, force);
  metrics_.force_squared_time += force * force * tick_s_;
  if (primary.nodes_in_contact > 0) ++metrics_.contact_ticks;
  ++ticks_;
  if (surgery_ && !surgery_->events().empty()) {
    scene_events_.add(surgery_->events(), time_s(), surgery_->setup().spec.tools, damage());
  }
  // A non-finite state is the session's to report (state_finite); the damage stays as it was.
  // (A surgical scene tracks its own damage, every spec.damage_every steps.)
  if (damage_ && ticks_ % kDamageEvery == 0 && simulation_->state_finite()) {
    damage_->record_strain(simulation_->mesh().x, kDamageEvery * tick_s_);
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
  if (surgery_) {
    return {{},           hand_,   metrics_,
            ticks_,       nullptr, std::make_shared<const SurgeryWorld>(*surgery_),
            scene_events_};
  }
  return {simulation_->save_state(),
          hand_,
          metrics_,
          ticks_,
          std::make_shared<const sim::tools::DamageTracker>(*damage_),
          nullptr,
          {}};
}

void SimEngine::restore(const Checkpoint& c) {
  if (surgery_) {
    if (!c.surgery) throw std::logic_error("restore: the checkpoint is not of a surgical scene");
    *surgery_ = *c.surgery;
    scene_events_ = c.scene_events;
  } else {
    simulation_->restore_state(c.simulation);
    if (c.damage) *damage_ = *c.damage;
  }
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
  s->positions = engine.positions();
  s->tool_tip = engine.tool_tip();
  s->tool_radius = engine.tool().radius;
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
  s->surgical = engine.surgery() != nullptr;
  if (const SurgeryWorld* world = engine.surgery()) {
    s->marks = world->marked_line();
    // The tool points along R e_z (tip forwards); its shaft runs back the other way.
    for (int h = 0; h < engine.hands(); ++h) {
      s->shaft_direction[static_cast<std::size_t>(h)] =
          -(tool_input(engine.last_input(h)).orientation * sim::Vec3::UnitZ());
    }
  }
  s->cut_area_m2 = damage.cut_area;
  s->cut_mean_distance_m = damage.cut_mean_distance;
  s->never_event = damage.never_event;
  s->published_at = std::chrono::steady_clock::now();
  return s;
}

}  // namespace incise::server::live
