#include "sim/tools/probe.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "sim/collide/inside_surface.h"
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
  if (!(settings.max_force > 0) || !std::isfinite(settings.max_force)) {
    throw std::invalid_argument("Probe: max_force must be finite and > 0, got " +
                                std::to_string(settings.max_force));
  }
  if (!(settings.contact_stiffness_ratio > 0) || !std::isfinite(settings.contact_stiffness_ratio)) {
    throw std::invalid_argument("Probe: contact_stiffness_ratio must be finite and > 0, got " +
                                std::to_string(settings.contact_stiffness_ratio));
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
                 const Points& v, const VecX& masses, Points& node_forces,
                 const VecX* inverse_masses) {
  checks::check_vector(device_position, "Probe::step", "device_position");
  if (node_forces.rows() != x.rows()) {
    throw std::invalid_argument("Probe::step: x has " + std::to_string(x.rows()) +
                                " rows but node_forces " + std::to_string(node_forces.rows()));
  }
  device_ = device_position;
  // 1. Towards the device without tunnelling, then to the point nearest the device with the tip's
  //    core outside every contact's plane, through the sweep again: the proxy seats on the
  //    surface (in a dimple, where its walls hold it) and never stays behind it.
  ToolMotion motion = motion_.move(bvh, x, proxy_, device_);
  proxy_ = motion.centre;
  blocked_ = motion.blocked;
  // A proxy enclosed by the tissue (inside it, or between faces that face each other: a flap, a
  // crack that shut over it) that the hand has pulled on at max_force for kTrappedSteps steps
  // from outside the tissue is trapped: it slips out to the device, as a real tip would tear
  // free. So is one the hand pulls back along its shaft (set_shaft). Counted in slips(). A proxy
  // on the surface never slips otherwise: a hand pressing at max_force, even through to the far
  // side of a thin part, keeps it there (no tunnelling).
  const Real kv = settings_.coupling_stiffness;
  const bool pulled_hard = (kv * (device_ - proxy_)).norm() > settings_.max_force;
  saturated_steps_ = pulled_hard ? saturated_steps_ + 1 : 0;
  withdrawn_time_ = pulled_hard && withdrawn() ? withdrawn_time_ + settings_.contact.time_step : 0;
  bool slip = false;
  if (saturated_steps_ >= kTrappedSteps) {
    slip = enclosed(bvh, x, v, masses);
    saturated_steps_ = 0;
  }
  if (withdrawn_time_ >= kWithdrawnTime) {
    slip = true;
    withdrawn_time_ = 0;
  }
  if (slip && !inside(bvh, x, device_)) {
    proxy_ = device_;
    ++slips_;
  }
  response_.evaluate(bvh, x, v, masses, tip(), Vec3::Zero());
  if (!response_.contacts().empty()) {
    motion = motion_.move(bvh, x, proxy_, nearest_free_position());
    proxy_ = motion.centre;
    blocked_ = blocked_ || motion.blocked;
  }
  // 2. The contacts there, and the balance of the proxy between the coupling and the tissue.
  //    Once: a second balance from where the first put the proxy (with the contacts there) was
  //    tried, and from inside the surface it found the dimple's walls from behind and threw the
  //    proxy out, then through (the liver pressed 5 mm in: 3 N spikes).
  response_.evaluate(bvh, x, v, masses, tip(), Vec3::Zero());
  const Mat3 m = balance(bvh, x, v, masses, inverse_masses, node_forces);
  // 3. The push.
  transmitted_.setZero();
  const std::vector<ContactForce>& contacts = response_.contacts();
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    if (!(multipliers_[c] > 0)) continue;
    const Vec3 push = -multipliers_[c] * contacts[c].contact.normal;
    transmitted_ += push;
    for (int k = 0; k < 3; ++k) {
      node_forces.row(contacts[c].nodes[k]) +=
          contacts[c].contact.barycentric[k] * push.transpose();
    }
  }
  blocked_ = blocked_ || transmitted_.squaredNorm() > 0;
  hand_force_ = saturated(kv * (proxy_ - device_), settings_.max_force);
  hand_model_.reference_position = device_;
  hand_model_.force = hand_force_;
  // Saturated, the force no longer grows as the device goes deeper: no stiffness to render.
  const bool saturating = (kv * (device_ - proxy_)).norm() > settings_.max_force * (1 + 1e-9);
  const Mat3 series = kv * (kv * Mat3::Identity() + m).inverse() * m;
  hand_model_.stiffness = saturating ? Mat3::Zero() : Mat3(0.5 * (series + series.transpose()));
}

