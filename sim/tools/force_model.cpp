#include "sim/tools/force_model.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Eigenvalues>

#include "sim/tools/tool_checks.h"

namespace incise::sim::tools {
namespace {

// Barycentric weights below this are a contact on the triangle's boundary (the closest-point
// routine sets them to exactly 0 there; the slack absorbs rounding).
constexpr Real kWeightTolerance = 1e-12;

// Adds u to the orthonormal set basis[0..count) if it is independent of it.
void add_direction(const Vec3& u, Vec3* basis, int& count) {
  Vec3 rest = u;
  for (int i = 0; i < count; ++i)
    rest -= rest.dot(basis[i]) * basis[i];
  const Real length = rest.norm();
  if (length > 1e-9 * u.norm() && count < 3) basis[count++] = rest / length;
}

Mat3 contact_stiffness(const ContactForce& force, const Points& x, Real radius,
                       const collide::Capsule* capsule) {
  const collide::Contact& contact = force.contact;
  const Vec3& n = contact.normal;
  Mat3 k = n * n.transpose();
  const Real rho = radius - contact.depth;
  if (!(rho > 1e-9 * radius)) return force.stiffness * k;
  Vec3 basis[3];
  int count = 0;
  add_direction(n, basis, count);
  // The triangle's feature: the corners with a weight.
  int corners[3];
  int used = 0;
  for (int j = 0; j < 3; ++j) {
    if (contact.barycentric[j] > kWeightTolerance) corners[used++] = force.nodes[j];
  }
  for (int j = 1; j < used; ++j) {
    add_direction(row3(x, corners[j]) - row3(x, corners[0]), basis, count);
  }
  // The tool's feature: a capsule's axis when the closest axis point is inside the segment.
  if (capsule != nullptr) {
    const Vec3 axis = capsule->b - capsule->a;
    const Real squared = axis.squaredNorm();
    if (squared > 0) {
      const Vec3 q = contact.point + rho * n;
      const Real s = (q - capsule->a).dot(axis) / squared;
      if (s > 1e-9 && s < 1 - 1e-9) add_direction(axis, basis, count);
    }
  }
  Mat3 projector = Mat3::Identity();
  for (int i = 0; i < count; ++i)
    projector -= basis[i] * basis[i].transpose();
  k -= (contact.depth / rho) * projector;
  return force.stiffness * k;
}

LocalForceModel force_model(const std::vector<ContactForce>& contacts, const Points& x, Real radius,
                            const Vec3& reference, const collide::Capsule* capsule) {
  LocalForceModel model;
  model.reference_position = reference;
  for (const ContactForce& c : contacts)
    model.force += c.elastic_force;
  if (!contacts.empty()) {
    model.stiffness = positive_part(exact_contact_stiffness(contacts, x, radius, capsule));
  }
  return model;
}

}  // namespace

Mat3 exact_contact_stiffness(const std::vector<ContactForce>& contacts, const Points& x,
                             Real radius, const collide::Capsule* capsule) {
  checks::check_radius(radius, "exact_contact_stiffness");
  Mat3 k = Mat3::Zero();
  for (const ContactForce& c : contacts)
    k += contact_stiffness(c, x, radius, capsule);
  return Real(0.5) * (k + k.transpose());
}

Mat3 positive_part(const Mat3& symmetric) {
  if (!symmetric.allFinite()) {
    throw std::invalid_argument("positive_part: the matrix must be finite");
  }
  const Real asymmetry = (symmetric - symmetric.transpose()).cwiseAbs().maxCoeff();
  if (asymmetry > 1e-9 * symmetric.cwiseAbs().maxCoeff()) {
    throw std::invalid_argument("positive_part: the matrix must be symmetric, |K - K^T| max is " +
                                std::to_string(asymmetry));
  }
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(symmetric);
  const Vec3 clamped = eigen.eigenvalues().cwiseMax(0);
  return eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
}

LocalForceModel sphere_force_model(const std::vector<ContactForce>& contacts, const Points& x,
                                   const collide::Sphere& tool) {
  checks::check_sphere(tool, "sphere_force_model");
  return force_model(contacts, x, tool.radius, tool.centre, nullptr);
}

LocalForceModel capsule_force_model(const std::vector<ContactForce>& contacts, const Points& x,
                                    const collide::Capsule& tool) {
  checks::check_capsule(tool, "capsule_force_model");
  return force_model(contacts, x, tool.radius, tool.a, &tool);
}

}  // namespace incise::sim::tools
