#include "sim/solve/constrained_system.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace incise::sim {
namespace {

using SparseVector = Eigen::Map<VecX>;
using ConstSparseVector = Eigen::Map<const VecX>;

}  // namespace

bool ConstrainedSystem::prepare(const Model& model, Real mass_scale, Real damping_scale,
                                Real stiffness_scale, const Points& free,
                                const LinearSolveSettings& settings) {
  if (!(mass_scale >= 0) || !(damping_scale >= 0) || !(stiffness_scale > 0)) {
    throw std::invalid_argument("linear system needs a >= 0, b >= 0, c > 0");
  }
  const Eigen::Index n = model.masses().size();
  if (free.rows() != n) throw std::invalid_argument("free mask must be #nodes by 3");
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
  }
  pattern_rebuilt_ = false;

  const VecX& m = model.masses();
  const bool assembled = settings.solver != LinearSolver::matrix_free_cg;
  if (assembled) {
    if (!assemble()) return false;
  }
  if (settings.solver == LinearSolver::assembled_ldlt) {
    if (pattern_rebuilt_ || !factorised_pattern_) {
      ldlt_.analyzePattern(matrix_);
      factorised_pattern_ = true;
    }
    ldlt_.factorize(matrix_);
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
        for (Eigen::Index d = 0; d < 3 * n; ++d)
          diagonal_.data()[d] = matrix_.coeff(d, d);
      } else {
        triplets_.clear();
        model.add_stiffness_triplets(triplets_);
        for (Eigen::Index i = 0; i < n; ++i)
          diagonal_.row(i).setConstant(mass_scale * m(i));
        for (const auto& t : triplets_) {
          if (t.row() == t.col()) diagonal_.data()[t.row()] += stiffness_scale * t.value();
        }
      }
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
  const Eigen::Index dofs = 3 * m.size();
  triplets_.clear();
  model_->add_stiffness_triplets(triplets_);
  model_triplets_ = triplets_.size();
  // The mass diagonal also guarantees every diagonal entry a slot in the pattern.
  for (Eigen::Index d = 0; d < dofs; ++d) {
    triplets_.emplace_back(static_cast<int>(d), static_cast<int>(d), m(d / 3));
  }
  if (matrix_.rows() != dofs || slots_.size() != triplets_.size() || !scatter_values()) {
    rebuild_pattern();
    scatter_values();
  }
  // Held coordinates: identity rows and columns, so that A stays symmetric positive definite.
  const Real* free = free_->data();
  Real* values = matrix_.valuePtr();
  const int* inner = matrix_.innerIndexPtr();
  const int* outer = matrix_.outerIndexPtr();
  for (Eigen::Index j = 0; j < dofs; ++j) {
    for (int s = outer[j]; s < outer[j + 1]; ++s) {
      const int i = inner[s];
      if (free[i] == 0 || free[j] == 0) values[s] = (i == j) ? 1 : 0;
    }
  }
  return Eigen::Map<const VecX>(values, matrix_.nonZeros()).allFinite();
}

void ConstrainedSystem::rebuild_pattern() {
  const Eigen::Index dofs = 3 * model_->masses().size();
  for (const auto& t : triplets_) {
    if (t.row() < 0 || t.row() >= dofs || t.col() < 0 || t.col() >= dofs) {
      throw std::logic_error(std::string(model_->name()) + " gave a stiffness triplet (" +
                             std::to_string(t.row()) + ", " + std::to_string(t.col()) +
                             ") outside the " + std::to_string(dofs) + " degrees of freedom");
    }
  }
  matrix_.resize(dofs, dofs);
  matrix_.setFromTriplets(triplets_.begin(), triplets_.end());  // compressed, sorted columns
  const int* inner = matrix_.innerIndexPtr();
  const int* outer = matrix_.outerIndexPtr();
  slots_.resize(triplets_.size());
  for (std::size_t k = 0; k < triplets_.size(); ++k) {
    const auto& t = triplets_[k];
    const int* begin = inner + outer[t.col()];
    const int* end = inner + outer[t.col() + 1];
    slots_[k] = static_cast<int>(std::lower_bound(begin, end, t.row()) - inner);
  }
  pattern_rebuilt_ = true;
}

bool ConstrainedSystem::scatter_values() {
  Real* values = matrix_.valuePtr();
  const int* inner = matrix_.innerIndexPtr();
  const int* outer = matrix_.outerIndexPtr();
  std::fill(values, values + matrix_.nonZeros(), Real(0));
  for (std::size_t k = 0; k < triplets_.size(); ++k) {
    const auto& t = triplets_[k];
    const int s = slots_[k];
    // The same model on the same topology gives its triplets in the same order; anything else
    // (a topology change) is caught here and rebuilds the pattern.
    if (t.col() < 0 || t.col() >= matrix_.cols() || s < outer[t.col()] || s >= outer[t.col() + 1] ||
        inner[s] != t.row()) {
      return false;
    }
    values[s] += (k < model_triplets_ ? stiffness_scale_ : mass_scale_) * t.value();
  }
  return true;
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
    SparseVector(out.data(), out.size()).noalias() =
        matrix_ * ConstSparseVector(p.data(), p.size());
    if (damping_scale_ > 0) {
      scratch_.setZero();
      model_->add_damping_times(p, scratch_);
      out += damping_scale_ * scratch_;
    }
  }
  out = out.cwiseProduct(*free_);
}

void ConstrainedSystem::precondition(const Points& r, Points& z) const {
  if (settings_.solver == LinearSolver::assembled_ldlt) {
    SparseVector(z.data(), z.size()) = ldlt_.solve(ConstSparseVector(r.data(), r.size()));
    z = z.cwiseProduct(*free_);
  } else {
    z = r.cwiseQuotient(diagonal_).cwiseProduct(*free_);
  }
}

CgReport ConstrainedSystem::solve(const Points& rhs, Points& y) {
  if (model_ == nullptr) throw std::logic_error("ConstrainedSystem::solve before prepare");
  rhs_ = rhs.cwiseProduct(*free_);
  y = y.cwiseProduct(*free_);
  return conjugate_gradient([this](const Points& p, Points& q) { apply(p, q); },
                            [this](const Points& r, Points& z) { precondition(r, z); }, rhs_,
                            settings_.cg, cg_work_, y);
}

}  // namespace incise::sim
