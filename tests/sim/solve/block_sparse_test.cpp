// SymmetricBlockMatrix against a dense reference: the blocks a model writes through BlockTarget
// (with the slots build returns, transposed ones included) must add up to the dense symmetric
// sum of block k at (i, j) and its transpose at (j, i), and every view of the stored upper
// triangle (full, multiply, hold, the lower triangle for Eigen) must agree with that sum.
#include "sim/solve/block_sparse.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "sim/models/model.h"

namespace incise::sim {
namespace {

constexpr int kNodes = 9;

struct RandomPattern {
  std::vector<std::pair<int, int>> pairs;
  std::vector<Mat3> blocks;  // one per pair; symmetric for the diagonal pairs (i, i)
};

// Random pairs over nodes 0 .. kNodes - 2 (the last node is in no pair: its block row is the
// diagonal only), in both orders, with repeats of earlier pairs as given and reversed.
RandomPattern random_pattern(unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> node(0, kNodes - 2);
  std::uniform_real_distribution<Real> value(-1, 1);
  RandomPattern pattern;
  for (int k = 0; k < 40; ++k) {
    std::pair<int, int> pair{node(random), node(random)};
    if (k % 5 == 4) {
      // A duplicate of an earlier pair, every other one in the opposite order.
      pair = pattern.pairs[static_cast<std::size_t>(k / 2)];
      if (k % 10 == 9) std::swap(pair.first, pair.second);
    }
    pattern.pairs.push_back(pair);
  }
  pattern.pairs.emplace_back(3, 3);  // a diagonal pair for sure
  pattern.pairs.emplace_back(6, 1);  // a pair below the diagonal for sure
  for (const auto& [i, j] : pattern.pairs) {
    Mat3 block;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c)
        block(r, c) = value(random);
    }
    if (i == j) block = (block + block.transpose()).eval();
    pattern.blocks.push_back(block);
  }
  return pattern;
}

// The matrix the blocks stand for: block k at (i, j) and, for i != j, its transpose at (j, i).
Eigen::MatrixXd dense_sum(const RandomPattern& pattern) {
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(3 * kNodes, 3 * kNodes);
  for (std::size_t k = 0; k < pattern.pairs.size(); ++k) {
    const auto [i, j] = pattern.pairs[k];
    dense.block<3, 3>(3 * i, 3 * j) += pattern.blocks[k];
    if (i != j) dense.block<3, 3>(3 * j, 3 * i) += pattern.blocks[k].transpose();
  }
  return dense;
}

// Builds the matrix on the pattern and writes the blocks through BlockTarget.
void build_and_fill(const RandomPattern& pattern, SymmetricBlockMatrix& matrix) {
  std::vector<int> slots;
  matrix.build(kNodes, pattern.pairs, slots);
  ASSERT_EQ(slots.size(), pattern.pairs.size());
  const BlockTarget target{matrix.values(), slots.data()};
  for (std::size_t k = 0; k < pattern.pairs.size(); ++k)
    target.add(k, pattern.blocks[k]);
}

Real max_abs(const Eigen::MatrixXd& m) {
  return m.cwiseAbs().maxCoeff();
}