Mat3 Probe::balance(const collide::SurfaceBvh& bvh, const Points& x, const Points& v,
                    const VecX& masses, const VecX* inverse_masses, const Points& other_forces) {
  const std::vector<ContactForce>& contacts = response_.contacts();
  const std::size_t n = contacts.size();
  multipliers_.assign(n, 0);
  if (n == 0) return Mat3::Zero();
  const Real dt = settings_.contact.time_step;
  const Real kv = settings_.coupling_stiffness;
  const Real k = settings_.contact_stiffness_ratio * kv;
  // How the integrator moves the node: a held node not at all.
  const auto inverse_mass = [&](int node) {
    if (inverse_masses != nullptr) return (*inverse_masses)[node];
    const Real m = masses[node];
    return m > 0 ? 1 / m : Real(0);
  };
  // The contacts' inverse mass G, and their depth at the end of the step without contact forces.
  const Eigen::Index count = static_cast<Eigen::Index>(n);
  gram_.resize(count, count);
  excess_.resize(count);
  normals_.resize(count, 3);
  for (std::size_t c = 0; c < n; ++c) {
    const ContactForce& cc = contacts[c];
    const Eigen::Index ci = static_cast<Eigen::Index>(c);
    normals_.row(ci) = cc.contact.normal.transpose();
    Vec3 drift = Vec3::Zero();
    for (int a = 0; a < 3; ++a) {
      const int node = cc.nodes[a];
      drift += cc.contact.barycentric[a] *
               (dt * row3(v, node) + dt * dt * inverse_mass(node) * row3(other_forces, node));
    }
    excess_(ci) = cc.contact.depth + cc.contact.normal.dot(drift);
    for (std::size_t d = 0; d <= c; ++d) {
      const ContactForce& dd = contacts[d];
      Real g = 0;
      for (int a = 0; a < 3; ++a) {
        for (int b = 0; b < 3; ++b) {
          if (cc.nodes[a] == dd.nodes[b]) {
            g += cc.contact.barycentric[a] * dd.contact.barycentric[b] * inverse_mass(cc.nodes[a]);
          }
        }
      }
      g *= cc.contact.normal.dot(dd.contact.normal);
      gram_(ci, static_cast<Eigen::Index>(d)) = g;
      gram_(static_cast<Eigen::Index>(d), ci) = g;
    }
  }
  // Active set: every contact at first; one that would pull leaves, and the rest is solved again.
  active_.assign(n, 1);
  const Vec3 from = proxy_;
  Mat3 m = Mat3::Zero();
  for (int pass = 0; pass < kBalancePasses; ++pass) {
    // A = I + dt^2 K G over the active contacts (an inactive one: identity row, no load).
    system_.setIdentity(count, count);
    kn_ = k * normals_;
    ke_ = k * excess_;
    for (Eigen::Index c = 0; c < count; ++c) {
      if (active_[static_cast<std::size_t>(c)] == 0) {
        kn_.row(c).setZero();
        ke_(c) = 0;
        continue;
      }
      for (Eigen::Index d = 0; d < count; ++d) {
        if (active_[static_cast<std::size_t>(d)] != 0) system_(c, d) += dt * dt * k * gram_(c, d);
      }
    }
    lu_.compute(system_);
    a_kn_ = lu_.solve(kn_);
    a_ke_ = lu_.solve(ke_);
    m = normals_.transpose() * a_kn_;
    m = 0.5 * (m + m.transpose());
    const Vec3 pushed_out = normals_.transpose() * a_ke_;
    // The coupling: a spring; saturated, its force at p0 is capped at max_force (the spring's
    // stiffness stays in the solve, so that the proxy moves a bounded distance).
    const Vec3 pull = kv * (device_ - from);
    Vec3 shift = (kv * Mat3::Identity() + m)
                     .ldlt()
                     .solve(pull.norm() > settings_.max_force
                                ? Vec3(saturated(pull, settings_.max_force) + pushed_out)
                                : Vec3(pull + pushed_out));
    // Through the swept check, so that the proxy never tunnels into the tissue; the contacts'
    // forces follow where it actually went.
    shift = motion_.move(bvh, x, from, from + shift).centre - from;
    lambda_ = a_ke_;
    lambda_.noalias() -= a_kn_ * shift;
    bool changed = false;
    for (std::size_t c = 0; c < n; ++c) {
      if (active_[c] != 0 && lambda_(static_cast<Eigen::Index>(c)) < 0) {
        active_[c] = 0;
        changed = true;
      }
    }
    proxy_ = from + shift;
    for (std::size_t c = 0; c < n; ++c) {
      multipliers_[c] =
          active_[c] != 0 ? std::max(Real(0), lambda_(static_cast<Eigen::Index>(c))) : Real(0);
    }
    if (!changed) break;
  }
  // Saturated, the push is max_force (the fixed point above reaches it to rounding).
  Vec3 push = Vec3::Zero();
  for (std::size_t c = 0; c < n; ++c)
    push += multipliers_[c] * contacts[c].contact.normal;
  if (push.norm() > settings_.max_force) {
    const Real scale = settings_.max_force / push.norm();
    for (Real& l : multipliers_)
      l *= scale;
  }
  return m;
}

void Probe::set_shaft(const Vec3& towards_hand) {
  checks::check_vector(towards_hand, "Probe::set_shaft", "towards_hand");
  const Real length = towards_hand.norm();
  shaft_ = length > 0 ? Vec3(towards_hand / length) : Vec3::Zero();
}

bool Probe::withdrawn() const {
  const Vec3 pull = device_ - proxy_;
  return shaft_.dot(pull) > kShaftCone * pull.norm();  // never without a shaft
}

bool Probe::enclosed(const collide::SurfaceBvh& bvh, const Points& x, const Points& v,
                     const VecX& masses) {
  if (inside(bvh, x, proxy_)) return true;
  response_.evaluate(bvh, x, v, masses, tip(), Vec3::Zero());
  const std::vector<ContactForce>& contacts = response_.contacts();
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    for (std::size_t d = c + 1; d < contacts.size(); ++d) {
      // Nearly opposite (a crack or a flap shut over the tip), not just steep: the walls of a
      // deep dimple under a hard press face each other at 120 degrees and more, and a proxy
      // seated in one is on the surface (it slipped through the block once round-off made its
      // walls a little steeper).
      if (contacts[c].contact.normal.dot(contacts[d].contact.normal) < -0.9) return true;
    }
  }
  return false;
}

bool Probe::inside(const collide::SurfaceBvh& bvh, const Points& x, const Vec3& p) {
  return collide::inside_closed_surface(bvh, x, p, ray_triangles_);
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
