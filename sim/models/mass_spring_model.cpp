#include "sim/models/mass_spring_model.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "sim/mesh/tet_adjacency.h"
#include "sim/models/cofactor.h"
#include "sim/models/lanes.h"
#include "sim/models/spring_force.h"

namespace incise::sim {

namespace {

using namespace lanes;

struct SpringView {
  int count = 0;
  const int* ends = nullptr;  // 2 per spring: i, j
  const Real* stiffness = nullptr;
  const Real* damping = nullptr;
  const Real* rest_length = nullptr;
  const char* alive = nullptr;
};

// f += the spring-damper forces of every live spring at positions x and velocities v (#nodes by
// 3): spring_force.h, four springs to a SIMD register (their ends gathered as (x, y, z, 0) points
// and transposed into lanes, their forces transposed back), the last count % 4 one by one.
// Returns how many live springs were degenerate (no direction, no force). Compiled for
// x86-64-v3 (AVX2) and the baseline, picked at load time as corotational_batch.cpp's kernels.
[[gnu::target_clones("arch=x86-64-v3", "default")]] int spring_forces(const SpringView& s,
                                                                      const Real* x, const Real* v,
                                                                      Real* f) {
  int degenerate = 0;
  const int whole = s.count / kLaneWidth * kLaneWidth;
  for (int base = 0; base < whole; base += kLaneWidth) {
    int i[4], j[4];
    Lanes r_of[4], w_of[4];  // per spring: x_j - x_i, v_j - v_i
    LaneMask alive;
    for (int l = 0; l < 4; ++l) {
      // A dead spring's ends may name nodes that no longer exist: it reads node 0 instead.
      const bool live = s.alive[base + l] != 0;
      i[l] = live ? s.ends[2 * (base + l)] : 0;
      j[l] = live ? s.ends[2 * (base + l) + 1] : 0;
      alive[l] = live ? -1 : 0;
      r_of[l] = point_at(x + 3 * j[l]) - point_at(x + 3 * i[l]);
      w_of[l] = point_at(v + 3 * j[l]) - point_at(v + 3 * i[l]);
    }
    Lanes r[4], w[4];
    transpose(r_of[0], r_of[1], r_of[2], r_of[3], r);
    transpose(w_of[0], w_of[1], w_of[2], w_of[3], w);
    const Lanes length = lanes_sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    const Lanes rest = load(s.rest_length + base);
    // As spring_force: below 1e-12 of the rest length the direction is round-off.
    const LaneMask directed = alive & (length > Real(1e-12) * rest);
    degenerate += count(alive & ~directed);
    const Lanes inverse = select(directed, 1 / length, splat(0));
    const Lanes u0 = r[0] * inverse, u1 = r[1] * inverse, u2 = r[2] * inverse;
    const Lanes tension = load(s.stiffness + base) * (length - rest) +
                          load(s.damping + base) * (w[0] * u0 + w[1] * u1 + w[2] * u2);
    Lanes on_i[4];
    transpose(tension * u0, tension * u1, tension * u2, splat(0), on_i);
    for (int l = 0; l < 4; ++l) {
      if (!directed[l]) continue;
      add_point(f + 3 * i[l], on_i[l]);
      add_point(f + 3 * j[l], -on_i[l]);
    }
  }
  for (int k = whole; k < s.count; ++k) {
    if (s.alive[k] == 0) continue;
    const Real* xi = x + 3 * s.ends[2 * k];
    const Real* xj = x + 3 * s.ends[2 * k + 1];
    const Real* vi = v + 3 * s.ends[2 * k];
    const Real* vj = v + 3 * s.ends[2 * k + 1];
    const SpringForce force = spring_force(Vec3(xi[0], xi[1], xi[2]), Vec3(xj[0], xj[1], xj[2]),
                                           Vec3(vi[0], vi[1], vi[2]), Vec3(vj[0], vj[1], vj[2]),
                                           s.stiffness[k], s.damping[k], s.rest_length[k]);
    degenerate += force.degenerate ? 1 : 0;
    for (int c = 0; c < 3; ++c) {
      f[3 * s.ends[2 * k] + c] += force.on_i[c];
      f[3 * s.ends[2 * k + 1] + c] -= force.on_i[c];
    }
  }
  return degenerate;
}

// dP of the volume term P = k_v (J - 1) cof F.
Mat3 volume_stress_differential(const Mat3& f, const Mat3& df, Real k_v) {
  const Mat3 c = cofactor(f);
  return k_v *
         (c.cwiseProduct(df).sum() * c + (f.determinant() - 1) * cofactor_differential(f, df));
}

// The springs-only health of every live tet (no volume term, so F is never formed): inverted
// where det Ds <= 0, degenerate where |det Ds| < 6e-6 V0 (J = det Ds / (6 V0)), four tets to a
// register as spring_forces' springs.
[[gnu::target_clones("arch=x86-64-v3", "default")]] ModelHealth tet_health(
    int count_tets, const int* tets, const Real* rest_volume, const char* alive, const Real* x) {
  ModelHealth health;
  const auto determinant = [](const Lanes(&d)[3][4]) {  // d[column k][row i]
    return d[0][0] * (d[1][1] * d[2][2] - d[2][1] * d[1][2]) -
           d[1][0] * (d[0][1] * d[2][2] - d[2][1] * d[0][2]) +
           d[2][0] * (d[0][1] * d[1][2] - d[1][1] * d[0][2]);
  };
  const int whole = count_tets / kLaneWidth * kLaneWidth;
  for (int base = 0; base < whole; base += kLaneWidth) {
    int node[4][4];
    LaneMask live;
    for (int l = 0; l < 4; ++l) {
      // A dead slot's nodes may no longer exist: it reads node 0 instead.
      const bool is_live = alive[base + l] != 0;
      live[l] = is_live ? -1 : 0;
      const int* n = tets + 4 * (base + l);
      for (int c = 0; c < 4; ++c)
        node[l][c] = is_live ? n[c] : 0;
    }
    Lanes ds[3][4];  // [k][i]: Ds(i, k) of the four tets
    edge_lanes(x, node, ds);
    const Lanes det = determinant(ds);
    const Lanes abs_det = select(det < 0, -det, det);
    health.inverted_elements += count(live & (det <= 0));
    health.degenerate_elements += count(live & (abs_det < Real(6e-6) * load(rest_volume + base)));
  }
  for (int t = whole; t < count_tets; ++t) {
    if (alive[t] == 0) continue;
    const int* n = tets + 4 * t;
    Mat3 ds;
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i)
        ds(i, k) = x[3 * n[k + 1] + i] - x[3 * n[0] + i];
    const Real det = ds.determinant();
    health.inverted_elements += det <= 0 ? 1 : 0;
    health.degenerate_elements += std::abs(det) < Real(6e-6) * rest_volume[t] ? 1 : 0;
  }
  return health;
}

}  // namespace

