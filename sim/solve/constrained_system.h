#pragma once
// The linear system behind the implicit and static solvers,
//   A = a M + b D + c K,
// with M the lumped mass, D the damping and K the tangent stiffness of a Model (at its last
// prepare_stiffness), restricted to the free coordinates: the rows and columns of held
// coordinates are replaced by the identity, so A stays symmetric positive definite and a held
// coordinate's unknown stays 0. Three ways to solve it (choose per scene):
//   matrix_free_cg  CG with A applied through add_stiffness_times / add_damping_times; nothing
//                   assembled (as Physically Realistic FEM does, sections 2.3 and 3.3)
//   assembled_cg    A assembled once per step from the model's 3x3 blocks (Model::
//                   add_system_blocks) into a SymmetricBlockMatrix whose pattern is kept until
//                   the topology changes (only values are rewritten); one product per iteration
//   assembled_ldlt  the same matrix factorised by Eigen's SimplicialLDLT, used as the
//                   preconditioner of CG (which then converges in an iteration or two)

#include <Eigen/SparseCholesky>
#include <cstdint>
#include <vector>

#include "sim/core/types.h"
#include "sim/models/model.h"
#include "sim/solve/block_incomplete_cholesky.h"
#include "sim/solve/block_sparse.h"
#include "sim/solve/conjugate_gradient.h"

namespace incise::sim {

enum class LinearSolver { matrix_free_cg, assembled_cg, assembled_ldlt };

enum class Preconditioner {
  none,          // identity
  mass,          // diag(a M) (free to get; good while c K is small against a M, as at small steps)
  jacobi,        // diag(A)
  block_jacobi,  // the 3x3 diagonal blocks of A, inverted per node (couples a node's axes, which
                 // the rotated stiffness of a corotational tet mixes)
  incomplete_cholesky,  // assembled_cg only: block IC(0) of A (block_incomplete_cholesky.h), kept
                        // from step to step and refactorised when CG needs more than
                        // refactor_ratio times the iterations it took right after the last
                        // factorisation (a lagged preconditioner: A changes slowly between
                        // steps; refactor_ratio 0 refactorises every step)
};

struct LinearSolveSettings {
  LinearSolver solver = LinearSolver::matrix_free_cg;
  Preconditioner preconditioner = Preconditioner::jacobi;  // CG variants; LDLT is its own
  CgSettings cg;
  Real refactor_ratio = 1.5;  // incomplete_cholesky: see above
};

class ConstrainedSystem {
 public:
  // Sets up A for the model's current linearisation (call model.prepare_stiffness first).
  //   mass_scale a >= 0, damping_scale b >= 0, stiffness_scale c > 0
  //   free  #nodes by 3, 1 = free coordinate, 0 = held (free_coordinates)
  // Returns false if the assembled matrix or diagonal is not finite or the LDLT factorisation
  // fails (e.g. an indefinite tangent); solve must not be called then. Allocates only when the
  // node count or the stiffness pattern changed (and inside Eigen's LDLT factorisation).
  bool prepare(const Model& model, Real mass_scale, Real damping_scale, Real stiffness_scale,
               const Points& free, const LinearSolveSettings& settings);

  // out = (a M + b D + c K) p over all coordinates, held ones included (to move the known
  // values of held unknowns to the right-hand side). Allocates nothing.
  void apply_unconstrained(const Points& p, Points& out) const;

  // Solves A y = rhs on the free coordinates (rhs is read there only; y is 0 on held ones).
  // y: initial guess on entry (warm start), solution on return. Allocates nothing.
  CgReport solve(const Points& rhs, Points& y);

  // The assembled matrix (assembled_* only), 3 #nodes square, dof 3 i + axis (built on demand,
  // for tests and inspection).
  Eigen::SparseMatrix<Real> matrix() const { return matrix_.full(); }
  // Whether the last prepare had to build a new sparsity pattern.
  bool pattern_rebuilt() const { return pattern_rebuilt_; }
  // Incomplete Cholesky factorisations so far (incomplete_cholesky only).
  int factorisations() const { return factorisations_; }

 private:
  void apply(const Points& p, Points& out) const;
  void precondition(const Points& r, Points& z) const;
  bool assemble();
  void rebuild_pattern();
  void rebuild_diagonal_slots();
  bool prepare_diagonal_blocks();
  bool factorise_incomplete();

  const Model* model_ = nullptr;
  Real mass_scale_ = 0, damping_scale_ = 0, stiffness_scale_ = 0;
  const Points* free_ = nullptr;
  LinearSolveSettings settings_;

  // The model's block pattern and where its blocks go: the matrix (assembled) or a per-node 3x3
  // diagonal (matrix-free Jacobi), keyed by model and topology revision.
  const Model* pattern_model_ = nullptr;
  std::uint64_t pattern_revision_ = 0;
  SymmetricBlockMatrix matrix_;
  std::vector<int> block_slots_;  // per model block, into matrix_.values() (BlockTarget)
  const Model* diagonal_model_ = nullptr;
  std::uint64_t diagonal_revision_ = 0;
  std::vector<int> block_diagonal_slots_;  // per model block, into block_diagonal_ (or a sink)
  std::vector<Real> block_diagonal_;       // 9 per node, then 9 values of a sink
  // The lower triangle as an Eigen matrix, for LDLT and incomplete Cholesky.
  Eigen::SparseMatrix<Real> lower_;
  bool lower_pattern_ = false;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Real>> ldlt_;
  BlockIncompleteCholesky incomplete_;
  bool incomplete_valid_ = false;
  int iterations_after_factorisation_ = 0;
  int factorisations_ = 0;
  bool pattern_rebuilt_ = false;

  Points diagonal_;                  // #nodes by 3 Jacobi diagonal (1 on held coordinates)
  std::vector<Mat3> block_inverse_;  // #nodes inverted 3x3 diagonal blocks (block_jacobi)
  mutable Points scratch_;
  Points rhs_;
  CgWorkspace cg_work_;
};

}  // namespace incise::sim
