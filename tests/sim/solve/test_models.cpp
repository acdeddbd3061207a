#include "test_models.h"

#include <cmath>

namespace incise::sim::testing {
namespace {

Eigen::Map<const VecX> as_vector(const Points& p) {
  return Eigen::Map<const VecX>(p.data(), p.size());
}
Eigen::Map<VecX> as_vector(Points& p) {
  return Eigen::Map<VecX>(p.data(), p.size());
}

}  // namespace

LinearModel::LinearModel(Points rest, VecX masses, SparseMatrix stiffness, Real alpha, Real beta)
    : rest_(std::move(rest)),
      masses_(std::move(masses)),
      stiffness_(std::move(stiffness)),
      alpha_(alpha),
      beta_(beta),
      work_(rest_.rows(), 3) {}

void LinearModel::add_forces(const Points& x, const Points& v, Points& f) {
  work_ = x - rest_;
  as_vector(f) -= stiffness_ * as_vector(work_);
  add_damping_times(v, work_.setZero());
  f -= work_;
}

void LinearModel::add_stiffness_times(const Points& dx, Points& out) const {
  as_vector(out) += stiffness_ * as_vector(dx);
}

void LinearModel::add_damping_times(const Points& dv, Points& out) const {
  if (alpha_ != 0) {
    for (Eigen::Index i = 0; i < dv.rows(); ++i)
      out.row(i) += alpha_ * masses_(i) * dv.row(i);
  }
  if (beta_ != 0) as_vector(out) += beta_ * (stiffness_ * as_vector(dv));
}

void LinearModel::add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const {
  for (int j = 0; j < stiffness_.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(stiffness_, j); it; ++it) {
      triplets.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()), it.value());
    }
  }
}

void LinearModel::add_damping_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const {
  for (Eigen::Index i = 0; i < masses_.size(); ++i) {
    for (int a = 0; a < 3; ++a) {
      const int d = static_cast<int>(3 * i + a);
      triplets.emplace_back(d, d, alpha_ * masses_(i));
    }
  }
  for (int j = 0; j < stiffness_.outerSize(); ++j) {
    for (SparseMatrix::InnerIterator it(stiffness_, j); it; ++it) {
      triplets.emplace_back(static_cast<int>(it.row()), static_cast<int>(it.col()),
                            beta_ * it.value());
    }
  }
}

Real LinearModel::potential_energy(const Points& x) const {
  const Points u = x - rest_;
  return 0.5 * as_vector(u).dot(stiffness_ * as_vector(u));
}

LinearModel make_oscillator(Real mass, Real stiffness, Real alpha, Real beta) {
  SparseMatrix k(3, 3);
  k.setIdentity();
  k *= stiffness;
  return LinearModel(Points::Zero(1, 3), VecX::Constant(1, mass), k, alpha, beta);
}

LinearModel make_spring_pair(Real stiffness) {
  SparseMatrix k(6, 6);
  for (int a = 0; a < 3; ++a) {
    k.insert(a, a) = stiffness;
    k.insert(3 + a, 3 + a) = stiffness;
    k.insert(a, 3 + a) = -stiffness;
    k.insert(3 + a, a) = -stiffness;
  }
  Points rest(2, 3);
  rest << 0, 0, 0, 1, 0, 0;
  return LinearModel(rest, VecX::Constant(2, 1.0), k);
}

LinearModel make_linear_tet_model(const TetMesh& mesh, Real youngs_modulus, Real poisson_ratio,
                                  Real density, Real alpha, Real beta) {
  const Real nu = poisson_ratio;
  const Real lambda = youngs_modulus * nu / ((1 + nu) * (1 - 2 * nu));
  const Real mu = youngs_modulus / (2 * (1 + nu));
  std::vector<Eigen::Triplet<Real>> triplets;
  VecX masses = VecX::Zero(mesh.num_nodes());
  for (int t = 0; t < mesh.num_tets(); ++t) {
    Vec3 p[4];
    for (int k = 0; k < 4; ++k)
      p[k] = row3(mesh.rest, mesh.tets(t, k));
    Mat3 dm;
    dm << p[1] - p[0], p[2] - p[0], p[3] - p[0];
    const Real volume = dm.determinant() / 6;
    const Mat3 inv = dm.inverse();  // row k = gradient of the shape function of node k + 1
    Vec3 g[4];
    for (int k = 0; k < 3; ++k)
      g[k + 1] = inv.row(k).transpose();
    g[0] = -(g[1] + g[2] + g[3]);
    for (int a = 0; a < 4; ++a) {
      masses(mesh.tets(t, a)) += density * volume / 4;
      for (int b = 0; b < 4; ++b) {
        const Mat3 block =
            volume * (lambda * g[a] * g[b].transpose() + mu * g[b] * g[a].transpose() +
                      mu * g[a].dot(g[b]) * Mat3::Identity());
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) {
            triplets.emplace_back(3 * mesh.tets(t, a) + i, 3 * mesh.tets(t, b) + j, block(i, j));
          }
        }
      }
    }
  }
  SparseMatrix k(3 * mesh.num_nodes(), 3 * mesh.num_nodes());
  k.setFromTriplets(triplets.begin(), triplets.end());
  return LinearModel(mesh.rest, masses, k, alpha, beta);
}

