#include "sim/tools/probe.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/tools/swept_tool_motion.h"
#include "sim/tools/tool_checks.h"

namespace incise::sim::tools {
namespace {

const ProbeSettings& checked(const ProbeSettings& settings) {
  checks::check_radius(settings.radius, "Probe");
  if (!(settings.coupling_stiffness > 0) || !std::isfinite(settings.coupling_stiffness)) {
    throw std::invalid_argument("Probe: coupling_stiffness must be finite and > 0, got " +
                                std::to_string(settings.coupling_stiffness));
  }
  if (!(settings.allowed_penetration > 0 && settings.allowed_penetration < settings.radius)) {
    throw std::invalid_argument(
        "Probe: allowed_penetration must be in (0, radius = " + std::to_string(settings.radius) +
        "), got " + std::to_string(settings.allowed_penetration));
  }
  if (!(settings.coupling_damping_ratio >= 0) || !std::isfinite(settings.coupling_damping_ratio)) {
    throw std::invalid_argument("Probe: coupling_damping_ratio must be finite and >= 0, got " +
                                std::to_string(settings.coupling_damping_ratio));
  }
  if (!(settings.max_force > 0) || !std::isfinite(settings.max_force)) {
    throw std::invalid_argument("Probe: max_force must be finite and > 0, got " +
                                std::to_string(settings.max_force));
  }
  return settings;
}

// f scaled down to magnitude `limit` if longer.
Vec3 saturated(const Vec3& f, Real limit) {
  const Real norm = f.norm();
  return norm > limit ? Vec3(f * (limit / norm)) : f;
}

}  // namespace

Probe::Probe(ProbeSettings settings, const Vec3& position)
    : settings_(checked(settings)),
      response_(settings.contact),
      motion_(settings.radius, settings.allowed_penetration),
      proxy_(position),
      device_(position) {
  checks::check_vector(position, "Probe", "position");
  hand_model_.reference_position = position;
}

void Probe::step(const Vec3& device_position, const collide::SurfaceBvh& bvh, const Points& x,
                 const Points& v, const VecX& masses, Points& node_forces) {
  checks::check_vector(device_position, "Probe::step", "device_position");
  if (node_forces.rows() != x.rows()) {
    throw std::invalid_argument("Probe::step: x has " + std::to_string(x.rows()) +
                                " rows but node_forces " + std::to_string(node_forces.rows()));
  }
  const Vec3 start = proxy_;
  const Vec3 device_velocity = (device_position - device_) / settings_.contact.time_step;
  device_ = device_position;
  // 1. Towards the device without tunnelling.
  ToolMotion motion = motion_.move(bvh, x, proxy_, device_);
  proxy_ = motion.centre;
  blocked_ = motion.blocked;
  // 2. The nearest free position to the device among the contacts found there, reached through
  //    the swept check again (it stays inside the contacts' pocket).
  response_.evaluate(bvh, x, v, masses, tip(), Vec3::Zero());
  if (!response_.contacts().empty()) {
    const Vec3 target = nearest_free_position();
    motion = motion_.move(bvh, x, proxy_, target);
    proxy_ = motion.centre;
    blocked_ = blocked_ || motion.blocked;
  }
  const Vec3 velocity = (proxy_ - start) / settings_.contact.time_step;
  const ToolReaction& reaction = response_.evaluate(bvh, x, v, masses, tip(), velocity);

  // 3. The push, and the hand's model.
  const Real kv = settings_.coupling_stiffness;
  hand_force_ = saturated(kv * (proxy_ - device_), settings_.max_force);
  hand_model_.reference_position = device_;
  hand_model_.force = hand_force_;
  hand_model_.stiffness.setZero();
  transmitted_.setZero();
  // The proxy rests on the contacts its core touches (depth = allowed_penetration): they take
  // the push, so that the point pushed is the point that holds the proxy (the implicit push's
  // mass is then the right one). If the tissue left them all, every contact takes it.
  const Real resting = settings_.allowed_penetration - 1e-6 * settings_.radius;
  Real min_depth = 0;
  for (const ContactForce& c : response_.contacts()) {
    if (c.contact.depth >= resting) min_depth = resting;
  }
  Vec3 normal = Vec3::Zero();
  for (const ContactForce& c : response_.contacts()) {
    if (c.contact.depth >= min_depth) normal += c.elastic_force;
  }
  if (reaction.contacts == 0 || !(normal.norm() > 0)) return;
  normal.normalize();
  // The spring pulls the proxy towards the device; the massless proxy passes the pull on to the
  // tissue if it goes into the surface.
  const Vec3 pull = saturated(kv * (device_ - proxy_), settings_.max_force);
  if (!(pull.dot(normal) < 0)) return;
  const Mat3 blocked = blocked_projector();
  transmitted_ = saturated(implicit_push(pull, device_velocity, v, masses, node_forces, min_depth),
                           settings_.max_force);
  response_.distribute(transmitted_, node_forces, min_depth);
  hand_force_ = -transmitted_;
  hand_model_.force = hand_force_;
  // Saturated, the force no longer grows as the device goes deeper: no stiffness to render.
  const bool saturating = (kv * (device_ - proxy_)).norm() > settings_.max_force;
  hand_model_.stiffness = saturating ? Mat3::Zero() : Mat3(kv * blocked);
}

Vec3 Probe::implicit_push(const Vec3& pull, const Vec3& device_velocity, const Points& v,
                          const VecX& masses, const Points& other_forces, Real min_depth) {
  // The pushed point u = sum_j a_j x_j (a_j the distribution weights) has the effective mass m,
  // 1 / m = sum_j a_j^2 / m_j, velocity V0 = sum_j a_j v_j and, from the other forces g_j,
  // acceleration A = sum_j a_j g_j / m_j. The proxy rides on the surface, so the pull drops by
  // k_v dt V1 as the point moves in the step, and the coupling's damper b adds b (v_d - V1).
  // Implicit Euler on u:
  //   V1 = V0 + dt (F1 / m + A),   F1 = F0 + b v_d - (k_v dt + b) V1
  //   => (1 + dt (k_v dt + b) / m) V1 = V0 + dt ((F0 + b v_d) / m + A).
  const Real dt = settings_.contact.time_step;
  const Real kv = settings_.coupling_stiffness;
  response_.distribution_weights(weights_, min_depth);
  Real inverse_mass = 0;
  Vec3 velocity = Vec3::Zero(), acceleration = Vec3::Zero();
  for (const ToolContactResponse::NodeWeight& w : weights_) {
    const Real m = masses[w.node];
    inverse_mass += w.weight * w.weight / m;
    velocity += w.weight * row3(v, w.node);
    acceleration += (w.weight / m) * row3(other_forces, w.node);
  }
  const Real damping = 2 * settings_.coupling_damping_ratio * std::sqrt(kv / inverse_mass);
  const Vec3 driven = pull + damping * device_velocity;
  const Vec3 end_velocity = (velocity + dt * (inverse_mass * driven + acceleration)) /
                            (1 + dt * (kv * dt + damping) * inverse_mass);
  return driven - (kv * dt + damping) * end_velocity;
}

Vec3 Probe::nearest_free_position() {
  // Dykstra's alternating projections onto the half-spaces (p - q_c) . n_c >= core: they converge
  // to the point of the intersection nearest to the device (Boyle and Dykstra 1986), not just any
  // point of it as plain alternating projections would.
  const std::vector<ContactForce>& contacts = response_.contacts();
  const Real core = settings_.radius - settings_.allowed_penetration;
  corrections_.assign(contacts.size(), Vec3::Zero());
  Vec3 p = device_;
  for (int sweep = 0; sweep < kProjectionSweeps; ++sweep) {
    Real change = 0;
    for (std::size_t c = 0; c < contacts.size(); ++c) {
      const Vec3 z = p + corrections_[c];
      const Vec3& n = contacts[c].contact.normal;
      const Real gap = (z - contacts[c].contact.point).dot(n) - core;
      const Vec3 projected = gap < 0 ? Vec3(z - gap * n) : z;
      corrections_[c] = z - projected;
      change = std::max(change, (projected - p).norm());
      p = projected;
    }
    if (change <= 1e-12 * settings_.radius) break;
  }
  return p;
}

Mat3 Probe::blocked_projector() const {
  // The normals of the contacts the proxy rests on (its core touching their plane): within the
  // step the proxy follows the hand in every other direction, so the hand feels k_v along these.
  const Real core = settings_.radius - settings_.allowed_penetration;
  Vec3 basis[3];
  int count = 0;
  for (const ContactForce& c : response_.contacts()) {
    const Vec3& n = c.contact.normal;
    if ((proxy_ - c.contact.point).dot(n) > core + 1e-6 * settings_.radius) continue;
    Vec3 rest = n;
    for (int i = 0; i < count; ++i)
      rest -= rest.dot(basis[i]) * basis[i];
    if (rest.norm() > 0.05 && count < 3) basis[count++] = rest.normalized();
  }
  Mat3 projector = Mat3::Zero();
  for (int i = 0; i < count; ++i)
    projector += basis[i] * basis[i].transpose();
  return projector;
}

ContactRegion Probe::contact_region(const Points& rest) const {
  ContactRegion region;
  const std::vector<ContactForce>& contacts = response_.contacts();
  if (contacts.empty()) return region;
  Real weight = 0;
  Vec3 sum = Vec3::Zero();
  for (const ContactForce& c : contacts) {
    if (c.nodes.maxCoeff() >= rest.rows()) {
      throw std::invalid_argument("Probe::contact_region: rest has " + std::to_string(rest.rows()) +
                                  " rows, a contact uses node " +
                                  std::to_string(c.nodes.maxCoeff()));
    }
  }
  auto rest_point = [&rest](const ContactForce& c) {
    Vec3 p = Vec3::Zero();
    for (int k = 0; k < 3; ++k)
      p += c.contact.barycentric[k] * row3(rest, c.nodes[k]);
    return p;
  };
  for (const ContactForce& c : contacts) {
    // Depth-weighted; a contact at zero depth still counts a little, so the sum is never 0.
    const Real w = c.contact.depth + 1e-12;
    sum += w * rest_point(c);
    weight += w;
  }
  region.touching = true;
  region.centre = sum / weight;
  Real farthest = 0;
  for (const ContactForce& c : contacts) {
    farthest = std::max(farthest, (rest_point(c) - region.centre).norm());
  }
  region.radius = farthest + settings_.radius;
  return region;
}

}  // namespace incise::sim::tools
