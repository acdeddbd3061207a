#pragma once
// The one interface every deformable model implements (docs/architecture.md, "The parts"):
// volumetric mass-spring, linear FEM, corotational FEM (QR and polar), St Venant-Kirchhoff,
// Neo-Hookean. Solvers (sim/solve/) see only this. One virtual call per model operation, never per
// element: implementations loop over their elements in structure-of-arrays kernels.
//
// Conventions, all SI, node arrays #nodes by 3 (Points):
//   forces     f(x, v) = f_elastic(x) + f_damping(x, v), the internal forces on the nodes [N]
//   stiffness  K(x) = -d f_elastic / dx, the tangent stiffness (symmetric for every model here)
//   damping    D = -d f_damping / dv (Rayleigh or per-spring), symmetric positive semi-definite
//   energy     E(x), the elastic potential [J]; f_elastic = -dE/dx
// A model is built on a mesh's rest configuration and per-tet materials (from tissue labels).
#include <Eigen/Sparse>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <utility>
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

// Where an assembled solver keeps the 3x3 blocks it receives from Model::add_system_blocks: block
// k adds to the column-major 3x3 values at values + slots[k], or, for slots[k] < 0, adds its
// transpose at values + (-slots[k] - 1) (a solver that stores only one triangle of the symmetric
// matrix keeps block (i, j) with i > j as the transpose of (j, i)).
struct BlockTarget {
  Real* values = nullptr;
  const int* slots = nullptr;

  void add(std::size_t k, const Mat3& block) const {
    const int slot = slots[k];
    if (slot >= 0) {
      Eigen::Map<Mat3>(values + slot) += block;
    } else {
      Eigen::Map<Mat3>(values + (-slot - 1)) += block.transpose();
    }
  }
};

class Model {
 public:
  virtual ~Model() = default;

  virtual std::string_view name() const = 0;

  // A deep copy, state included (warm starts, linearisation, topology revision): stepped with
  // the same inputs, the copy and the original stay equal bit for bit. For checkpoints.
  virtual std::unique_ptr<Model> clone() const = 0;

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

  // D as (row, column, value) entries, with the same conventions as add_stiffness_triplets (D of
  // the last prepare_stiffness where it depends on the state).
  virtual void add_damping_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const = 0;

  // Block assembly of the symmetric b D + c K for the assembled solvers, without a triplet per
  // entry and step. system_blocks appends node pairs (i, j), in an order that stays fixed until
  // the topology changes (topology_revision); add_system_blocks then adds block k's values through
  // target.add(k, block). The matrix is the sum over the blocks of block k at (i, j) and, for
  // i != j, its transpose at (j, i): a model lists each off-diagonal pair of an element once.
  // Duplicate pairs add up. The defaults go through the triplets (those on or below the block
  // diagonal, one block each: correct, slow, and add_system_blocks allocates); the FEM models
  // override them with the 10 node pairs of each tet.
  virtual void system_blocks(std::vector<std::pair<int, int>>& blocks) const;
  virtual void add_system_blocks(Real damping_scale, Real stiffness_scale,
                                 const BlockTarget& target) const;
  // Unique in the process to this model's current elements: a new model, and update_topology,
  // take a new value (so that a solver keeping a sparsity pattern sees a different model even
  // at the same address).
  std::uint64_t topology_revision() const { return topology_revision_; }

  // Elastic potential energy at x [J].
  virtual Real potential_energy(const Points& x) const = 0;

  // Rebuilds per-element data after the mesh's topology changed (remeshing, cutting).
  virtual void update_topology(const TetMesh& mesh) = 0;

  // A local topology change instead (remeshing, cutting). Slot view: mesh.tets row s is element
  // slot s, holding a tet where alive[s] != 0 (other rows are ignored, whatever they hold);
  // mesh.rest has a row per node slot (it may have grown: new nodes; a node left without tets
  // keeps its row and gets no mass). `changed` lists the slots whose tet appeared, disappeared or
  // was replaced since the model was built or last updated. The FEM models recompute only those
  // elements and their nodes' masses; the default compacts the alive tets and calls
  // update_topology (correct, not local). Throws std::invalid_argument for a bad new tet, with the
  // model unchanged.
  virtual void update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                               std::span<const int> changed);

  virtual ModelHealth health() const = 0;

  // Scales element slot t's stiffness, and with it its stiffness-proportional damping, to factor
  // (in (0, 1]) times its material's; update_topology, and update_elements for the changed slots,
  // reset it to 1. Returns false when the model cannot (the default, e.g. the mass-spring model):
  // nothing changes then. For the sliver guard (surgery/tissue_body.h): a tet a cut left too thin
  // for the explicit step is softened rather than its nodes made heavy. Throws
  // std::invalid_argument for t out of range or factor outside (0, 1].
  virtual bool soften_element(int t, Real factor);

 protected:
  Model() : topology_revision_(next_topology_revision()) {}
  Model(const Model&) = default;
  Model& operator=(const Model&) = default;
  // For update_topology implementations.
  void topology_changed() { topology_revision_ = next_topology_revision(); }

 private:
  static std::uint64_t next_topology_revision();

  std::uint64_t topology_revision_;
};

}  // namespace incise::sim