NonlinearSprings::NonlinearSprings(Points rest, Edges edges, VecX masses, Real k1, Real k3)
    : edges_(std::move(edges)),
      rest_lengths_(edges_.rows()),
      masses_(std::move(masses)),
      k1_(k1),
      k3_(k3),
      blocks_(static_cast<std::size_t>(edges_.rows()), Mat3::Zero()) {
  for (Eigen::Index s = 0; s < edges_.rows(); ++s) {
    rest_lengths_(s) = (row3(rest, edges_(s, 1)) - row3(rest, edges_(s, 0))).norm();
  }
}

void NonlinearSprings::add_forces(const Points& x, const Points&, Points& f) {
  for (Eigen::Index s = 0; s < edges_.rows(); ++s) {
    const Vec3 d = row3(x, edges_(s, 1)) - row3(x, edges_(s, 0));
    const Real l = d.norm();
    const Vec3 pull = tension(l - rest_lengths_(s)) * d / l;
    f.row(edges_(s, 0)) += pull.transpose();
    f.row(edges_(s, 1)) -= pull.transpose();
  }
}

void NonlinearSprings::prepare_stiffness(const Points& x) {
  for (Eigen::Index s = 0; s < edges_.rows(); ++s) {
    const Vec3 d = row3(x, edges_(s, 1)) - row3(x, edges_(s, 0));
    const Real l = d.norm();
    const Vec3 n = d / l;
    const Real e = l - rest_lengths_(s);
    const Real slope = k1_ + 3 * k3_ * e * e;
    const Mat3 nn = n * n.transpose();
    blocks_[s] = slope * nn + (tension(e) / l) * (Mat3::Identity() - nn);
  }
}

void NonlinearSprings::add_stiffness_times(const Points& dx, Points& out) const {
  for (Eigen::Index s = 0; s < edges_.rows(); ++s) {
    const Vec3 du = row3(dx, edges_(s, 1)) - row3(dx, edges_(s, 0));
    const Vec3 k_du = blocks_[s] * du;
    out.row(edges_(s, 0)) -= k_du.transpose();
    out.row(edges_(s, 1)) += k_du.transpose();
  }
}

void NonlinearSprings::add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const {
  for (Eigen::Index s = 0; s < edges_.rows(); ++s) {
    const int nodes[2] = {edges_(s, 0), edges_(s, 1)};
    for (int a = 0; a < 2; ++a) {
      for (int b = 0; b < 2; ++b) {
        const Real sign = a == b ? 1 : -1;
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) {
            triplets.emplace_back(3 * nodes[a] + i, 3 * nodes[b] + j, sign * blocks_[s](i, j));
          }
        }
      }
    }
  }
}

Real NonlinearSprings::potential_energy(const Points& x) const {
  Real energy = 0;
  for (Eigen::Index s = 0; s < edges_.rows(); ++s) {
    const Real e = (row3(x, edges_(s, 1)) - row3(x, edges_(s, 0))).norm() - rest_lengths_(s);
    energy += 0.5 * k1_ * e * e + 0.25 * k3_ * e * e * e * e;
  }
  return energy;
}

Real total_energy(const Model& model, const Points& x, const Points& v) {
  Real kinetic = 0;
  for (Eigen::Index i = 0; i < v.rows(); ++i)
    kinetic += 0.5 * model.masses()(i) * v.row(i).squaredNorm();
  return kinetic + model.potential_energy(x);
}

}  // namespace incise::sim::testing
