#include "sim/calibrate/cube_experiment.h"

#include <stdexcept>

#include "sim/mesh/box_mesher.h"

namespace incise::sim::calibrate {

CubeExperiment seed004_cube(Real youngs_modulus, int cells) {
  if (cells <= 0 || cells % 2 != 0) {
    throw std::invalid_argument("the cube needs an even number of cells per edge");
  }
  CubeExperiment cube;
  Scene& scene = cube.scene;
  scene.mesh.source = MeshSource::box;
  scene.mesh.box.size = Vec3::Constant(kCubeEdge);
  scene.mesh.box.cells = Vec3i::Constant(cells);
  scene.material.model = MaterialModel::mass_spring;
  scene.material.youngs_modulus = youngs_modulus;
  scene.material.poisson_ratio = 0.3;
  scene.material.density = kCubeDensity;
  scene.material.damping = 0.5;
  Constraint bottom;
  bottom.where.box = Box3(Vec3::Zero(), Vec3(kCubeEdge, kCubeEdge, 0));
  scene.constraints.push_back(bottom);
  scene.solver.integrator = Integrator::implicit_euler;
  scene.solver.dt = kCubePushTime / kCubeSamples;
  scene.solver.steps = kCubeSamples;
  cube.mesh = make_box_mesh(scene.mesh.box.size, scene.mesh.box.cells);

  // The centres of the free faces (all but z = 0) and their inward normals.
  const Real half = kCubeEdge / 2;
  const Vec3 centres[5] = {{half, half, kCubeEdge},
                           {0, half, half},
                           {kCubeEdge, half, half},
                           {half, 0, half},
                           {half, kCubeEdge, half}};
  const Vec3 inward[5] = {-Vec3::UnitZ(), Vec3::UnitX(), -Vec3::UnitX(), Vec3::UnitY(),
                          -Vec3::UnitY()};
  cube.pushes.step = kCubePushTime / kCubeSamples;
  for (int face = 0; face < 5; ++face) {
    ProbeContact contact;
    contact.id = face;
    for (int k = 0; k <= kCubeSamples; ++k) {
      ProbeSample s;
      s.time = k * cube.pushes.step;
      s.position = centres[face];
      s.direction = inward[face];
      s.force = k == 0 ? 0 : kCubeForce;
      contact.samples.push_back(s);
    }
    cube.pushes.contacts.push_back(std::move(contact));
  }
  return cube;
}

}  // namespace incise::sim::calibrate
