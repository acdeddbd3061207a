#pragma once
// A symmetric matrix over the 3 #nodes coordinates of a node array, stored as 3x3 blocks of its
// upper triangle: block (i, j) for j >= i, by block rows, each row's diagonal block first, each
// block column-major (the 9 values of column c start at 9 b + 3 c). Half the memory of a full
// scalar sparse matrix and no index per entry, so the product A x (the inner loop of the assembled
// CG solvers) streams about a quarter of the bytes.

#include <Eigen/Sparse>
#include <utility>
#include <vector>

#include "sim/core/types.h"

namespace incise::sim {

class SymmetricBlockMatrix {
 public:
  // Sets the pattern to the diagonal blocks and the node pairs (either order, duplicates allowed)
  // and zeroes the values. slots receives, per pair, where Model::add_system_blocks writes its
  // block: the value offset of the stored block, or -(offset) - 1 for a pair (i, j) with i > j,
  // whose block is stored transposed at (j, i) (BlockTarget's convention). Throws
  // std::invalid_argument for a node out of [0, nodes).
  void build(int nodes, const std::vector<std::pair<int, int>>& pairs, std::vector<int>& slots);

  int nodes() const { return static_cast<int>(row_start_.size()) - 1; }
  // Block row i holds the blocks row_start(i) .. row_start(i + 1) - 1 (its diagonal first), block b
  // in block column column(b).
  int row_start(int i) const { return row_start_[static_cast<std::size_t>(i)]; }
  int column(int b) const { return column_[static_cast<std::size_t>(b)]; }
  int blocks() const { return static_cast<int>(column_.size()); }
  Real* values() { return values_.data(); }
  const Real* values() const { return values_.data(); }
  void set_zero() { std::fill(values_.begin(), values_.end(), Real(0)); }

  // Offset of node i's diagonal block in values().
  int diagonal_offset(int i) const { return 9 * row_start_[static_cast<std::size_t>(i)]; }
  Eigen::Map<Mat3> diagonal_block(int i) {
    return Eigen::Map<Mat3>(values_.data() + diagonal_offset(i));
  }
  Eigen::Map<const Mat3> diagonal_block(int i) const {
    return Eigen::Map<const Mat3>(values_.data() + diagonal_offset(i));
  }

  // Replaces the rows and columns of held coordinates (free == 0) by those of the identity.
  //   free  #nodes by 3, 1 = free, 0 = held
  void hold(const Points& free);

  // y = A x (x, y #nodes by 3, distinct). Allocates nothing.
  void multiply(const Points& x, Points& y) const;

  bool all_finite() const;

  // The lower triangle as an Eigen compressed-column matrix (for Eigen's LDLT and incomplete
  // Cholesky, which read only the lower triangle). lower_pattern builds it once per pattern;
  // copy_lower rewrites its values.
  void lower_pattern(Eigen::SparseMatrix<Real>& lower);
  void copy_lower(Eigen::SparseMatrix<Real>& lower) const;
  // The full symmetric matrix (for tests and inspection).
  Eigen::SparseMatrix<Real> full() const;

 private:
  // visit(value index, row, column) for every stored value on or below the diagonal of A.
  template <class Visit>
  void for_each_lower_entry(const Visit& visit) const;

  std::vector<int> row_start_;   // #nodes + 1, block index of each block row's first block
  std::vector<int> column_;      // #blocks, the block column j >= the row
  std::vector<Real> values_;     // 9 #blocks
  std::vector<int> lower_slot_;  // per stored value, its slot in the lower matrix (-1: none)
};

}  // namespace incise::sim