MassSpringModel::MassSpringModel(const TetMesh& mesh, std::vector<ElementMaterial> materials,
                                 Real volume_stiffness)
    : materials_(std::move(materials)), volume_stiffness_(volume_stiffness) {
  if (!(volume_stiffness >= 0)) {
    throw std::invalid_argument("mass-spring volume_stiffness must be >= 0, got " +
                                std::to_string(volume_stiffness));
  }
  rebuild(mesh);
}

void MassSpringModel::update_topology(const TetMesh& mesh) {
  rebuild(mesh);
  topology_changed();
}

void MassSpringModel::rebuild(const TetMesh& mesh) {
  elements_ = make_tet_elements(mesh, materials_);
  springs_ = unique_edges(elements_.tets);
  const TetEdgeIndices tet_springs = tet_edge_indices(elements_.tets, springs_);
  const Eigen::Index num_springs = springs_.rows();
  stiffness_volume_ = VecX::Zero(num_springs);
  damping_volume_ = VecX::Zero(num_springs);
  volume_ = VecX::Zero(num_springs);
  tet_count_.assign(static_cast<std::size_t>(num_springs), 0);
  for (int t = 0; t < elements_.num_tets(); ++t) {
    for (int e = 0; e < 6; ++e) {
      const int s = tet_springs(t, e);
      stiffness_volume_(s) += elements_.youngs_modulus(t) * elements_.rest_volume(t);
      damping_volume_(s) += elements_.damping(t) * elements_.rest_volume(t);
      volume_(s) += elements_.rest_volume(t);
      ++tet_count_[static_cast<std::size_t>(s)];
    }
  }
  rest_lengths_.resize(num_springs);
  stiffness_.resize(num_springs);
  damping_.resize(num_springs);
  spring_alive_.assign(static_cast<std::size_t>(num_springs), 1);
  free_springs_.clear();
  spring_of_edge_.clear();
  node_springs_.assign(static_cast<std::size_t>(mesh.num_nodes()), {});
  for (Eigen::Index s = 0; s < num_springs; ++s) {
    const int i = springs_(s, 0);
    const int j = springs_(s, 1);
    rest_lengths_(s) = (mesh.rest.row(j) - mesh.rest.row(i)).norm();
    set_spring_constants(static_cast<int>(s));
    spring_of_edge_[(static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j)] =
        static_cast<int>(s);
    node_springs_[static_cast<std::size_t>(i)].push_back(static_cast<int>(s));
    node_springs_[static_cast<std::size_t>(j)].push_back(static_cast<int>(s));
  }
  direction_.resize(num_springs, 3);
  transverse_.resize(num_springs);
  deformation_.assign(volume_stiffness_ > 0 ? static_cast<std::size_t>(elements_.num_tets()) : 0,
                      Mat3::Identity());
  prepare_stiffness(mesh.rest);
  health_ = {};
  health_pending_ = false;
}

