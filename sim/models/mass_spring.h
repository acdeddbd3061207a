#pragma once

#include "sim/core/types.h"

namespace incise::sim {

// Material constants of the volumetric mass-spring system.
struct MassSpringMaterial {
  Real youngs_modulus = 0;  // E [Pa], > 0
  Real density = 0;         // D [kg/m^3], > 0
  Real damping = 0;         // fraction of each spring's reference damping (see MassSpring), >= 0
};

// Volumetric mass-spring system on a tet mesh: a mass per node, a spring-damper per unique tet
// edge. Parameters follow Paloc 2006 (section "Physical consistency", after Paloc et al. MICCAI
// 2002), which keeps the global behaviour nearly unchanged when the resolution changes:
//   eq. 5  m_i  = D sum_{tets t at node i} V_t / 4
//   eq. 6  k_ij = E sum_{tets t at edge ij} V_t / l_ij^2
//   eq. 7  c_ij = damping * 2 sqrt(k_ij (m_i + m_j))
// Our reading of eq. 7, which the text extraction garbles to "c_ij = ( 2 k_ij m_i + m_j ) l_ij":
// the bracket is the square root of k_ij (m_i + m_j), and 2 sqrt(k m) is the critical damping of
// an oscillator, as the paper intends. The stray l_ij is not divided by: eq. 3 applies c_ij to a
// velocity, so c_ij must be in N s/m, which 2 sqrt(k_ij (m_i + m_j)) already is; dividing by
// l_ij would make the damping depend on the length unit. With the total mass m_i + m_j in place
// of the pair's reduced mass m_i m_j / (m_i + m_j), damping = 1 is twice the critical damping of
// an isolated spring between equal masses; the scene's "damping" in [0, 1] scales it.
// Rest lengths, stiffness and damping are fixed at construction (rest configuration).
class MassSpring {
 public:
  //   rest  #nodes by 3 rest positions [m]
  //   tets  #tets by 4 node indices, positively oriented at rest
  // Throws std::invalid_argument for a tet with non-positive rest volume or a material constant
  // out of range.
  MassSpring(const Points& rest, const Tets& tets, const MassSpringMaterial& material);

  int num_springs() const { return static_cast<int>(springs_.rows()); }
  const VecX& masses() const { return masses_; }              // #nodes m_i [kg]
  const Edges& springs() const { return springs_; }           // #springs by 2 nodes (i < j)
  const VecX& stiffness() const { return stiffness_; }        // #springs k_ij [N/m]
  const VecX& damping() const { return damping_; }            // #springs c_ij [N s/m]
  const VecX& rest_lengths() const { return rest_lengths_; }  // #springs l_ij [m]

  // Adds the spring and damper forces at positions x and velocities v to f:
  //   x  #nodes by 3 [m];  v  #nodes by 3 [m/s];  f  #nodes by 3 [N], accumulated into
  // Allocates nothing. Returns the number of degenerate springs (coincident nodes) left out.
  int add_forces(const Points& x, const Points& v, Points& f) const;

 private:
  VecX masses_;
  Edges springs_;
  VecX stiffness_;
  VecX damping_;
  VecX rest_lengths_;
};

}  // namespace incise::sim
