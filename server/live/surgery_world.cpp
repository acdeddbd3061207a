#include "server/live/surgery_world.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace incise::server::live {

sim::surgery::ToolInput tool_input(const devices::DeviceState& state) {
  sim::surgery::ToolInput in;
  in.tip = {state.position.x, state.position.y, state.position.z};
  const Eigen::Quaternion<sim::Real> q(state.orientation.w, state.orientation.x,
                                       state.orientation.y, state.orientation.z);
  // The protocol's decoder accepts only finite, near-unit quaternions; a zero one reads as
  // identity rather than dividing by zero.
  in.orientation = q.norm() > 0 ? q.normalized() : Eigen::Quaternion<sim::Real>::Identity();
  in.jaw = static_cast<sim::Real>(state.jaw);
  in.buttons = state.buttons;
  return in;
}

SurgeryWorld::SurgeryWorld(std::shared_ptr<const sim::surgery::SurgicalSceneSetup> setup,
                           double tick_s)
    : setup_(std::move(setup)) {
  const double dt = setup_->spec.dt;
  if (!(tick_s > 0) || !(dt > 0)) throw std::invalid_argument("tick and dt must be positive");
  // ceil with a tolerance, so that a tick that is a whole number of dt keeps dt.
  substeps_ = static_cast<int>(std::ceil(tick_s / dt - 1e-9));
  if (substeps_ < 1 || substeps_ > 10000) {
    throw std::invalid_argument("the tick " + std::to_string(tick_s) + " s needs " +
                                std::to_string(substeps_) + " steps of the scene's dt " +
                                std::to_string(dt) + " s");
  }
  dt_ = tick_s / substeps_;
  reset();
}

void SurgeryWorld::reset() {
  sim::surgery::SurgicalSceneSpec spec = setup_->spec;
  spec.dt = dt_;
  scene_ = std::make_unique<sim::surgery::SurgicalScene>(std::move(spec));
  contacts_ = {};
  events_.clear();
  surface_.reset();
  cut_walls_.reset();
  follow_surface();
}

void SurgeryWorld::tick(std::span<const devices::DeviceState> from,
                        std::span<const devices::DeviceState> to) {
  std::array<sim::surgery::ToolInput, 2> a;
  std::array<sim::surgery::ToolInput, 2> b;
  const std::size_t hands = std::min({from.size(), to.size(), a.size()});
  inputs_.resize(hands);
  for (std::size_t h = 0; h < hands; ++h) {
    a[h] = tool_input(from[h]);
    b[h] = tool_input(to[h]);
  }
  events_.clear();
  for (int s = 1; s <= substeps_; ++s) {
    const double t = static_cast<double>(s) / substeps_;
    for (std::size_t h = 0; h < hands; ++h) {
      sim::surgery::ToolInput& in = inputs_[h];
      in.tip = (1 - t) * a[h].tip + t * b[h].tip;
      in.orientation = a[h].orientation.slerp(t, b[h].orientation);
      in.jaw = (1 - t) * a[h].jaw + t * b[h].jaw;
      in.buttons = b[h].buttons;
    }
    scene_->step(inputs_);
    for (auto& e : scene_->take_events())
      events_.push_back(std::move(e));
  }
  for (std::size_t h = 0; h < contacts_.size(); ++h) {
    sim::ToolContact& c = contacts_[h];
    c = {};
    if (h >= hands) continue;
    const auto model = scene_->force_model(static_cast<int>(h));
    c.force_on_tool = model.force;
    c.stiffness = model.stiffness;
    for (int k = 0; k < scene_->num_tools(); ++k) {
      if (setup_->spec.tools[static_cast<std::size_t>(k)].device != static_cast<int>(h)) continue;
      if (scene_->tool_view(k).touching) c.nodes_in_contact = 1;
    }
  }
  follow_surface();
}

std::vector<sim::Vec3> SurgeryWorld::marked_line() const {
  const sim::TetMesh& mesh = scene_->tissue().mesh();
  const std::vector<int>& nodes = surface_->nodes;
  std::vector<sim::Vec3> out;
  out.reserve(setup_->cut_target.size());
  for (const sim::Vec3& p : setup_->cut_target) {
    int nearest = -1;
    double best = 0;
    for (const int n : nodes) {
      const double d = (mesh.rest.row(n).transpose() - p).squaredNorm();
      if (nearest < 0 || d < best) {
        nearest = n;
        best = d;
      }
    }
    out.push_back(nearest < 0
                      ? p
                      : sim::Vec3(p + (mesh.x.row(nearest) - mesh.rest.row(nearest)).transpose()));
  }
  return out;
}

void SurgeryWorld::follow_surface() {
  const sim::BoundarySurface& now = scene_->tissue().surface();
  if (surface_ && surface_->nodes == now.nodes && surface_->faces.rows() == now.faces.rows() &&
      surface_->faces == now.faces) {
    return;
  }
  surface_ = std::make_shared<const sim::BoundarySurface>(now);
  const sim::TetMesh& mesh = scene_->tissue().mesh();
  auto labels = std::make_shared<std::vector<std::uint8_t>>(now.tets.size());
  for (std::size_t f = 0; f < now.tets.size(); ++f) {
    const int t = now.tets[f];
    const int label = t < mesh.labels.size() ? mesh.labels[t] : 0;
    (*labels)[f] = static_cast<std::uint8_t>(std::clamp(label, 0, 255));
  }
  face_labels_ = std::move(labels);
  auto rest = std::make_shared<sim::Points>(static_cast<Eigen::Index>(now.nodes.size()), 3);
  for (std::size_t j = 0; j < now.nodes.size(); ++j)
    rest->row(static_cast<Eigen::Index>(j)) = mesh.rest.row(now.nodes[j]);
  surface_rest_ = std::move(rest);
  if (setup_->tools_stand_for_any) return;  // the palpation block: nothing cuts it
  if (!cut_walls_) cut_walls_.emplace(mesh.rest, scene_->tissue().surface_faces());
  auto flags = std::make_shared<std::vector<std::uint8_t>>();
  cut_walls_->classify(mesh.rest, now, *flags);
  cut_faces_ = std::move(flags);
}

}  // namespace incise::server::live
