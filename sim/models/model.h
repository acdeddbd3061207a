#pragma once
// The one interface every deformable model implements (DESIGN.md section 3): volumetric
// mass-spring, linear FEM, corotational FEM (QR and polar), St Venant-Kirchhoff, Neo-Hookean.
// Solvers (sim/solve/) see only this. One virtual call per model operation, never per element:
// implementations loop over their elements in structure-of-arrays kernels.
//
// Conventions, all SI, node arrays #nodes by 3 (Points):
//   forces     f(x, v) = f_elastic(x) + f_damping(x, v), the internal forces on the nodes [N]
//   stiffness  K(x) = -d f_elastic / dx, the tangent stiffness (symmetric for every model here)
//   damping    D = -d f_damping / dv (Rayleigh or per-spring), symmetric positive semi-definite
//   energy     E(x), the elastic potential [J]; f_elastic = -dE/dx
// A model is built on a mesh's rest configuration and per-tet materials (from tissue labels).
#include <Eigen/Sparse>
#include <string_view>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim {

// What the element computations met at the last evaluation: inverted or degenerate elements are
// handled (clamped, a restoring force), never NaN, and counted here so that sessions can report it.
struct ModelHealth {
  int inverted_elements = 0;    // det F <= 0 at the last add_forces
  int degenerate_elements = 0;  // (near) zero volume or length, left out or clamped
};

// Per-tet material constants, looked up by tet label.
struct ElementMaterial {
  Real youngs_modulus = 0;  // E [Pa], > 0
  Real poisson_ratio = 0;   // nu in (-1, 0.5)
  Real density = 0;         // [kg/m^3], > 0
  Real damping = 0;         // model-specific damping factor, >= 0 (see each model)
};

enum class MassLumping {
  lumped,      // diagonal: each tet's mass split equally over its 4 nodes
  consistent,  // the full consistent mass matrix (only where a solver asks for it)
};

class Model {
 public:
  virtual ~Model() = default;

  virtual std::string_view name() const = 0;

  // Lumped node masses [kg], #nodes; positive for every node that belongs to a tet.
  virtual const VecX& masses() const = 0;

  // Adds the internal forces at positions x and velocities v to f. Allocates nothing.
  virtual void add_forces(const Points& x, const Points& v, Points& f) = 0;

  // Linearises at positions x (e.g. extracts rotations, assembles element stiffness); later
  // add_stiffness_times calls use this linearisation until the next call.
  virtual void prepare_stiffness(const Points& x) = 0;
  // out += K dx, with K from the last prepare_stiffness. Allocates nothing.
  virtual void add_stiffness_times(const Points& dx, Points& out) const = 0;
  // out += D dv. Allocates nothing.
  virtual void add_damping_times(const Points& dv, Points& out) const = 0;
  // The K of the last prepare_stiffness as (row, column, value) entries over the 3 #nodes degrees
  // of freedom (node i's x, y, z are 3i, 3i+1, 3i+2), appended to triplets; duplicates add up. For
  // the assembled (block-sparse) solver variant.
  virtual void add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const = 0;

  // Elastic potential energy at x [J].
  virtual Real potential_energy(const Points& x) const = 0;

  // Rebuilds per-element data after the mesh's topology changed (remeshing, cutting).
  virtual void update_topology(const TetMesh& mesh) = 0;

  virtual ModelHealth health() const = 0;
};

}  // namespace incise::sim
