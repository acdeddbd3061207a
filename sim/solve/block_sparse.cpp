#include "sim/solve/block_sparse.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace incise::sim {

void SymmetricBlockMatrix::build(int nodes, const std::vector<std::pair<int, int>>& pairs,
                                 std::vector<int>& slots) {
  // Per block row, the sorted distinct columns j >= i (the diagonal included).
  std::vector<std::vector<int>> columns(static_cast<std::size_t>(nodes));
  for (int i = 0; i < nodes; ++i)
    columns[static_cast<std::size_t>(i)].push_back(i);
  for (const auto& [i, j] : pairs) {
    if (i < 0 || i >= nodes || j < 0 || j >= nodes) {
      throw std::invalid_argument("matrix block (" + std::to_string(i) + ", " + std::to_string(j) +
                                  ") outside the " + std::to_string(nodes) + " nodes");
    }
    columns[static_cast<std::size_t>(std::min(i, j))].push_back(std::max(i, j));
  }
  row_start_.assign(static_cast<std::size_t>(nodes) + 1, 0);
  column_.clear();
  for (int i = 0; i < nodes; ++i) {
    auto& row = columns[static_cast<std::size_t>(i)];
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    column_.insert(column_.end(), row.begin(), row.end());  // the diagonal (j = i) comes first
    row_start_[static_cast<std::size_t>(i) + 1] = static_cast<int>(column_.size());
  }
  values_.assign(9 * column_.size(), Real(0));
  slots.resize(pairs.size());
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    const auto [i, j] = pairs[k];
    const int row = std::min(i, j);
    const auto begin = column_.begin() + row_start_[static_cast<std::size_t>(row)];
    const auto end = column_.begin() + row_start_[static_cast<std::size_t>(row) + 1];
    const int offset =
        9 * static_cast<int>(std::lower_bound(begin, end, std::max(i, j)) - column_.begin());
    slots[k] = i <= j ? offset : -offset - 1;
  }
  lower_slot_.clear();
}

void SymmetricBlockMatrix::hold(const Points& free) {
  for (int i = 0; i < nodes(); ++i) {
    for (int b = row_start_[static_cast<std::size_t>(i)];
         b < row_start_[static_cast<std::size_t>(i) + 1]; ++b) {
      const int j = column_[static_cast<std::size_t>(b)];
      Eigen::Map<Mat3> block(values_.data() + 9 * b);
      for (int a = 0; a < 3; ++a) {
        if (free(i, a) == 0) block.row(a).setZero();
        if (free(j, a) == 0) block.col(a).setZero();
      }
      if (i == j) {
        for (int a = 0; a < 3; ++a) {
          if (free(i, a) == 0) block(a, a) = 1;
        }
      }
    }
  }
}

void SymmetricBlockMatrix::multiply(const Points& x, Points& y) const {
  y.setZero();
  const Real* values = values_.data();
  for (int i = 0; i < nodes(); ++i) {
    const int first = row_start_[static_cast<std::size_t>(i)];
    const int last = row_start_[static_cast<std::size_t>(i) + 1];
    const Vec3 xi = x.row(i).transpose();
    // The diagonal block, then y_i += B x_j and y_j += B^T x_i for each stored B = A_ij.
    Vec3 yi = Eigen::Map<const Mat3>(values + 9 * first) * xi;
    for (int b = first + 1; b < last; ++b) {
      const int j = column_[static_cast<std::size_t>(b)];
      const Eigen::Map<const Mat3> block(values + 9 * b);
      yi.noalias() += block * x.row(j).transpose();
      y.row(j).noalias() += (block.transpose() * xi).transpose();
    }
    y.row(i) += yi.transpose();
  }
}

bool SymmetricBlockMatrix::all_finite() const {
  return Eigen::Map<const VecX>(values_.data(), static_cast<Eigen::Index>(values_.size()))
      .allFinite();
}

template <class Visit>
void SymmetricBlockMatrix::for_each_lower_entry(const Visit& visit) const {
  // Stored block (i, j), j >= i, entry (r, c) is A(3 i + r, 3 j + c) = A(3 j + c, 3 i + r): its
  // lower-triangle position is row 3 j + c, column 3 i + r (for the diagonal block only r >= c).
  for (int i = 0; i < nodes(); ++i) {
    for (int b = row_start(i); b < row_start(i + 1); ++b) {
      const int j = column(b);
      for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r) {
          if (i == j && r < c) continue;
          visit(9 * b + 3 * c + r, i == j ? 3 * i + r : 3 * j + c, i == j ? 3 * i + c : 3 * i + r);
        }
      }
    }
  }
}

void SymmetricBlockMatrix::lower_pattern(Eigen::SparseMatrix<Real>& lower) {
  std::vector<Eigen::Triplet<Real>> entries;
  entries.reserve(values_.size());
  for_each_lower_entry([&](int, int row, int column) { entries.emplace_back(row, column, 0.0); });
  const int dofs = 3 * nodes();
  lower.resize(dofs, dofs);
  lower.setFromTriplets(entries.begin(), entries.end());
  const int* inner = lower.innerIndexPtr();
  const int* outer = lower.outerIndexPtr();
  lower_slot_.assign(values_.size(), -1);
  for_each_lower_entry([&](int value, int row, int column) {
    const int* found = std::lower_bound(inner + outer[column], inner + outer[column + 1], row);
    lower_slot_[static_cast<std::size_t>(value)] = static_cast<int>(found - inner);
  });
}

void SymmetricBlockMatrix::copy_lower(Eigen::SparseMatrix<Real>& lower) const {
  Real* out = lower.valuePtr();
  for (std::size_t v = 0; v < values_.size(); ++v) {
    if (lower_slot_[v] >= 0) out[lower_slot_[v]] = values_[v];
  }
}

Eigen::SparseMatrix<Real> SymmetricBlockMatrix::full() const {
  std::vector<Eigen::Triplet<Real>> entries;
  for (int i = 0; i < nodes(); ++i) {
    for (int b = row_start_[static_cast<std::size_t>(i)];
         b < row_start_[static_cast<std::size_t>(i) + 1]; ++b) {
      const int j = column_[static_cast<std::size_t>(b)];
      for (int c = 0; c < 3; ++c) {
        for (int r = 0; r < 3; ++r) {
          const Real value = values_[static_cast<std::size_t>(9 * b + 3 * c + r)];
          entries.emplace_back(3 * i + r, 3 * j + c, value);
          if (i != j) entries.emplace_back(3 * j + c, 3 * i + r, value);
        }
      }
    }
  }
  Eigen::SparseMatrix<Real> a(3 * nodes(), 3 * nodes());
  a.setFromTriplets(entries.begin(), entries.end());
  return a;
}

}  // namespace incise::sim
