#include "sim/calibrate/linear_response.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace incise::sim::calibrate {

std::vector<ProbeExperiment> attach_probe_data(const ProbeData& data, const Points& rest,
                                               const std::vector<char>& fixed, Real max_distance) {
  std::vector<ProbeExperiment> experiments;
  for (const ProbeContact& contact : data.contacts) {
    const Vec3 start = contact.samples.front().position;
    int nearest = -1;
    Real nearest_distance = std::numeric_limits<Real>::infinity();
    for (int i = 0; i < rest.rows(); ++i) {
      if (fixed[static_cast<std::size_t>(i)]) continue;
      const Real d = (row3(rest, i) - start).norm();
      if (d < nearest_distance) {
        nearest_distance = d;
        nearest = i;
      }
    }
    if (nearest < 0 || nearest_distance > max_distance) {
      std::ostringstream why;
      why.precision(3);
      why << "contact " << contact.id << ": the probe starts at (" << start.x() << ", " << start.y()
          << ", " << start.z() << ") m, ";
      if (nearest < 0) {
        why << "and the scene holds every node fixed";
      } else {
        why << nearest_distance * 1e3 << " mm from the nearest free node of the tissue (at most "
            << max_distance * 1e3 << " mm)";
      }
      why << ": no contact";
      throw CalibrationError(why.str());
    }
    ProbeExperiment e;
    e.contact_id = contact.id;
    e.node = nearest;
    e.distance = nearest_distance;
    const auto steps = static_cast<Eigen::Index>(contact.samples.size()) - 1;
    e.force.resize(steps, 3);
    e.measured.resize(steps, 3);
    for (Eigen::Index k = 0; k < steps; ++k) {
      const ProbeSample& s = contact.samples[static_cast<std::size_t>(k + 1)];
      e.force.row(k) = (s.force * s.direction).transpose();
      e.measured.row(k) = (s.position - start).transpose();
    }
    experiments.push_back(std::move(e));
  }
  return experiments;
}

LinearResponse::LinearResponse(const VecX& masses, const std::vector<char>& fixed, Real step,
                               std::vector<ProbeExperiment> experiments)
    : experiments_(std::move(experiments)), step_(step) {
  const auto nodes = static_cast<int>(masses.size());
  free_of_coordinate_.assign(static_cast<std::size_t>(3 * nodes), -1);
  for (int i = 0; i < nodes; ++i) {
    if (fixed[static_cast<std::size_t>(i)]) continue;
    for (int a = 0; a < 3; ++a)
      free_of_coordinate_[static_cast<std::size_t>(3 * i + a)] = free_++;
  }
  if (free_ == 0) throw CalibrationError("the scene holds every node fixed: nothing to probe");
  if (!(step_ > 0)) throw CalibrationError("the data's time step is not positive");
  mass_.resize(free_);
  for (int i = 0; i < nodes; ++i) {
    for (int a = 0; a < 3; ++a) {
      const int f = free_of_coordinate_[static_cast<std::size_t>(3 * i + a)];
      if (f >= 0) mass_[f] = masses[i];
    }
  }
  for (const ProbeExperiment& e : experiments_) {
    if (fixed[static_cast<std::size_t>(e.node)]) {
      throw CalibrationError("contact " + std::to_string(e.contact_id) + " pushes a fixed node");
    }
    steps_ = std::max(steps_, static_cast<int>(e.force.rows()));
  }
  const auto columns = static_cast<Eigen::Index>(experiments_.size());
  u_.resize(free_, columns);
  v_.resize(free_, columns);
  w_.resize(free_, columns);
  rhs_.resize(free_, columns);
}

SparseMatrix LinearResponse::free_matrix(const Triplets& entries) const {
  Triplets kept;
  kept.reserve(entries.size());
  for (const auto& t : entries) {
    const int r = free_of_coordinate_[static_cast<std::size_t>(t.row())];
    const int c = free_of_coordinate_[static_cast<std::size_t>(t.col())];
    if (r >= 0 && c >= 0) kept.emplace_back(r, c, t.value());
  }
  SparseMatrix m(free_, free_);
  m.setFromTriplets(kept.begin(), kept.end());
  return m;
}

bool LinearResponse::simulate(const Triplets& stiffness, const Triplets& damping,
                              std::vector<Points>& displacement) {
  const Real h = step_;
  const SparseMatrix k = free_matrix(stiffness);
  const SparseMatrix d = free_matrix(damping);
  SparseMatrix a = h * d + (h * h) * k;
  for (int i = 0; i < free_; ++i)
    a.coeffRef(i, i) += mass_[i];
  solver_.compute(a);
  if (solver_.info() != Eigen::Success) return false;

  displacement.resize(experiments_.size());
  for (std::size_t e = 0; e < experiments_.size(); ++e) {
    displacement[e].resize(experiments_[e].force.rows(), 3);
  }
  u_.setZero();
  v_.setZero();
  for (int step = 0; step < steps_; ++step) {
    // rhs = h (f - D v - K (u + h v))
    w_ = u_ + h * v_;
    rhs_.noalias() = -(k * w_);
    rhs_.noalias() -= d * v_;
    for (std::size_t e = 0; e < experiments_.size(); ++e) {
      const ProbeExperiment& x = experiments_[e];
      if (step >= x.force.rows()) continue;
      for (int a = 0; a < 3; ++a) {
        rhs_(free_of_coordinate_[static_cast<std::size_t>(3 * x.node + a)],
             static_cast<Eigen::Index>(e)) += x.force(step, a);
      }
    }
    rhs_ *= h;
    v_ += solver_.solve(rhs_);
    u_ += h * v_;
    for (std::size_t e = 0; e < experiments_.size(); ++e) {
      const ProbeExperiment& x = experiments_[e];
      if (step >= x.force.rows()) continue;
      for (int a = 0; a < 3; ++a) {
        displacement[e](step, a) = u_(free_of_coordinate_[static_cast<std::size_t>(3 * x.node + a)],
                                      static_cast<Eigen::Index>(e));
      }
    }
  }
  return u_.allFinite();
}

}  // namespace incise::sim::calibrate
