#include "poke_fixture.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>

#include "sim/mesh/box_mesher.h"
#include "sim/models/mass_spring_model.h"
#include "sim/solve/stable_time_step.h"
#include "sim/solve/symplectic_euler.h"

namespace incise::sim::testing {

namespace {

Points gather(const Points& x, const std::vector<int>& nodes) {
  Points out(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t j = 0; j < nodes.size(); ++j) {
    out.row(static_cast<Eigen::Index>(j)) = x.row(nodes[j]);
  }
  return out;
}

using Clock = std::chrono::steady_clock;

Real seconds_since(Clock::time_point start) {
  return std::chrono::duration<Real>(Clock::now() - start).count();
}

}  // namespace

ModelFactory mass_spring_factory(Real damping) {
  return [damping](const TetMesh& mesh) -> std::unique_ptr<Model> {
    ElementMaterial material{kYoungs, 0.3, kDensity, damping};
    return std::make_unique<MassSpringModel>(mesh, std::vector<ElementMaterial>{material});
  };
}

PokeSetup make_poke_setup(const Vec3i& cells) {
  PokeSetup setup;
  const Real edge = 0.1 / cells.x();
  setup.mesh = make_box_mesh(Vec3(0.1, edge * cells.y(), edge * cells.z()), cells);
  const Real top = edge * cells.z();
  const Vec3 centre(0.05, edge * cells.y() / 2, top);
  Real nearest = std::numeric_limits<Real>::infinity();
  for (int i = 0; i < setup.mesh.num_nodes(); ++i) {
    const Vec3 p = row3(setup.mesh.rest, i);
    if (p.z() == 0) setup.fixed.push_back(i);
    if (p.z() == top && (p - centre).norm() < nearest) {
      nearest = (p - centre).norm();
      setup.poked = i;
    }
  }
  setup.dt = stable_time_step(setup.mesh, kYoungs, 0.3, kDensity);
  return setup;
}

std::vector<int> nodes_near(const TetMesh& mesh, int node, Real radius) {
  std::vector<int> near;
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if ((mesh.rest.row(i) - mesh.rest.row(node)).norm() <= radius) near.push_back(i);
  }
  return near;
}

RunRecord full_run(const PokeSetup& setup, int steps, const std::vector<int>& region,
                   const LoadAt& load) {
  const std::unique_ptr<Model> model = mass_spring_factory()(setup.mesh);
  VecX inv_mass = model->masses().cwiseInverse();
  for (const int i : setup.fixed)
    inv_mass(i) = 0;
  Points x = setup.mesh.x, v = setup.mesh.v;
  Points f(x.rows(), 3), external(x.rows(), 3);
  RunRecord record;
  const auto start = Clock::now();
  Real outside = 0;  // time spent recording, not stepping
  for (int s = 0; s < steps; ++s) {
    const auto step_start = Clock::now();
    external.setZero();
    load(s, external);
    f = external;
    model->add_forces(x, v, f);
    symplectic_euler_step(setup.dt, Vec3::Zero(), inv_mass, Prescribed{}, f, x, v);
    const auto record_start = Clock::now();
    record.step_seconds.push_back(std::chrono::duration<Real>(record_start - step_start).count());
    record.region_x.push_back(gather(x, region));
    outside += seconds_since(record_start);
  }
  record.seconds = seconds_since(start) - outside;
  record.final_x = x;
  return record;
}

RunRecord active_run(const PokeSetup& setup, const ActiveRegionSettings& settings, int steps,
                     const std::vector<int>& region, const LoadAt& load) {
  ActiveExplicitStepper stepper(setup.mesh, mass_spring_factory(), settings, setup.fixed);
  Points x = setup.mesh.x, v = setup.mesh.v;
  Points external(x.rows(), 3);
  RunRecord record;
  const auto start = Clock::now();
  Real outside = 0;
  for (int s = 0; s < steps; ++s) {
    const auto step_start = Clock::now();
    external.setZero();
    load(s, external);
    stepper.step(setup.dt, Vec3::Zero(), external, x, v);
    const auto record_start = Clock::now();
    record.step_seconds.push_back(std::chrono::duration<Real>(record_start - step_start).count());
    record.region_x.push_back(gather(x, region));
    record.metrics.push_back(stepper.metrics());
    outside += seconds_since(record_start);
  }
  record.seconds = seconds_since(start) - outside;
  record.final_x = x;
  return record;
}

RegionError region_error(const RunRecord& a, const RunRecord& b, const Points& rest,
                         const std::vector<int>& region) {
  RegionError e;
  for (std::size_t s = 0; s < a.region_x.size() && s < b.region_x.size(); ++s) {
    for (std::size_t j = 0; j < region.size(); ++j) {
      const auto r = static_cast<Eigen::Index>(j);
      e.max_error = std::max(e.max_error, (a.region_x[s].row(r) - b.region_x[s].row(r)).norm());
      e.peak_displacement =
          std::max(e.peak_displacement, (b.region_x[s].row(r) - rest.row(region[j])).norm());
    }
  }
  return e;
}

}  // namespace incise::sim::testing
