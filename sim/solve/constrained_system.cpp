#include "sim/solve/constrained_system.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace incise::sim {
namespace {

using VectorView = Eigen::Map<VecX>;
using ConstVectorView = Eigen::Map<const VecX>;

}  // namespace

bool ConstrainedSystem::prepare(const Model& model, Real mass_scale, Real damping_scale,
                                Real stiffness_scale, const Points& free,
                                const LinearSolveSettings& settings) {
  if (!(mass_scale >= 0) || !(damping_scale >= 0) || !(stiffness_scale > 0)) {
    throw std::invalid_argument("linear system needs a >= 0, b >= 0, c > 0");
  }
  const bool assembled = settings.solver != LinearSolver::matrix_free_cg;
  if (settings.preconditioner == Preconditioner::incomplete_cholesky &&
      settings.solver != LinearSolver::assembled_cg) {
    throw std::invalid_argument("the incomplete Cholesky preconditioner needs assembled_cg");
  }
  const Eigen::Index n = model.masses().size();
  if (free.rows() != n) throw std::invalid_argument("free mask must be #nodes by 3");
  if (model_ != &model || settings.preconditioner != settings_.preconditioner) {
    incomplete_valid_ = false;
  }
  model_ = &model;
  mass_scale_ = mass_scale;
  damping_scale_ = damping_scale;
  stiffness_scale_ = stiffness_scale;
  free_ = &free;
  settings_ = settings;
  cg_work_.resize(n);
  if (scratch_.rows() != n) {
    scratch_.resize(n, 3);
    rhs_.resize(n, 3);
    diagonal_.resize(n, 3);
    block_inverse_.resize(static_cast<std::size_t>(n));
  }
  pattern_rebuilt_ = false;

  const VecX& m = model.masses();
  if (assembled) {
    if (!assemble()) return false;
  }
  if (settings.solver == LinearSolver::assembled_ldlt) {
    const bool new_pattern = !lower_pattern_;
    if (new_pattern) {
      matrix_.lower_pattern(lower_);
      lower_pattern_ = true;
    }
    matrix_.copy_lower(lower_);
    if (new_pattern) ldlt_.analyzePattern(lower_);
    ldlt_.factorize(lower_);
    return ldlt_.info() == Eigen::Success;
  }
  switch (settings.preconditioner) {
    case Preconditioner::none:
      diagonal_.setOnes();
      break;
    case Preconditioner::mass:
      // Without a mass term (statics) M still fixes the relative scale of the nodes.
      for (Eigen::Index i = 0; i < n; ++i) {
        diagonal_.row(i).setConstant(mass_scale > 0 ? mass_scale * m(i) : m(i));
      }
      break;
    case Preconditioner::jacobi:
      if (assembled) {
        for (Eigen::Index d = 0; d < 3 * n; ++d) {
          diagonal_.data()[d] = matrix_.diagonal_block(static_cast<int>(d / 3))(d % 3, d % 3);
        }
      } else {
        if (!prepare_diagonal_blocks()) return false;
        for (Eigen::Index d = 0; d < 3 * n; ++d)
          diagonal_.data()[d] =
              block_diagonal_[static_cast<std::size_t>(9 * (d / 3) + 4 * (d % 3))];
      }
      break;
    case Preconditioner::block_jacobi:
      if (!assembled && !prepare_diagonal_blocks()) return false;
      for (Eigen::Index i = 0; i < n; ++i) {
        Mat3 block;
        for (int c = 0; c < 3; ++c) {
          for (int r = 0; r < 3; ++r) {
            block(r, c) = assembled ? matrix_.diagonal_block(static_cast<int>(i))(r, c)
                                    : block_diagonal_[static_cast<std::size_t>(9 * i + 3 * c + r)];
          }
        }
        // Held axes: identity rows and columns, as in A.
        for (int a = 0; a < 3; ++a) {
          if (free(i, a) != 0) continue;
          block.row(a).setZero();
          block.col(a).setZero();
          block(a, a) = 1;
        }
        if (!block.allFinite()) return false;
        // An indefinite block (an indefinite tangent) would break the preconditioner's positivity;
        // fall back to its diagonal there, and to 1 where that is not positive either.
        Eigen::LLT<Mat3> llt(block);
        if (llt.info() == Eigen::Success) {
          block_inverse_[static_cast<std::size_t>(i)] = llt.solve(Mat3::Identity());
        } else {
          Mat3 inverse = Mat3::Zero();
          for (int a = 0; a < 3; ++a)
            inverse(a, a) = block(a, a) > 0 ? 1 / block(a, a) : 1;
          block_inverse_[static_cast<std::size_t>(i)] = inverse;
        }
      }
      return true;
    case Preconditioner::incomplete_cholesky:
      if ((incomplete_valid_ && !pattern_rebuilt_) || factorise_incomplete()) return true;
      // No positive pivots even with the largest shift (an indefinite tangent): this step is
      // preconditioned by the diagonal instead (precondition() checks incomplete_valid_).
      for (Eigen::Index d = 0; d < 3 * n; ++d)
        diagonal_.data()[d] = matrix_.diagonal_block(static_cast<int>(d / 3))(d % 3, d % 3);
      break;
  }
  for (Eigen::Index d = 0; d < 3 * n; ++d) {
    Real& entry = diagonal_.data()[d];
    if (free.data()[d] == 0) entry = 1;
    if (!std::isfinite(entry)) return false;
    // A non-positive diagonal (an indefinite tangent) would break the preconditioner's symmetry
    // and positivity; fall back to the identity there.
    if (!(entry > 0)) entry = 1;
  }
  return true;
}

