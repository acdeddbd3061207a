#pragma once
#include <memory>

#include <cstdint>
#include <span>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "sim/models/model.h"
#include "sim/models/tet_elements.h"

namespace incise::sim {

// The volumetric mass-spring system of MassSpring (sim/models/mass_spring.h; Paloc 2006, eqs. 5-7)
// as a Model, with per-tet materials from tissue labels and an optional volume-preservation term.
// With one material it has MassSpring's masses, springs and forces exactly; with several, the sums
// of eqs. 5 and 6 take each tet's own density and E:
//   m_i  = sum_{tets t at i} density_t V_t / 4
//   k_ij = sum_{tets t at edge ij} E_t V_t / l_ij^2
//   c_ij = d_ij 2 sqrt(k_ij (m_i + m_j)),  d_ij = the V-weighted mean damping of the tets at ij
// Spring energy k/2 (l - l0)^2; stiffness is the exact spring tangent
//   K_s = k (u u^T + (1 - l0 / l) (I - u u^T)),   u = (x_j - x_i) / l,
// (indefinite for a compressed spring), damping D_s = c u u^T (the dashpot acts along u), both at
// the x of the last prepare_stiffness. A spring whose nodes coincide has no direction: no force, no
// stiffness, counted as degenerate.
// Volume preservation (volume_stiffness = s > 0), per tet with signed volume V and rest volume V0:
//   E_v = k_v (V - V0)^2 / (2 V0),   k_v = s E_t [Pa],
// i.e. V0 k_v (J - 1)^2 / 2 with J = V / V0 = det F: P = k_v (J - 1) cof F. It vanishes at rest and
// for any rigid motion, and pushes an inverted tet (V < 0) back to positive volume, which springs
// alone do not (a tet mirrored through a face has all its rest lengths).
// ElementMaterial::poisson_ratio is not used by this model (it is validated all the same).
class MassSpringModel final : public Model {
 public:
  //   mesh              rest positions, tets (positively oriented) and labels
  //   materials         material of tet label l at materials[l]; damping is the fraction d of eq. 7
  //   volume_stiffness  s >= 0 (0: no volume term)
  // Throws std::invalid_argument as make_tet_elements, or for a negative volume_stiffness.
  MassSpringModel(const TetMesh& mesh, std::vector<ElementMaterial> materials,
                  Real volume_stiffness = 0);

  std::string_view name() const override { return "mss"; }
  std::unique_ptr<Model> clone() const override { return std::make_unique<MassSpringModel>(*this); }
  const VecX& masses() const override { return elements_.masses; }
  void add_forces(const Points& x, const Points& v, Points& f) override;
  void prepare_stiffness(const Points& x) override;
  void add_stiffness_times(const Points& dx, Points& out) const override;
  void add_damping_times(const Points& dv, Points& out) const override;
  void add_stiffness_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override;
  void add_damping_triplets(std::vector<Eigen::Triplet<Real>>& triplets) const override;
  Real potential_energy(const Points& x) const override;
  void update_topology(const TetMesh& mesh) override;
  // Local (model.h): only the springs on the edges of the changed tets are re-summed, created or
  // dropped, and the damping of the springs at nodes whose mass changed is recomputed. Dropped
  // springs leave empty slots (spring_alive) that later springs reuse.
  void update_elements(const TetMesh& mesh, const std::vector<char>& alive,
                       std::span<const int> changed) override;
  // Springs only, the tets' share (inverted, degenerate) is counted when asked for, from the
  // positions of the last add_forces: a scene step never asks, and counting every step cost the
  // block at a live station a sixth of its tick.
  ModelHealth health() const override;

  const Edges& springs() const { return springs_; }           // #springs by 2 nodes (i < j)
  const VecX& stiffness() const { return stiffness_; }        // #springs k_ij [N/m]
  const VecX& damping() const { return damping_; }            // #springs c_ij [N s/m]
  const VecX& rest_lengths() const { return rest_lengths_; }  // #springs l_ij [m]
  // #springs: 1 for a spring slot in use (all, until update_elements drops one).
  const std::vector<char>& spring_alive() const { return spring_alive_; }

 private:
  void rebuild(const TetMesh& mesh);
  Mat3 spring_tangent(int s) const;
  // The slot of spring (i, j) (created empty if absent).
  int spring_slot(int i, int j, const Points& rest);
  // What one tet adds to the sums of its six springs.
  struct TetShare {
    int nodes[4];
    Real stiffness_volume, damping_volume, volume;  // E V, d V, V
  };
  TetShare share_of(int t) const;
  // Adds (sign +1) or removes (-1) a tet's share; the springs it reached go to touched.
  void add_tet_share(const TetShare& share, int sign, const Points& rest,
                     std::vector<int>& touched);
  // k and c of spring s from its sums and its nodes' masses.
  void set_spring_constants(int s);

  std::vector<ElementMaterial> materials_;
  Real volume_stiffness_ = 0;
  TetElements elements_;
  Edges springs_;
  VecX stiffness_;
  VecX damping_;
  VecX rest_lengths_;
  // Per spring slot: the sums of eqs. 5-7 over its tets and their number, kept for local updates.
  VecX stiffness_volume_;  // sum E_t V_t
  VecX damping_volume_;    // sum d_t V_t
  VecX volume_;            // sum V_t
  std::vector<int> tet_count_;
  std::vector<char> spring_alive_;
  std::vector<int> free_springs_;
  std::unordered_map<std::uint64_t, int> spring_of_edge_;  // key i << 32 | j, i < j
  std::vector<std::vector<int>> node_springs_;             // per node, its spring slots
  // Linearisation of the last prepare_stiffness.
  Points direction_;               // #springs u (0 for a degenerate spring)
  VecX transverse_;                // #springs k (1 - l0 / l) (0 for a degenerate spring)
  std::vector<Mat3> deformation_;  // #tets F (volume term only)
  // Counts the tets' share of health_ from health_x_ if add_forces left it pending.
  void settle_health() const;
  mutable ModelHealth health_;
  Points health_x_;  // springs only: x of the last add_forces, while its tets are uncounted
  mutable bool health_pending_ = false;
};

}  // namespace incise::sim
