#include "sim/calibrate/material_parameters.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <map>

#include "sim/models/mass_spring_model.h"
#include "sim/scene/scene_run.h"

namespace incise::sim::calibrate {
namespace {

std::string indexed(const char* name, int i) {
  return std::string(name) + "[" + std::to_string(i) + "]";
}

// K's four 3x3 blocks of a two-node element k u u^T (and likewise D's).
void add_spring(int i, int j, const Vec3& u, Real k, Triplets& out) {
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) {
      const Real value = k * u[a] * u[b];
      out.emplace_back(3 * i + a, 3 * i + b, value);
      out.emplace_back(3 * j + a, 3 * j + b, value);
      out.emplace_back(3 * i + a, 3 * j + b, -value);
      out.emplace_back(3 * j + a, 3 * i + b, -value);
    }
  }
}

}  // namespace

MaterialParameters MaterialParameters::node_moduli(const Scene& scene, const TetMesh& mesh,
                                                   Real smoothing) {
  if (scene.material.model != MaterialModel::mass_spring) {
    throw CalibrationError(
        "per-node moduli are the mass-spring model's (seed 004); this scene's model takes its "
        "constants per label");
  }
  if (scene.material.volume_stiffness > 0) {
    throw CalibrationError(
        "per-node moduli calibrate the springs only, and this scene adds a volume term "
        "(material.volume_stiffness); calibrate per label instead");
  }
  MaterialParameters p;
  p.kind_ = ParameterKind::node_moduli;
  p.scene_ = scene;
  p.mesh_ = std::make_shared<const TetMesh>(mesh);
  p.smoothing_ = smoothing;
  std::vector<ElementMaterial> materials = element_materials(scene, mesh);
  std::vector<ElementMaterial> unit = materials;
  for (auto& m : unit)
    m.youngs_modulus = 1;
  const MassSpringModel model(mesh, unit);
  p.masses_ = model.masses();
  p.springs_ = model.springs();
  p.spring_volume_ = model.stiffness();  // sum V / l^2 with E = 1
  p.spring_direction_.resize(p.springs_.rows(), 3);
  for (Eigen::Index s = 0; s < p.springs_.rows(); ++s) {
    const Vec3 d = row3(mesh.rest, p.springs_(s, 1)) - row3(mesh.rest, p.springs_(s, 0));
    p.spring_direction_.row(s) = d.normalized().transpose();
  }
  const VecX volumes = tet_volumes(mesh.rest, mesh.tets);
  VecX weighted = VecX::Zero(mesh.num_nodes());
  VecX volume = VecX::Zero(mesh.num_nodes());
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const int label = mesh.labels.size() > 0 ? mesh.labels[t] : 0;
    const Real e = materials[static_cast<std::size_t>(label)].youngs_modulus;
    for (int c = 0; c < 4; ++c) {
      weighted[mesh.tets(t, c)] += e * volumes[t];
      volume[mesh.tets(t, c)] += volumes[t];
    }
  }
  p.start_.resize(mesh.num_nodes());
  p.lower_.resize(mesh.num_nodes());
  p.upper_.resize(mesh.num_nodes());
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Real e = volume[i] > 0 ? weighted[i] / volume[i] : scene.material.youngs_modulus;
    p.names_.push_back(indexed("E", i));
    p.log_.push_back(1);
    p.owner_.push_back(i);
    p.start_[i] = std::log(e);
    p.lower_[i] = std::log(e / kModulusRange);
    p.upper_[i] = std::log(e * kModulusRange);
  }
  // c_ij = d 2 sqrt(k_ij (m_i + m_j)) = (the unit model's c_ij) sqrt(E_ij).
  p.unit_damping_ = model.damping();
  return p;
}