bool ConstrainedSystem::assemble() {
  const VecX& m = model_->masses();
  const int nodes = static_cast<int>(m.size());
  if (matrix_.nodes() != nodes || pattern_model_ != model_ ||
      pattern_revision_ != model_->topology_revision()) {
    rebuild_pattern();
  }
  matrix_.set_zero();
  model_->add_system_blocks(damping_scale_, stiffness_scale_,
                            BlockTarget{matrix_.values(), block_slots_.data()});
  for (int i = 0; i < nodes; ++i)
    matrix_.diagonal_block(i).diagonal().array() += mass_scale_ * m(i);
  // Held coordinates: identity rows and columns, so that A stays symmetric positive definite.
  matrix_.hold(*free_);
  return matrix_.all_finite();
}

void ConstrainedSystem::rebuild_pattern() {
  std::vector<std::pair<int, int>> blocks;
  model_->system_blocks(blocks);
  try {
    matrix_.build(static_cast<int>(model_->masses().size()), blocks, block_slots_);
  } catch (const std::invalid_argument& e) {
    throw std::logic_error(std::string(model_->name()) + " gave a " + e.what());
  }
  pattern_model_ = model_;
  pattern_revision_ = model_->topology_revision();
  pattern_rebuilt_ = true;
  lower_pattern_ = false;
  incomplete_valid_ = false;
}

bool ConstrainedSystem::prepare_diagonal_blocks() {
  const Eigen::Index n = model_->masses().size();
  const std::size_t sink = static_cast<std::size_t>(9 * n);
  const std::size_t size = sink + 9;
  if (diagonal_model_ != model_ || diagonal_revision_ != model_->topology_revision() ||
      block_diagonal_.size() != size) {
    std::vector<std::pair<int, int>> blocks;
    model_->system_blocks(blocks);
    block_diagonal_slots_.resize(blocks.size());
    for (std::size_t k = 0; k < blocks.size(); ++k) {
      // Off-diagonal blocks all land in the sink block after the last node.
      block_diagonal_slots_[k] =
          blocks[k].first == blocks[k].second ? 9 * blocks[k].first : static_cast<int>(sink);
    }
    block_diagonal_.resize(size);
    diagonal_model_ = model_;
    diagonal_revision_ = model_->topology_revision();
  }
  std::fill(block_diagonal_.begin(), block_diagonal_.end(), Real(0));
  model_->add_system_blocks(damping_scale_, stiffness_scale_,
                            BlockTarget{block_diagonal_.data(), block_diagonal_slots_.data()});
  const VecX& m = model_->masses();
  for (Eigen::Index i = 0; i < n; ++i) {
    for (int a = 0; a < 3; ++a)
      block_diagonal_[static_cast<std::size_t>(9 * i + 4 * a)] += mass_scale_ * m(i);
  }
  return std::all_of(block_diagonal_.begin(), block_diagonal_.begin() + static_cast<long>(sink),
                     [](Real value) { return std::isfinite(value); });
}