void MassSpringModel::set_spring_constants(int s) {
  const int i = springs_(s, 0);
  const int j = springs_(s, 1);
  const Real length = rest_lengths_(s);
  stiffness_(s) = stiffness_volume_(s) / (length * length);
  damping_(s) = damping_volume_(s) / volume_(s) * 2 *
                std::sqrt(stiffness_(s) * (elements_.masses(i) + elements_.masses(j)));
}

int MassSpringModel::spring_slot(int i, int j, const Points& rest) {
  if (i > j) std::swap(i, j);
  const std::uint64_t key = (static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j);
  const auto found = spring_of_edge_.find(key);
  if (found != spring_of_edge_.end()) return found->second;
  int s;
  if (!free_springs_.empty()) {
    s = free_springs_.back();
    free_springs_.pop_back();
  } else {
    s = static_cast<int>(springs_.rows());
    const Eigen::Index slots = s + 1;
    springs_.conservativeResize(slots, 2);
    for (VecX* v : {&rest_lengths_, &stiffness_, &damping_, &stiffness_volume_, &damping_volume_,
                    &volume_, &transverse_}) {
      v->conservativeResize(slots);
    }
    direction_.conservativeResize(slots, 3);
    tet_count_.push_back(0);
    spring_alive_.push_back(0);
  }
  springs_(s, 0) = i;
  springs_(s, 1) = j;
  rest_lengths_(s) = (rest.row(j) - rest.row(i)).norm();
  stiffness_volume_(s) = damping_volume_(s) = volume_(s) = 0;
  stiffness_(s) = damping_(s) = transverse_(s) = 0;
  direction_.row(s).setZero();
  tet_count_[static_cast<std::size_t>(s)] = 0;
  spring_alive_[static_cast<std::size_t>(s)] = 1;
  spring_of_edge_[key] = s;
  if (node_springs_.size() < static_cast<std::size_t>(j) + 1) node_springs_.resize(j + 1);
  node_springs_[static_cast<std::size_t>(i)].push_back(s);
  node_springs_[static_cast<std::size_t>(j)].push_back(s);
  return s;
}

void MassSpringModel::add_tet_share(const TetShare& share, int sign, const Points& rest,
                                    std::vector<int>& touched) {
  static constexpr int kEdges[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (const auto& edge : kEdges) {
    const int s = spring_slot(share.nodes[edge[0]], share.nodes[edge[1]], rest);
    stiffness_volume_(s) += sign * share.stiffness_volume;
    damping_volume_(s) += sign * share.damping_volume;
    volume_(s) += sign * share.volume;
    tet_count_[static_cast<std::size_t>(s)] += sign;
    touched.push_back(s);
  }
}

MassSpringModel::TetShare MassSpringModel::share_of(int t) const {
  const Real v = elements_.rest_volume(t);
  return {{elements_.tets(t, 0), elements_.tets(t, 1), elements_.tets(t, 2), elements_.tets(t, 3)},
          elements_.youngs_modulus(t) * v,
          elements_.damping(t) * v,
          v};
}

void MassSpringModel::update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                                      std::span<const int> changed) {
  settle_health();  // with the tets the last add_forces saw
  // The leaving tets' shares, taken before update_tet_elements overwrites their slots (it checks
  // every new tet first and throws with nothing changed).
  std::vector<TetShare> leaving;
  for (const int t : changed) {
    if (t >= 0 && t < elements_.num_tets() && elements_.alive(t)) leaving.push_back(share_of(t));
  }
  update_tet_elements(elements_, mesh, alive, changed, materials_);
  std::vector<int> touched;
  for (const TetShare& share : leaving)
    add_tet_share(share, -1, mesh.rest, touched);
  for (const int t : changed) {
    if (elements_.alive(t)) add_tet_share(share_of(t), +1, mesh.rest, touched);
  }
  // Springs no tet holds any more are dropped; the others get new constants, and so does every
  // spring at a node whose mass changed (its damping depends on the masses).
  std::vector<int> nodes;
  for (const int s : touched) {
    const std::size_t ss = static_cast<std::size_t>(s);
    if (!spring_alive_[ss]) continue;
    const int i = springs_(s, 0);
    const int j = springs_(s, 1);
    nodes.push_back(i);
    nodes.push_back(j);
    if (tet_count_[ss] > 0) continue;
    spring_alive_[ss] = 0;
    free_springs_.push_back(s);
    spring_of_edge_.erase((static_cast<std::uint64_t>(i) << 32) | static_cast<std::uint32_t>(j));
    for (const int node : {i, j}) {
      auto& list = node_springs_[static_cast<std::size_t>(node)];
      list.erase(std::find(list.begin(), list.end(), s));
    }
  }
  // Each node once: a node is at the end of many touched springs.
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  for (const int node : nodes) {
    for (const int s : node_springs_[static_cast<std::size_t>(node)])
      set_spring_constants(s);
  }
  if (volume_stiffness_ > 0) {
    deformation_.resize(static_cast<std::size_t>(elements_.num_tets()), Mat3::Identity());
  }
  topology_changed();
}