TEST(SymmetricBlockMatrix, SlotsPointAtTheStoredUpperBlockAndMarkTransposedPairs) {
  const RandomPattern pattern = random_pattern(1);
  SymmetricBlockMatrix matrix;
  std::vector<int> slots;
  matrix.build(kNodes, pattern.pairs, slots);
  // Diagonal blocks for every node plus one block per distinct unordered off-diagonal pair.
  std::set<std::pair<int, int>> distinct;
  for (const auto& [i, j] : pattern.pairs) {
    if (i != j) distinct.emplace(std::min(i, j), std::max(i, j));
  }
  EXPECT_EQ(matrix.nodes(), kNodes);
  EXPECT_EQ(matrix.blocks(), kNodes + static_cast<int>(distinct.size()));
  for (std::size_t k = 0; k < pattern.pairs.size(); ++k) {
    const auto [i, j] = pattern.pairs[k];
    if (i <= j) {
      EXPECT_GE(slots[k], 0) << i << ", " << j;
    } else {
      EXPECT_LT(slots[k], 0) << i << ", " << j;
    }
    const int offset = slots[k] >= 0 ? slots[k] : -slots[k] - 1;
    EXPECT_EQ(offset % 9, 0);
    if (i == j) {
      EXPECT_EQ(offset, matrix.diagonal_offset(i));
    }
    // The same unordered pair always lands on the same stored block.
    for (std::size_t l = 0; l < k; ++l) {
      const auto [p, q] = pattern.pairs[l];
      const int other = slots[l] >= 0 ? slots[l] : -slots[l] - 1;
      const bool same = std::minmax(i, j) == std::minmax(p, q);
      EXPECT_EQ(offset == other, same) << "pairs " << k << " and " << l;
    }
  }
}

TEST(SymmetricBlockMatrix, FullIsTheDenseSymmetricSumOfTheBlocks) {
  const RandomPattern pattern = random_pattern(2);
  SymmetricBlockMatrix matrix;
  build_and_fill(pattern, matrix);
  const Eigen::MatrixXd expected = dense_sum(pattern);
  const Eigen::MatrixXd full(matrix.full());
  EXPECT_LE(max_abs(full - expected), 1e-14 * max_abs(expected));
  EXPECT_LE(max_abs(full - full.transpose()), 1e-14 * max_abs(expected));
  // The diagonal block view reads the same values.
  for (int i = 0; i < kNodes; ++i) {
    EXPECT_LE(max_abs(Mat3(matrix.diagonal_block(i)) - expected.block<3, 3>(3 * i, 3 * i)),
              1e-14 * max_abs(expected));
  }
  EXPECT_TRUE(matrix.all_finite());
  // set_zero keeps the pattern (same slots) and clears the values.
  matrix.set_zero();
  EXPECT_EQ(Eigen::MatrixXd(matrix.full()).cwiseAbs().maxCoeff(), 0);
}

TEST(SymmetricBlockMatrix, MultiplyIsTheDenseProduct) {
  const RandomPattern pattern = random_pattern(3);
  SymmetricBlockMatrix matrix;
  build_and_fill(pattern, matrix);
  const Eigen::MatrixXd dense = dense_sum(pattern);
  std::mt19937 random(7);
  std::uniform_real_distribution<Real> value(-1, 1);
  for (int trial = 0; trial < 3; ++trial) {
    Points x(kNodes, 3);
    for (Eigen::Index d = 0; d < x.size(); ++d)
      x.data()[d] = value(random);
    Points y = Points::Constant(kNodes, 3, 123.0);  // stale contents must not leak in
    matrix.multiply(x, y);
    const VecX expected = dense * Eigen::Map<const VecX>(x.data(), x.size());
    EXPECT_LE((Eigen::Map<const VecX>(y.data(), y.size()) - expected).cwiseAbs().maxCoeff(),
              1e-13 * expected.cwiseAbs().maxCoeff());
  }
}