bool ConstrainedSystem::factorise_incomplete() {
  incomplete_valid_ = incomplete_.factorize(matrix_);
  iterations_after_factorisation_ = -1;  // set by the next solve
  ++factorisations_;
  return incomplete_valid_;
}

void ConstrainedSystem::apply_unconstrained(const Points& p, Points& out) const {
  const VecX& m = model_->masses();
  for (Eigen::Index i = 0; i < p.rows(); ++i)
    out.row(i) = (mass_scale_ * m(i)) * p.row(i);
  if (damping_scale_ > 0) {
    scratch_.setZero();
    model_->add_damping_times(p, scratch_);
    out += damping_scale_ * scratch_;
  }
  scratch_.setZero();
  model_->add_stiffness_times(p, scratch_);
  out += stiffness_scale_ * scratch_;
}

void ConstrainedSystem::apply(const Points& p, Points& out) const {
  if (settings_.solver == LinearSolver::matrix_free_cg) {
    apply_unconstrained(p, out);
  } else {
    matrix_.multiply(p, out);
  }
  out = out.cwiseProduct(*free_);
}

void ConstrainedSystem::precondition(const Points& r, Points& z) const {
  switch (settings_.solver == LinearSolver::assembled_ldlt ? Preconditioner::none
                                                           : settings_.preconditioner) {
    case Preconditioner::none:
      if (settings_.solver == LinearSolver::assembled_ldlt) {
        VectorView(z.data(), z.size()) = ldlt_.solve(ConstVectorView(r.data(), r.size()));
        z = z.cwiseProduct(*free_);
        return;
      }
      break;
    case Preconditioner::block_jacobi:
      for (Eigen::Index i = 0; i < r.rows(); ++i) {
        z.row(i) = (block_inverse_[static_cast<std::size_t>(i)] * r.row(i).transpose()).transpose();
      }
      z = z.cwiseProduct(*free_);
      return;
    case Preconditioner::incomplete_cholesky:
      if (!incomplete_valid_) break;  // the diagonal fallback of prepare
      incomplete_.solve(r, z);
      z = z.cwiseProduct(*free_);
      return;
    case Preconditioner::mass:
    case Preconditioner::jacobi:
      break;
  }
  z = r.cwiseQuotient(diagonal_).cwiseProduct(*free_);
}

CgReport ConstrainedSystem::solve(const Points& rhs, Points& y) {
  if (model_ == nullptr) throw std::logic_error("ConstrainedSystem::solve before prepare");
  rhs_ = rhs.cwiseProduct(*free_);
  y = y.cwiseProduct(*free_);
  const CgReport report = conjugate_gradient(
      [this](const Points& p, Points& q) { apply(p, q); },
      [this](const Points& r, Points& z) { precondition(r, z); }, rhs_, settings_.cg, cg_work_, y);
  if (settings_.preconditioner == Preconditioner::incomplete_cholesky &&
      settings_.solver == LinearSolver::assembled_cg) {
    // The lag policy: the first solve after a factorisation sets the baseline; a solve that
    // needs refactor_ratio times as many iterations (the matrix has drifted away from the
    // factor) or breaks down asks for a new factorisation at the next prepare.
    if (iterations_after_factorisation_ < 0) {
      iterations_after_factorisation_ = std::max(report.iterations, 1);
    } else if (report.breakdown ||
               report.iterations > settings_.refactor_ratio * iterations_after_factorisation_) {
      incomplete_valid_ = false;
    }
  }
  return report;
}

}  // namespace incise::sim