MaterialParameters MaterialParameters::label_materials(const Scene& scene, const TetMesh& mesh) {
  MaterialParameters p;
  p.kind_ = ParameterKind::label_materials;
  p.scene_ = scene;
  p.mesh_ = std::make_shared<const TetMesh>(mesh);
  std::vector<char> present(1, 0);
  for (int t = 0; t < mesh.num_tets(); ++t) {
    const int label = mesh.labels.size() > 0 ? mesh.labels[t] : 0;
    if (label >= static_cast<int>(present.size())) present.resize(label + 1, 0);
    present[static_cast<std::size_t>(label)] = 1;
  }
  std::vector<Real> start, lower, upper;
  const bool fem = scene.material.model != MaterialModel::mass_spring;
  for (int label = 0; label < static_cast<int>(present.size()); ++label) {
    if (!present[static_cast<std::size_t>(label)]) continue;
    const auto found = scene.materials_by_label.find(label);
    const Material& m = found != scene.materials_by_label.end() ? found->second : scene.material;
    p.names_.push_back(indexed("E", label));
    p.log_.push_back(1);
    p.owner_.push_back(label);
    start.push_back(std::log(m.youngs_modulus));
    lower.push_back(std::log(m.youngs_modulus / kModulusRange));
    upper.push_back(std::log(m.youngs_modulus * kModulusRange));
    if (fem) {
      p.names_.push_back(indexed("nu", label));
      p.log_.push_back(0);
      p.owner_.push_back(label);
      start.push_back(std::clamp(m.poisson_ratio, kMinPoisson, kMaxPoisson));
      lower.push_back(kMinPoisson);
      upper.push_back(kMaxPoisson);
    }
  }
  p.start_ = Eigen::Map<const VecX>(start.data(), static_cast<Eigen::Index>(start.size()));
  p.lower_ = Eigen::Map<const VecX>(lower.data(), static_cast<Eigen::Index>(lower.size()));
  p.upper_ = Eigen::Map<const VecX>(upper.data(), static_cast<Eigen::Index>(upper.size()));
  p.masses_ = make_model(scene, mesh)->masses();
  return p;
}

bool MaterialParameters::assemble(const VecX& z, Triplets& stiffness, Triplets& damping) const {
  stiffness.clear();
  damping.clear();
  if (!z.allFinite()) return false;
  if (kind_ == ParameterKind::node_moduli) {
    for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
      const int i = springs_(s, 0);
      const int j = springs_(s, 1);
      const Real e = 0.5 * (std::exp(z[i]) + std::exp(z[j]));
      const Vec3 u = row3(spring_direction_, static_cast<int>(s));
      add_spring(i, j, u, e * spring_volume_[s], stiffness);
      add_spring(i, j, u, unit_damping_[s] * std::sqrt(e), damping);
    }
    return true;
  }
  try {
    const std::unique_ptr<Model> model = make_model(scene_with(z), *mesh_);
    model->prepare_stiffness(mesh_->rest);
    model->add_stiffness_triplets(stiffness);
    model->add_damping_triplets(damping);
    return true;
  } catch (const std::exception&) {
    return false;  // constants the model refuses: not evaluable
  }
}

int MaterialParameters::prior_size() const {
  return kind_ == ParameterKind::node_moduli && smoothing_ > 0 ? static_cast<int>(springs_.rows())
                                                               : 0;
}

void MaterialParameters::prior(const VecX& z, Eigen::Ref<VecX> out) const {
  if (prior_size() == 0) return;
  const Real weight = std::sqrt(smoothing_);
  for (Eigen::Index s = 0; s < springs_.rows(); ++s) {
    out[s] = weight * (z[springs_(s, 0)] - z[springs_(s, 1)]);
  }
}

Scene MaterialParameters::scene_with(const VecX& z) const {
  Scene scene = scene_;
  const auto material_of = [&](int label) -> Material& {
    auto found = scene.materials_by_label.find(label);
    if (found == scene.materials_by_label.end()) {
      found = scene.materials_by_label.emplace(label, scene.material).first;
    }
    return found->second;
  };
  if (kind_ == ParameterKind::label_materials) {
    for (int i = 0; i < size(); ++i) {
      Material& m = material_of(owner(i));
      (is_modulus(i) ? m.youngs_modulus : m.poisson_ratio) = value(i, z);
      if (owner(i) == 0) {
        (is_modulus(i) ? scene.material.youngs_modulus : scene.material.poisson_ratio) =
            value(i, z);
      }
    }
    return scene;
  }
  // Node moduli: each label's volume-weighted mean of its tets' mean node modulus.
  const VecX volumes = tet_volumes(mesh_->rest, mesh_->tets);
  std::map<int, std::pair<Real, Real>> sums;  // label: sum E V, sum V
  for (int t = 0; t < mesh_->num_tets(); ++t) {
    Real e = 0;
    for (int c = 0; c < 4; ++c)
      e += std::exp(z[mesh_->tets(t, c)]) / 4;
    auto& [ev, v] = sums[mesh_->labels.size() > 0 ? mesh_->labels[t] : 0];
    ev += e * volumes[t];
    v += volumes[t];
  }
  for (const auto& [label, sum] : sums) {
    material_of(label).youngs_modulus = sum.first / sum.second;
    if (label == 0) scene.material.youngs_modulus = sum.first / sum.second;
  }
  return scene;
}

}  // namespace incise::sim::calibrate
