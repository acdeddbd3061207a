#pragma once
// The forward model of calibration: how a body at rest answers each probe experiment, in its
// linearisation at rest (small strain: a probing experiment of a few per cent strain), stepped by
// linearised backward Euler (sim/solve/implicit_euler.h) at the data's sample step:
//   (M + h D + h^2 K) dv = h (f - D v - K (u + h v)),   v += dv,   u += h v,
// for displacement u and velocity v on the free coordinates. The matrix is factorised once per
// parameter set (a sparse LDLT) and every experiment is a column of the same solve, so a
// calibration's thousands of evaluations each cost a few hundred back-substitutions. The
// nonlinear models agree with it to the order of the strain (tests/sim/calibrate/).

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <vector>

#include "sim/calibrate/probe_data.h"
#include "sim/core/types.h"

namespace incise::sim::calibrate {

using SparseMatrix = Eigen::SparseMatrix<Real>;
using Triplets = std::vector<Eigen::Triplet<Real>>;

// One contact of the data on the body: the node the probe pushes, the force over each step and
// the displacement measured at the end of it.
struct ProbeExperiment {
  int contact_id = 0;
  int node = 0;       // the free node nearest to the probe's first position
  Real distance = 0;  // from the probe's first position to that node [m]
  Points force;       // #steps by 3: the force during step k [N]
  Points measured;    // #steps by 3: the probe's displacement at the end of step k [m]
};

// The experiments of data on a body with rest positions rest whose fixed nodes are marked.
// A contact attaches to the nearest free node; it is refused (CalibrationError, "contact 2: the
// probe starts 8.1 mm from the tissue ...: no contact") farther than max_distance [m].
std::vector<ProbeExperiment> attach_probe_data(const ProbeData& data, const Points& rest,
                                               const std::vector<char>& fixed, Real max_distance);

class LinearResponse {
 public:
  //   masses  #nodes lumped masses [kg]
  //   fixed   #nodes, 1 for a node held at rest
  //   step    the data's sample step h [s], > 0
  // Throws CalibrationError when no node is free or an experiment pushes a fixed node.
  LinearResponse(const VecX& masses, const std::vector<char>& fixed, Real step,
                 std::vector<ProbeExperiment> experiments);

  // Simulates every experiment with stiffness K and damping D (entries over the 3 #nodes
  // coordinates, duplicates adding up; those of fixed nodes are dropped). Writes each
  // experiment's simulated displacement (#steps by 3) to displacement. Returns false when the
  // matrix cannot be factorised or the response is not finite (a parameter set the model
  // cannot take); displacement is then unspecified.
  bool simulate(const Triplets& stiffness, const Triplets& damping,
                std::vector<Points>& displacement);

  const std::vector<ProbeExperiment>& experiments() const { return experiments_; }
  Real step() const { return step_; }
  int free_coordinates() const { return free_; }

 private:
  SparseMatrix free_matrix(const Triplets& entries) const;

  std::vector<ProbeExperiment> experiments_;
  Real step_;
  int free_ = 0;
  std::vector<int> free_of_coordinate_;  // 3 #nodes: the free index, or -1
  VecX mass_;                            // free coordinates
  int steps_ = 0;                        // the longest experiment's
  Eigen::SimplicialLDLT<SparseMatrix> solver_;
  Eigen::MatrixXd u_, v_, w_, rhs_;  // free coordinates by experiments
};

}  // namespace incise::sim::calibrate
