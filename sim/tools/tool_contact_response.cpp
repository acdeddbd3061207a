#include "sim/tools/tool_contact_response.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "sim/tools/tool_checks.h"

namespace incise::sim::tools {

void validate(const PenaltySettings& settings) {
  if (!(settings.time_step > 0) || !std::isfinite(settings.time_step)) {
    throw std::invalid_argument("PenaltySettings: time_step must be finite and > 0, got " +
                                std::to_string(settings.time_step));
  }
  if (!(settings.stiffness_fraction > 0 && settings.stiffness_fraction <= 1)) {
    throw std::invalid_argument("PenaltySettings: stiffness_fraction must be in (0, 1], got " +
                                std::to_string(settings.stiffness_fraction));
  }
  if (!(settings.damping_ratio >= 0) || !std::isfinite(settings.damping_ratio)) {
    throw std::invalid_argument("PenaltySettings: damping_ratio must be finite and >= 0, got " +
                                std::to_string(settings.damping_ratio));
  }
}

ToolContactResponse::ToolContactResponse(PenaltySettings settings) : settings_(settings) {
  validate(settings_);
}

const ToolReaction& ToolContactResponse::apply(const collide::SurfaceBvh& bvh, const Points& x,
                                               const Points& v, const VecX& masses,
                                               const collide::Sphere& tool,
                                               const Vec3& tool_velocity, Points& node_forces) {
  checks::check_sphere(tool, "ToolContactResponse::apply");
  checks::check_vector(tool_velocity, "ToolContactResponse::apply", "tool_velocity");
  bvh.contacts(x, tool, found_);
  respond(bvh, x, v, masses, tool.centre, tool_velocity);
  if (node_forces.rows() != x.rows()) {
    throw std::invalid_argument("ToolContactResponse::apply: x has " + std::to_string(x.rows()) +
                                " rows but node_forces " + std::to_string(node_forces.rows()));
  }
  add_node_forces(node_forces);
  return reaction_;
}

const ToolReaction& ToolContactResponse::evaluate(const collide::SurfaceBvh& bvh, const Points& x,
                                                  const Points& v, const VecX& masses,
                                                  const collide::Sphere& tool,
                                                  const Vec3& tool_velocity) {
  checks::check_sphere(tool, "ToolContactResponse::evaluate");
  checks::check_vector(tool_velocity, "ToolContactResponse::evaluate", "tool_velocity");
  bvh.contacts(x, tool, found_);
  respond(bvh, x, v, masses, tool.centre, tool_velocity);
  return reaction_;
}

const ToolReaction& ToolContactResponse::apply(const collide::SurfaceBvh& bvh, const Points& x,
                                               const Points& v, const VecX& masses,
                                               const collide::Capsule& tool,
                                               const Vec3& tool_velocity, Points& node_forces) {
  checks::check_capsule(tool, "ToolContactResponse::apply");
  checks::check_vector(tool_velocity, "ToolContactResponse::apply", "tool_velocity");
  bvh.contacts(x, tool, found_);
  respond(bvh, x, v, masses, tool.a, tool_velocity);
  if (node_forces.rows() != x.rows()) {
    throw std::invalid_argument("ToolContactResponse::apply: x has " + std::to_string(x.rows()) +
                                " rows but node_forces " + std::to_string(node_forces.rows()));
  }
  add_node_forces(node_forces);
  return reaction_;
}

void ToolContactResponse::respond(const collide::SurfaceBvh& bvh, const Points& x, const Points& v,
                                  const VecX& masses, const Vec3& reference,
                                  const Vec3& tool_velocity) {
  const Eigen::Index n = x.rows();
  if (v.rows() != n || masses.size() != n) {
    throw std::invalid_argument("ToolContactResponse: x has " + std::to_string(n) +
                                " rows but v has " + std::to_string(v.rows()) + " and masses " +
                                std::to_string(masses.size()));
  }
  const Real dt = settings_.time_step;
  const Real beta = settings_.stiffness_fraction;
  forces_.clear();
  reaction_ = ToolReaction{};
  reaction_.reference = reference;
  for (const collide::Contact& contact : found_) {
    ContactForce out;
    out.contact = contact;
    out.nodes = bvh.triangle(contact.triangle);
    const Vec3& w = contact.barycentric;
    Real mass = masses[out.nodes[0]];
    Vec3 point_velocity = Vec3::Zero();
    for (int k = 0; k < 3; ++k) {
      mass = std::min(mass, masses[out.nodes[k]]);
      point_velocity += w[k] * row3(v, out.nodes[k]);
    }
    // A node without mass (no tet) cannot be pushed: no contact on its triangle.
    if (!(mass > 0)) continue;
    out.stiffness = beta * mass / (dt * dt);
    out.damping = 2 * settings_.damping_ratio * std::sqrt(beta) * mass / dt;
    const Vec3& normal = contact.normal;
    out.elastic_force = out.stiffness * contact.depth * normal;
    const Real approach = (tool_velocity - point_velocity).dot(normal);
    // The damping resists approach and separation, but the total may not pull the tool onto
    // the tissue (no adhesion): the normal force is clamped at zero.
    const Real magnitude =
        std::max(Real(0), out.stiffness * contact.depth - out.damping * approach);
    out.force = magnitude * normal;
    reaction_.force += out.force;
    reaction_.torque += (contact.point - reference).cross(out.force);
    reaction_.max_depth = std::max(reaction_.max_depth, contact.depth);
    ++reaction_.contacts;
    forces_.push_back(out);
  }
}

void ToolContactResponse::add_node_forces(Points& node_forces) const {
  for (const ContactForce& c : forces_) {
    for (int k = 0; k < 3; ++k) {
      node_forces.row(c.nodes[k]) -= c.contact.barycentric[k] * c.force.transpose();
    }
  }
}

void ToolContactResponse::distribute(const Vec3& force, Points& node_forces, Real min_depth) const {
  Real total = 0;
  for (const ContactForce& c : forces_) {
    if (c.contact.depth >= min_depth) total += c.elastic_force.norm();
    if (c.nodes.maxCoeff() >= node_forces.rows()) {
      throw std::invalid_argument(
          "ToolContactResponse::distribute: node_forces has " + std::to_string(node_forces.rows()) +
          " rows, a contact uses node " + std::to_string(c.nodes.maxCoeff()));
    }
  }
  if (!(total > 0)) return;
  for (const ContactForce& c : forces_) {
    if (c.contact.depth < min_depth) continue;
    const Vec3 share = (c.elastic_force.norm() / total) * force;
    for (int k = 0; k < 3; ++k) {
      node_forces.row(c.nodes[k]) += c.contact.barycentric[k] * share.transpose();
    }
  }
}

void ToolContactResponse::distribution_weights(std::vector<NodeWeight>& weights,
                                               Real min_depth) const {
  weights.clear();
  Real total = 0;
  for (const ContactForce& c : forces_) {
    if (c.contact.depth >= min_depth) total += c.elastic_force.norm();
  }
  if (!(total > 0)) return;
  for (const ContactForce& c : forces_) {
    if (c.contact.depth < min_depth) continue;
    const Real share = c.elastic_force.norm() / total;
    for (int k = 0; k < 3; ++k) {
      const Real w = share * c.contact.barycentric[k];
      // A handful of contacts share nodes: a linear search is cheaper than a map here.
      auto found = std::find_if(weights.begin(), weights.end(),
                                [&](const NodeWeight& e) { return e.node == c.nodes[k]; });
      if (found == weights.end()) {
        weights.push_back({c.nodes[k], w});
      } else {
        found->weight += w;
      }
    }
  }
}

}  // namespace incise::sim::tools