namespace {

void count_health(Real j, ModelHealth& health) {
  health.inverted_elements += j <= 0 ? 1 : 0;
  health.degenerate_elements += std::abs(j) < 1e-6 ? 1 : 0;
}

}  // namespace

void MassSpringModel::add_forces(const Points& x, const Points& v, Points& f) {
  ModelHealth health;
  health_pending_ = false;
  const SpringView springs{static_cast<int>(springs_.rows()),
                           springs_.data(),
                           stiffness_.data(),
                           damping_.data(),
                           rest_lengths_.data(),
                           spring_alive_.data()};
  health.degenerate_elements += spring_forces(springs, x.data(), v.data(), f.data());
  if (volume_stiffness_ > 0) {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
      const Mat3 deformation =
          edge_matrix(x, elements_.tets, t) * elements_.rest_inverse[static_cast<std::size_t>(t)];
      const Real j = deformation.determinant();
      count_health(j, health);
      const Real k_v = volume_stiffness_ * elements_.youngs_modulus(t);
      scatter_stress(elements_, t, k_v * (j - 1) * cofactor(deformation), f);
    }
  } else {
    // Springs only: the tets' health when asked for (health()).
    health_x_ = x;  // no allocation while the node count stays
    health_pending_ = true;
  }
  health_ = health;
}

void MassSpringModel::settle_health() const {
  if (!health_pending_) return;
  health_pending_ = false;
  const ModelHealth tets =
      tet_health(elements_.num_tets(), elements_.tets.data(), elements_.rest_volume.data(),
                 elements_.alive_slots.data(), health_x_.data());
  health_.inverted_elements += tets.inverted_elements;
  health_.degenerate_elements += tets.degenerate_elements;
}

ModelHealth MassSpringModel::health() const {
  settle_health();
  return health_;
}

void MassSpringModel::prepare_stiffness(const Points& x) {
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    if (!spring_alive_[static_cast<std::size_t>(s)]) continue;
    const Vec3 r = row3(x, springs_(s, 1)) - row3(x, springs_(s, 0));
    const Real length = r.norm();
    // As spring_force: below 1e-12 of the rest length the direction is round-off.
    if (length > Real(1e-12) * rest_lengths_(s)) {
      direction_.row(s) = r.transpose() / length;
      transverse_(s) = stiffness_(s) * (1 - rest_lengths_(s) / length);
    } else {
      direction_.row(s).setZero();
      transverse_(s) = 0;
    }
  }
  for (std::size_t t = 0; t < deformation_.size(); ++t) {
    if (!elements_.alive(static_cast<int>(t))) continue;
    deformation_[t] =
        edge_matrix(x, elements_.tets, static_cast<int>(t)) * elements_.rest_inverse[t];
  }
}

Mat3 MassSpringModel::spring_tangent(int s) const {
  const Vec3 u = direction_.row(s).transpose();
  const Mat3 along = u * u.transpose();
  // K_s = k u u^T + t (I - u u^T); a degenerate spring has u = 0 and t = 0: no stiffness.
  return (stiffness_(s) - transverse_(s)) * along + transverse_(s) * Mat3::Identity();
}

