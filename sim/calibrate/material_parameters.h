#pragma once
// What calibration searches (docs/calibration.md): a scene's material constants as a point z of
// the optimisers' space, and how a point becomes the body's stiffness K and damping D at rest.
//   node moduli      (mass-spring, seed 004) a Young's modulus E_i per node; spring ij takes
//                    the mean of its ends: k_ij = (E_i + E_j) / 2 sum_t V_t / l_ij^2 (eq. 6),
//                    its damper c_ij = d 2 sqrt(k_ij (m_i + m_j)) (eq. 7)
//   label materials  (any model) E per tissue label of the mesh and, for the FEM models, nu:
//                    the scene's model rebuilt with them
// Moduli are searched as z = ln E (positive, and a factor is a step), nu as itself. Densities are
// not calibrated: the masses are the scene's.
// Node moduli are many more than a few probes can see, so their search adds a smoothness prior:
// the residuals sqrt(smoothing) (z_i - z_j) over the springs, which pulls the moduli no probe
// informs towards their neighbours' (Tikhonov on the mesh graph).

#include <memory>
#include <string>
#include <vector>

#include "sim/calibrate/linear_response.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"

namespace incise::sim::calibrate {

enum class ParameterKind { node_moduli, label_materials };

class MaterialParameters {
 public:
  // Node moduli of scene's mass-spring model, each starting at its tets' modulus. Throws
  // CalibrationError when the scene's model is not "mss" or uses a volume term.
  static MaterialParameters node_moduli(const Scene& scene, const TetMesh& mesh, Real smoothing);
  // E (and nu, for the FEM models) of each label the mesh holds, starting at the scene's.
  static MaterialParameters label_materials(const Scene& scene, const TetMesh& mesh);

  ParameterKind kind() const { return kind_; }
  int size() const { return static_cast<int>(names_.size()); }
  // "E[3]" (node or label 3), "nu[1]"
  const std::vector<std::string>& names() const { return names_; }
  bool is_modulus(int i) const { return log_[static_cast<std::size_t>(i)] != 0; }
  const VecX& start() const { return start_; }
  const VecX& lower() const { return lower_; }
  const VecX& upper() const { return upper_; }
  const VecX& masses() const { return masses_; }
  // Springs of the mass-spring model (node moduli; 0 otherwise).
  Eigen::Index spring_count() const { return springs_.rows(); }
  // Node or label of coordinate i.
  int owner(int i) const { return owner_[static_cast<std::size_t>(i)]; }

  // Coordinate i's value in its unit (E [Pa], nu) at z, and back.
  Real value(int i, const VecX& z) const { return is_modulus(i) ? std::exp(z[i]) : z[i]; }
  Real coordinate(int i, Real value) const { return is_modulus(i) ? std::log(value) : value; }

  // K and D at rest for point z, appended to stiffness and damping (cleared first). Returns false
  // when the model refuses the constants (then the point is not evaluable).
  bool assemble(const VecX& z, Triplets& stiffness, Triplets& damping) const;

  // The prior's residuals at z (empty but for node moduli with smoothing > 0).
  int prior_size() const;
  void prior(const VecX& z, Eigen::Ref<VecX> out) const;

  // The scene with z's constants: per label E and nu for label materials; for node moduli each
  // label's mean (what a scene file can hold).
  Scene scene_with(const VecX& z) const;

 private:
  ParameterKind kind_ = ParameterKind::label_materials;
  std::vector<std::string> names_;
  std::vector<char> log_;
  std::vector<int> owner_;
  VecX start_, lower_, upper_, masses_;
  Scene scene_;
  std::shared_ptr<const TetMesh> mesh_;
  // Node moduli: the springs, their sum V / l^2, unit rest direction and the damping fraction.
  Edges springs_;
  VecX spring_volume_;
  Points spring_direction_;
  VecX unit_damping_;  // each spring's c_ij at E = 1: c_ij(E) = unit_damping_ sqrt(E)
  Real smoothing_ = 0;
};

// Bounds of the search: a modulus within this factor of its start either way; nu within these.
inline constexpr Real kModulusRange = 20;
inline constexpr Real kMinPoisson = 0.05;
inline constexpr Real kMaxPoisson = 0.49;

}  // namespace incise::sim::calibrate
