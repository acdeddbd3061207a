#include "sim/interact/tool_contact.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace incise::sim {
namespace {

// Below this fraction of the radius the direction from the centre to a node is not trusted.
constexpr Real kCentreTolerance = 1e-9;

// The PSD part of a symmetric matrix: its spectral decomposition with negative eigenvalues set to
// 0, the nearest PSD matrix in the Frobenius norm (Higham 1988, "Computing a nearest symmetric
// positive semidefinite matrix", theorem 2.1). Fixed-size: no allocation.
Mat3 positive_part(const Mat3& symmetric) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eigen(symmetric);
  const Vec3 clamped = eigen.eigenvalues().cwiseMax(0);
  return eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
}

// The shared loop; damping is applied only when v is given.
ToolContact sphere_contact(const SphereTool& tool, const Vec3& centre, const Vec3& tool_velocity,
                           const BoundarySurface& surface, const Points& x, const Points* v,
                           Points& node_forces) {
  ToolContact contact;
  const Real r = tool.radius;
  const Real k = tool.stiffness;
  for (const int i : surface.nodes) {
    const Vec3 offset = row3(x, i) - centre;
    const Real squared = offset.squaredNorm();
    if (!(squared < r * r)) continue;  // outside, on the sphere, or not finite
    const Real rho = std::sqrt(squared);
    const Real depth = r - rho;
    const bool at_centre = rho <= kCentreTolerance * r;
    const Vec3 n = at_centre ? Vec3::UnitZ() : Vec3(offset / rho);
    Vec3 f = k * depth * n;
    if (v != nullptr) f -= tool.damping * (row3(*v, i) - tool_velocity).dot(n) * n;
    node_forces.row(i) += f.transpose();
    contact.force_on_tool -= f;

    // d depth / d c = n^T and d n / d c = -(I - n n^T) / rho, so
    // d f_i / d c = k (n n^T - (d / rho) (I - n n^T)), and the tool's reaction is -f_i.
    const Mat3 normal = n * n.transpose();
    contact.exact_stiffness += k * normal;
    if (!at_centre) contact.exact_stiffness -= (k * depth / rho) * (Mat3::Identity() - normal);
    ++contact.nodes_in_contact;
    contact.max_depth = std::max(contact.max_depth, depth);
  }
  if (contact.nodes_in_contact > 0) contact.stiffness = positive_part(contact.exact_stiffness);
  return contact;
}

}  // namespace

ToolContact apply_sphere_contact(const SphereTool& tool, const Vec3& centre,
                                 const BoundarySurface& surface, const Points& x,
                                 Points& node_forces) {
  return sphere_contact(tool, centre, Vec3::Zero(), surface, x, nullptr, node_forces);
}

ToolContact apply_sphere_contact(const SphereTool& tool, const Vec3& centre,
                                 const Vec3& tool_velocity, const BoundarySurface& surface,
                                 const Points& x, const Points& v, Points& node_forces) {
  return sphere_contact(tool, centre, tool_velocity, surface, x, &v, node_forces);
}

}  // namespace incise::sim
