#include "contact_fixtures.h"

#include <vector>

#include "sim/collide/mesh_surface_faces.h"
#include "sim/mesh/boundary_surface.h"
#include "sim/mesh/box_mesher.h"
#include "sim/models/corotational_fem.h"
#include "sim/solve/stable_time_step.h"

namespace incise::sim::tools::contact_testing {

ContactBlock::ContactBlock(const Vec3& size, const Vec3i& cells, Real youngs, Clamp clamp,
                           Real beta)
    : mesh(make_box_mesh(size, cells)) {
  model = std::make_unique<CorotationalFem>(
      mesh, std::vector<ElementMaterial>{{youngs, kPoisson, kDensity, beta}},
      RotationExtraction::polar);
  inverse_masses = model->masses().cwiseInverse();
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    const Vec3 p = row3(mesh.rest, i);
    const bool held = clamp == Clamp::base
                          ? p.z() == 0
                          : (p.x() == 0 || p.x() == size.x() || p.y() == 0 || p.y() == size.y());
    if (held) inverse_masses[i] = 0;
  }
  faces = collide::mesh_surface_faces(boundary_surface(mesh));
  bvh.build(mesh.x, faces);
  dt = stable_time_step(mesh, youngs, kPoisson, kDensity);
  forces = Points::Zero(mesh.num_nodes(), 3);
}

void ContactBlock::prepare() {
  bvh.refit(mesh.x);
  forces.setZero();
  model->add_forces(mesh.x, mesh.v, forces);
}

void ContactBlock::integrate() {
  symplectic_euler_step(dt, Vec3::Zero(), inverse_masses, prescribed, forces, mesh.x, mesh.v);
}

Real ContactBlock::kinetic_energy() const {
  const VecX& m = model->masses();
  Real sum = 0;
  for (int i = 0; i < mesh.num_nodes(); ++i)
    sum += 0.5 * m[i] * mesh.v.row(i).squaredNorm();
  return sum;
}

Vec3 ContactBlock::support_reaction() const {
  Points internal = Points::Zero(mesh.num_nodes(), 3);
  model->add_forces(mesh.x, Points::Zero(mesh.num_nodes(), 3), internal);
  Vec3 sum = Vec3::Zero();
  for (int i = 0; i < mesh.num_nodes(); ++i) {
    if (inverse_masses[i] == 0) sum -= row3(internal, i);
  }
  return sum;
}

}  // namespace incise::sim::tools::contact_testing
