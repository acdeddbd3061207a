#pragma once
// Block incomplete Cholesky, IC(0) on 3x3 blocks: A ~ R^T R with R block upper triangular on
// exactly A's stored block pattern (no fill; Saad, "Iterative Methods for Sparse Linear Systems",
// 2003, section 10.3, here by blocks so that a node's three coupled axes are factorised together).
// The preconditioner of assembled CG for stiff elastic systems: it cuts the iterations about 3x
// against Jacobi, and applying it costs about one matrix product (two triangular sweeps of one
// 3x3 product per block). Elasticity matrices are not M-matrices, so a pivot can fail; then the
// factorisation starts again on A + shift diag(A) with a growing shift (Manteuffel 1980), which
// only weakens the preconditioner, never the answer CG converges to.

#include <vector>

#include "sim/core/types.h"
#include "sim/solve/block_sparse.h"

namespace incise::sim {

class BlockIncompleteCholesky {
 public:
  // Factorises a (symmetric positive definite); allocates only when the pattern size changed.
  // Returns false if no shift up to 1 (A + diag(A)) gave positive pivots or a value is not
  // finite.
  bool factorize(const SymmetricBlockMatrix& a);

  // z = (R^T R)^-1 r (r, z #nodes by 3, distinct). Allocates nothing.
  void solve(const Points& r, Points& z) const;

  // The diagonal shift the last factorisation needed (0: none).
  Real shift() const { return shift_; }

 private:
  bool try_factorize(const SymmetricBlockMatrix& a, Real shift);

  const SymmetricBlockMatrix* pattern_ = nullptr;
  std::vector<Real> factor_;        // R's blocks, 9 per block of a's pattern, column-major
  std::vector<Mat3> inverse_diag_;  // #nodes R_ii^-1
  std::vector<int> position_;       // #nodes scratch: block index of column j in the current row
  Real shift_ = 0;
};

}  // namespace incise::sim
