#pragma once
// Runs any scene (issue 4): the model material.model names, on a mesh the caller built (a box, a
// .msh or TetGen file, or a generated one: sim/io and the CLI do that, since reading files and
// CGAL are not this layer's business), stepped by the integrator solver.integrator names.
//
//   symplectic_euler, central_difference   solver.steps steps of solver.dt
//   adaptive_explicit                      solver.steps intervals of solver.dt, each advanced in
//                                          as many error-controlled steps as it needs
//   implicit_euler                         solver.steps linearised backward Euler steps, CG to
//                                          solver.tolerance
//   static                                 the equilibrium, in solver.steps load increments (loads,
//                                          gravity and "displace" constraints grow linearly to
//                                          their full value); Newton to solver.tolerance
// "displace" constraints ramp over the first half of the steps of a dynamic run, as in
// Simulation. Loads are split equally over their selected nodes.
#include <memory>
#include <vector>

#include "sim/mesh/tet_mesh.h"
#include "sim/models/model.h"
#include "sim/scene/run_scene.h"
#include "sim/scene/scene.h"

namespace incise::sim {

// The per-label constants the models take: materials[l] for tet label l (scene.materials_by_label
// where given, else scene.material). "damping" is a fraction of a reference damping: for the
// mass-spring model as in mass_spring.h (eq. 7), for the FEM models a Kelvin-Voigt viscosity
// beta = damping * l_min / c [s] (l_min the smallest tet altitude, c the P-wave speed).
std::vector<ElementMaterial> element_materials(const Scene& scene, const TetMesh& mesh);

// The model scene.material.model names, on mesh. Throws SceneError("mesh", ...) if the mesh
// cannot carry it (e.g. an inverted tet).
std::unique_ptr<Model> make_model(const Scene& scene, const TetMesh& mesh);

// Runs the scene on mesh (whose rest configuration it starts from) and reports as run_scene.
// Throws SceneError for selections that pick no node or a mesh the model refuses.
RunResult run_scene_on(const Scene& scene, TetMesh mesh);

}  // namespace incise::sim
