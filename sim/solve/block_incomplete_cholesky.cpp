#include "sim/solve/block_incomplete_cholesky.h"

#include <Eigen/Cholesky>
#include <algorithm>

namespace incise::sim {

bool BlockIncompleteCholesky::factorize(const SymmetricBlockMatrix& a) {
  pattern_ = &a;
  const std::size_t values = 9 * static_cast<std::size_t>(a.blocks());
  if (factor_.size() != values) factor_.resize(values);
  if (inverse_diag_.size() != static_cast<std::size_t>(a.nodes())) {
    inverse_diag_.resize(static_cast<std::size_t>(a.nodes()));
    position_.assign(static_cast<std::size_t>(a.nodes()), -1);
  }
  for (Real shift : {0.0, 1e-3, 1e-2, 1e-1, 1.0}) {
    if (try_factorize(a, shift)) {
      shift_ = shift;
      return true;
    }
  }
  return false;
}

// Right-looking, row by row of R: row k is final once the rows above have updated it; then it
// updates the rows below, dropping every update outside the pattern (IC(0)).
bool BlockIncompleteCholesky::try_factorize(const SymmetricBlockMatrix& a, Real shift) {
  std::copy(a.values(), a.values() + factor_.size(), factor_.begin());
  Real* r = factor_.data();
  const int n = a.nodes();
  for (int i = 0; i < n; ++i) {
    Eigen::Map<Mat3> diagonal(r + 9 * a.row_start(i));
    if (shift > 0) diagonal.diagonal() *= 1 + shift;
  }
  for (int k = 0; k < n; ++k) {
    const int first = a.row_start(k);
    const int last = a.row_start(k + 1);
    // R_kk = upper Cholesky factor of the updated diagonal block: A_kk = L L^T, R_kk = L^T.
    Eigen::Map<Mat3> diagonal(r + 9 * first);
    const Eigen::LLT<Mat3> llt(diagonal);
    if (llt.info() != Eigen::Success || !diagonal.allFinite()) return false;
    const Mat3 r_kk = llt.matrixU();
    const Mat3 r_kk_inverse = r_kk.inverse();
    if (!r_kk_inverse.allFinite() || !(r_kk.diagonal().minCoeff() > 0)) return false;
    diagonal = r_kk;
    inverse_diag_[static_cast<std::size_t>(k)] = r_kk_inverse;
    // R_kj = R_kk^-T A_kj.
    for (int b = first + 1; b < last; ++b) {
      Eigen::Map<Mat3> block(r + 9 * b);
      block = r_kk_inverse.transpose() * block;
    }
    // A_jl -= R_kj^T R_kl for the pairs j <= l of row k that are in the pattern (row j).
    for (int b = first + 1; b < last; ++b) {
      const int j = a.column(b);
      const int row_first = a.row_start(j);
      const int row_last = a.row_start(j + 1);
      for (int c = row_first; c < row_last; ++c)
        position_[static_cast<std::size_t>(a.column(c))] = c;
      const Eigen::Map<const Mat3> r_kj(r + 9 * b);
      for (int d = b; d < last; ++d) {
        const int target = position_[static_cast<std::size_t>(a.column(d))];
        if (target < 0) continue;
        Eigen::Map<Mat3>(r + 9 * target).noalias() -=
            r_kj.transpose() * Eigen::Map<const Mat3>(r + 9 * d);
      }
      for (int c = row_first; c < row_last; ++c)
        position_[static_cast<std::size_t>(a.column(c))] = -1;
    }
  }
  return true;
}

void BlockIncompleteCholesky::solve(const Points& rhs, Points& z) const {
  const SymmetricBlockMatrix& a = *pattern_;
  const Real* r = factor_.data();
  const int n = a.nodes();
  // R^T y = rhs, forward: y_k = R_kk^-T (rhs_k - sum_{i<k} R_ik^T y_i), pushing each y_k's
  // contributions down to the rows it couples to. y is kept in z.
  z = rhs;
  for (int k = 0; k < n; ++k) {
    const Vec3 y_k = inverse_diag_[static_cast<std::size_t>(k)].transpose() * z.row(k).transpose();
    z.row(k) = y_k.transpose();
    for (int b = a.row_start(k) + 1; b < a.row_start(k + 1); ++b) {
      z.row(a.column(b)).noalias() -=
          (Eigen::Map<const Mat3>(r + 9 * b).transpose() * y_k).transpose();
    }
  }
  // R z = y, backward: z_k = R_kk^-1 (y_k - sum_{j>k} R_kj z_j).
  for (int k = n - 1; k >= 0; --k) {
    Vec3 w = z.row(k).transpose();
    for (int b = a.row_start(k) + 1; b < a.row_start(k + 1); ++b)
      w.noalias() -= Eigen::Map<const Mat3>(r + 9 * b) * z.row(a.column(b)).transpose();
    z.row(k) = (inverse_diag_[static_cast<std::size_t>(k)] * w).transpose();
  }
}

}  // namespace incise::sim
