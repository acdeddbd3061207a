#include "accuracy_scenes.h"

#include <cmath>
#include <stdexcept>

#include "sim/mesh/box_mesher.h"
#include "tests/sim/closed_forms.h"

namespace incise::bench {
namespace {

using sim::Box3;

constexpr Real kEps = 1e-9;  // selection boxes drawn on a face

sim::Scene soft_tissue_scene() {
  sim::Scene scene;
  scene.material = {sim::MaterialModel::linear, kYoungsModulus, kPoissonRatio, kDensity, 0.0};
  return scene;
}

}  // namespace

sim::Scene compression_scene(Real strain, int cells) {
  sim::Scene scene = soft_tissue_scene();
  const Real l = kBlockSize;
  scene.mesh.box = {Vec3(l, l, l), Vec3i(cells, cells, cells)};
  scene.constraints = {
      {{Box3(Vec3(-kEps, -1, -1), Vec3(kEps, 1, 1))}, {true, false, false}, Vec3::Zero()},
      {{Box3(Vec3(-1, -kEps, -1), Vec3(1, kEps, 1))}, {false, true, false}, Vec3::Zero()},
      {{Box3(Vec3(-1, -1, -kEps), Vec3(1, 1, kEps))}, {false, false, true}, Vec3::Zero()},
      {{Box3(Vec3(-1, -1, l - kEps), Vec3(1, 1, l + kEps))},
       {false, false, true},
       Vec3(0, 0, -strain * l)},
  };
  return scene;
}

sim::Scene cantilever_scene(int n) {
  sim::Scene scene = soft_tissue_scene();
  const Real l = kBeamLength, w = 0.02;
  scene.mesh.box = {Vec3(l, w, w), Vec3i(5 * n, n, n)};
  scene.constraints = {
      {{Box3(Vec3(-kEps, -1, -1), Vec3(kEps, 1, 1))}, {true, true, true}, Vec3::Zero()}};
  scene.loads = {{{Box3(Vec3(l - kEps, -1, -1), Vec3(l + kEps, 1, 1))}, Vec3(0, 0, -kTipLoad)}};
  return scene;
}

sim::TetMesh scene_mesh(const sim::Scene& scene) {
  return sim::make_box_mesh(scene.mesh.box.size, scene.mesh.box.cells);
}

std::optional<Points> compression_closed_form(sim::MaterialModel model, Real strain,
                                              const Points& rest) {
  Real lateral = 0;  // lateral stretch - 1
  if (model == sim::MaterialModel::linear) {
    lateral = kPoissonRatio * strain;
  } else if (model == sim::MaterialModel::neohookean) {
    const auto lame = sim::test::lame_parameters(kYoungsModulus, kPoissonRatio);
    lateral = sim::test::neo_hookean_lateral_stretch(1 - strain, lame.mu, lame.lambda) - 1;
  } else {
    return std::nullopt;
  }
  Points u(rest.rows(), 3);
  u.col(0) = lateral * rest.col(0);
  u.col(1) = lateral * rest.col(1);
  u.col(2) = -strain * rest.col(2);
  return u;
}

Points restrict_to_coarse(const Points& reference, const Vec3i& fine_cells,
                          const Vec3i& coarse_cells) {
  if (fine_cells.x() % coarse_cells.x() != 0 || fine_cells.y() % coarse_cells.y() != 0 ||
      fine_cells.z() % coarse_cells.z() != 0) {
    throw std::invalid_argument("restrict_to_coarse: fine cells are not a multiple of coarse");
  }
  const Vec3i ratio = fine_cells.cwiseQuotient(coarse_cells);
  // Node (i, j, k) of a box grid has index i + (cells.x + 1) (j + (cells.y + 1) k) (box_mesher.h).
  const auto index = [](const Vec3i& cells, int i, int j, int k) {
    return i + (cells.x() + 1) * (j + (cells.y() + 1) * k);
  };
  Points out((coarse_cells.x() + 1) * (coarse_cells.y() + 1) * (coarse_cells.z() + 1), 3);
  for (int k = 0; k <= coarse_cells.z(); ++k) {
    for (int j = 0; j <= coarse_cells.y(); ++j) {
      for (int i = 0; i <= coarse_cells.x(); ++i) {
        out.row(index(coarse_cells, i, j, k)) =
            reference.row(index(fine_cells, i * ratio.x(), j * ratio.y(), k * ratio.z()));
      }
    }
  }
  return out;
}

Real relative_error(const Points& u, const Points& reference) {
  const Real scale = reference.rowwise().norm().maxCoeff();
  return (u - reference).rowwise().norm().maxCoeff() / scale;
}

std::string model_name(sim::MaterialModel model) {
  switch (model) {
    case sim::MaterialModel::mass_spring:
      return "mss";
    case sim::MaterialModel::linear:
      return "linear";
    case sim::MaterialModel::corotational:
      return "corotational";
    case sim::MaterialModel::corotational_polar:
      return "corotational_polar";
    case sim::MaterialModel::corotational_nodal_pressure:
      return "corotational_nodal_pressure";
    case sim::MaterialModel::stvk:
      return "stvk";
    case sim::MaterialModel::neohookean:
      return "neohookean";
  }
  return "?";
}

std::string integrator_name(sim::Integrator integrator) {
  switch (integrator) {
    case sim::Integrator::symplectic_euler:
      return "symplectic_euler";
    case sim::Integrator::central_difference:
      return "central_difference";
    case sim::Integrator::adaptive_explicit:
      return "adaptive_explicit";
    case sim::Integrator::implicit_euler:
      return "implicit_euler";
    case sim::Integrator::static_equilibrium:
      return "static";
  }
  return "?";
}

}  // namespace incise::bench