void MassSpringModel::add_stiffness_times(const Points& dx, Points& out) const {
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    if (!spring_alive_[static_cast<std::size_t>(s)]) continue;
    const int i = springs_(s, 0);
    const int j = springs_(s, 1);
    const Vec3 k_dx = spring_tangent(static_cast<int>(s)) * (row3(dx, i) - row3(dx, j));
    out.row(i) += k_dx.transpose();
    out.row(j) -= k_dx.transpose();
  }
  for (std::size_t t = 0; t < deformation_.size(); ++t) {
    if (!elements_.alive(static_cast<int>(t))) continue;
    const int ti = static_cast<int>(t);
    const Mat3& f = deformation_[t];
    const Mat3 df = edge_matrix(dx, elements_.tets, ti) * elements_.rest_inverse[t];
    const Real k_v = volume_stiffness_ * elements_.youngs_modulus(ti);
    const Mat3 dp = volume_stress_differential(f, df, k_v);
    scatter_stress(elements_, ti, -dp, out);
  }
}

void MassSpringModel::add_damping_times(const Points& dv, Points& out) const {
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    if (!spring_alive_[static_cast<std::size_t>(s)]) continue;
    const int i = springs_(s, 0);
    const int j = springs_(s, 1);
    const Vec3 u = direction_.row(s).transpose();
    const Vec3 d_dv = damping_(s) * u.dot(row3(dv, i) - row3(dv, j)) * u;
    out.row(i) += d_dv.transpose();
    out.row(j) -= d_dv.transpose();
  }
}

namespace {

// The triplets of a two-node element with matrix [b, -b; -b, b] on nodes i and j.
void add_pair_triplets(int i, int j, const Mat3& b, std::vector<Eigen::Triplet<Real>>& triplets) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      triplets.emplace_back(3 * i + r, 3 * i + c, b(r, c));
      triplets.emplace_back(3 * j + r, 3 * j + c, b(r, c));
      triplets.emplace_back(3 * i + r, 3 * j + c, -b(r, c));
      triplets.emplace_back(3 * j + r, 3 * i + c, -b(r, c));
    }
  }
}

}  // namespace

void MassSpringModel::add_damping_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const {
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    if (!spring_alive_[static_cast<std::size_t>(s)]) continue;
    const Vec3 u = direction_.row(s).transpose();
    // The dashpot acts along the spring.
    add_pair_triplets(springs_(s, 0), springs_(s, 1), damping_(s) * u * u.transpose(), triplets);
  }
}

void MassSpringModel::add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const {
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    if (!spring_alive_[static_cast<std::size_t>(s)]) continue;
    add_pair_triplets(springs_(s, 0), springs_(s, 1), spring_tangent(static_cast<int>(s)),
                      triplets);
  }
  // The volume term column by column: node a moved along c, dF = e_c g_a^T.
  for (std::size_t t = 0; t < deformation_.size(); ++t) {
    if (!elements_.alive(static_cast<int>(t))) continue;
    const int ti = static_cast<int>(t);
    Eigen::Matrix<Real, 3, 4> g;
    g.rightCols<3>() = elements_.rest_inverse[t].transpose();
    g.col(0) = -g.rightCols<3>().rowwise().sum();
    const Mat3& f = deformation_[t];
    const Real k_v = volume_stiffness_ * elements_.youngs_modulus(ti);
    for (int a = 0; a < 4; ++a) {
      for (int c = 0; c < 3; ++c) {
        Mat3 df = Mat3::Zero();
        df.row(c) = g.col(a).transpose();
        const Mat3 dp = volume_stress_differential(f, df, k_v);
        for (int b = 0; b < 4; ++b) {
          const Vec3 block = elements_.rest_volume(ti) * dp * g.col(b);
          for (int r = 0; r < 3; ++r)
            triplets.emplace_back(3 * elements_.tets(ti, b) + r, 3 * elements_.tets(ti, a) + c,
                                  block(r));
        }
      }
    }
  }
}

Real MassSpringModel::potential_energy(const Points& x) const {
  Real energy = 0;
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    if (!spring_alive_[static_cast<std::size_t>(s)]) continue;
    const Real stretch = (x.row(springs_(s, 1)) - x.row(springs_(s, 0))).norm() - rest_lengths_(s);
    energy += stiffness_(s) / 2 * stretch * stretch;
  }
  if (volume_stiffness_ > 0) {
    for (int t = 0; t < elements_.num_tets(); ++t) {
      if (!elements_.alive(t)) continue;
      const Real j =
          (edge_matrix(x, elements_.tets, t) * elements_.rest_inverse[static_cast<std::size_t>(t)])
              .determinant();
      energy += volume_stiffness_ * elements_.youngs_modulus(t) * elements_.rest_volume(t) *
                (j - 1) * (j - 1) / 2;
    }
  }
  return energy;
}

}  // namespace incise::sim