TEST(SymmetricBlockMatrix, HoldReplacesHeldRowsAndColumnsByTheIdentity) {
  const RandomPattern pattern = random_pattern(4);
  SymmetricBlockMatrix matrix;
  build_and_fill(pattern, matrix);
  Points free = Points::Ones(kNodes, 3);
  free(0, 1) = 0;
  free.row(3).setZero();  // a node of the sure diagonal pair, all axes
  free(6, 2) = 0;         // a node of the sure (6, 1) pair, stored transposed
  free(kNodes - 1, 0) = 0;
  matrix.hold(free);
  Eigen::MatrixXd expected = dense_sum(pattern);
  const Real scale = max_abs(expected);
  for (Eigen::Index d = 0; d < 3 * kNodes; ++d) {
    if (free.data()[d] != 0) continue;
    expected.row(d).setZero();
    expected.col(d).setZero();
    expected(d, d) = 1;
  }
  const Eigen::MatrixXd full(matrix.full());
  EXPECT_LE(max_abs(full - expected), 1e-14 * scale);
  // The held unknowns of the product are then the held entries of x.
  Points x = Points::Random(kNodes, 3);
  Points y(kNodes, 3);
  matrix.multiply(x, y);
  for (Eigen::Index d = 0; d < 3 * kNodes; ++d) {
    if (free.data()[d] == 0) {
      EXPECT_NEAR(y.data()[d], x.data()[d], 1e-15) << d;
    }
  }
}

TEST(SymmetricBlockMatrix, LowerPatternAndCopyLowerGiveExactlyTheLowerTriangle) {
  const RandomPattern pattern = random_pattern(5);
  SymmetricBlockMatrix matrix;
  std::vector<int> slots;
  matrix.build(kNodes, pattern.pairs, slots);
  Eigen::SparseMatrix<Real> lower;
  matrix.lower_pattern(lower);
  // The structure: every lower entry of the stored blocks, nothing above the diagonal, and as many
  // entries as the blocks hold below and on the diagonal (6 of a diagonal block, 9 of the others).
  ASSERT_EQ(lower.rows(), 3 * kNodes);
  ASSERT_EQ(lower.cols(), 3 * kNodes);
  EXPECT_EQ(lower.nonZeros(), 6 * kNodes + 9 * (matrix.blocks() - kNodes));
  for (int column = 0; column < lower.outerSize(); ++column) {
    for (Eigen::SparseMatrix<Real>::InnerIterator it(lower, column); it; ++it)
      EXPECT_GE(it.row(), it.col());
  }
  // Values: two rounds on the same pattern (copy_lower rewrites, it does not add).
  for (unsigned round = 0; round < 2; ++round) {
    RandomPattern values = random_pattern(5);  // the same pairs ...
    const RandomPattern other = random_pattern(50 + round);
    for (std::size_t k = 0; k < values.blocks.size(); ++k) {
      values.blocks[k] = other.blocks[k];  // ... with other blocks
      if (values.pairs[k].first == values.pairs[k].second)
        values.blocks[k] = (values.blocks[k] + values.blocks[k].transpose()).eval();
    }
    matrix.set_zero();
    const BlockTarget target{matrix.values(), slots.data()};
    for (std::size_t k = 0; k < values.pairs.size(); ++k)
      target.add(k, values.blocks[k]);
    matrix.copy_lower(lower);
    const Eigen::MatrixXd full(matrix.full());
    const Eigen::MatrixXd expected = full.triangularView<Eigen::Lower>();
    EXPECT_LE(max_abs(Eigen::MatrixXd(lower) - expected), 1e-15 * max_abs(full))
        << "round " << round;
    EXPECT_LE(max_abs(full - dense_sum(values)), 1e-14 * max_abs(full));
  }
}

TEST(SymmetricBlockMatrix, BuildRejectsNodesOutOfRange) {
  SymmetricBlockMatrix matrix;
  std::vector<int> slots;
  EXPECT_THROW(matrix.build(4, {{0, 1}, {2, 4}}, slots), std::invalid_argument);
  EXPECT_THROW(matrix.build(4, {{4, 0}}, slots), std::invalid_argument);
  EXPECT_THROW(matrix.build(4, {{-1, 2}}, slots), std::invalid_argument);
  EXPECT_THROW(matrix.build(4, {{1, -1}}, slots), std::invalid_argument);
  // In range, including the last node, builds.
  EXPECT_NO_THROW(matrix.build(4, {{3, 0}, {3, 3}}, slots));
  EXPECT_EQ(matrix.blocks(), 5);
}

}  // namespace
}  // namespace incise::sim
