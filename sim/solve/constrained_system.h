#pragma once
// The linear system behind the implicit and static solvers,
//   A = a M + b D + c K,
// with M the lumped mass, D the damping and K the tangent stiffness of a Model (at its last
// prepare_stiffness), restricted to the free coordinates: the rows and columns of held
// coordinates are replaced by the identity, so A stays symmetric positive definite and a held
// coordinate's unknown stays 0. Three ways to solve it (choose per scene):
//   matrix_free_cg  CG with A applied through add_stiffness_times / add_damping_times; nothing
//                   assembled (Phymul's choice, seed 002 section 2.3)
//   assembled_cg    a M + c K assembled once per step into an Eigen sparse matrix whose pattern is
//                   kept from step to step (only values are rewritten); D applied matrix-free
//   assembled_ldlt  the same matrix factorised by Eigen's SimplicialLDLT, used as the
//                   preconditioner of CG on the full A: without damping the first iteration
//                   solves it to round-off; with damping CG corrects for the b D term that Model
//                   offers only as an operator (it has no damping triplets)

#include <Eigen/SparseCholesky>
#include <vector>

#include "sim/core/types.h"
#include "sim/models/model.h"
#include "sim/solve/conjugate_gradient.h"

namespace incise::sim {

enum class LinearSolver { matrix_free_cg, assembled_cg, assembled_ldlt };

enum class Preconditioner {
  none,    // identity
  mass,    // diag(a M) (free to get; good while c K is small against a M, as at small steps)
  jacobi,  // diag(a M + c K); matrix-free reads K's diagonal from add_stiffness_triplets. D's
           // diagonal is not available through Model and is left out (only the preconditioner
           // is affected, not the answer)
};

struct LinearSolveSettings {
  LinearSolver solver = LinearSolver::matrix_free_cg;
  Preconditioner preconditioner = Preconditioner::jacobi;  // CG variants; LDLT is its own
  CgSettings cg;
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

  // The assembled matrix (assembled_* only), 3 #nodes square, dof 3 i + axis.
  const Eigen::SparseMatrix<Real>& matrix() const { return matrix_; }
  // Whether the last prepare had to build a new sparsity pattern.
  bool pattern_rebuilt() const { return pattern_rebuilt_; }

 private:
  void apply(const Points& p, Points& out) const;
  void precondition(const Points& r, Points& z) const;
  bool assemble();
  void rebuild_pattern();
  bool scatter_values();

  const Model* model_ = nullptr;
  Real mass_scale_ = 0, damping_scale_ = 0, stiffness_scale_ = 0;
  const Points* free_ = nullptr;
  LinearSolveSettings settings_;

  std::vector<Eigen::Triplet<Real>> triplets_;  // the model's, then the 3 #nodes mass diagonal
  std::size_t model_triplets_ = 0;
  std::vector<int> slots_;  // triplet k adds to matrix_.valuePtr()[slots_[k]]
  Eigen::SparseMatrix<Real> matrix_;
  bool pattern_rebuilt_ = false;
  bool factorised_pattern_ = false;
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<Real>> ldlt_;

  Points diagonal_;  // #nodes by 3 Jacobi diagonal (1 on held coordinates)
  mutable Points scratch_;
  Points rhs_;
  CgWorkspace cg_work_;
};

}  // namespace incise::sim
