#pragma once
// Runs any scene: the model material.model names, on a mesh the caller built (a box, a
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
// "displace" constraints ramp linearly over the first max(1, steps / 2) steps of a dynamic run
// and are then held. Loads are split equally over their selected nodes.
// A scene with "adaptivity" is run by remesh::run_adaptive_scene (sim/remesh/adaptive_run.h; the
// CLI dispatches), whose RunResult describes the FINAL remeshed mesh: its node and tet counts.
#include <memory>
#include <string>
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
// cannot carry it (e.g. an inverted tet). St Venant-Kirchhoff and Neo-Hookean get the exact
// Hessian as K for the static solve and its positive semi-definite projection for the time
// integrators (projected_tangent.h: implicit Euler's CG needs it; the explicit ones never use K).
std::unique_ptr<Model> make_model(const Scene& scene, const TetMesh& mesh);

// Why a run stopped.
enum class RunStop {
  completed,   // every step taken
  not_finite,  // a position or velocity became NaN or infinite (or a solve failed)
  diverged,    // finite, but the body grew past kDivergedExtent times its rest size
};

// A run whose deformed bounding box has a diagonal above this many times the rest one has blown
// up: no tissue scene stretches a body a hundredfold (a node yanked 5 body lengths away gives
// about 3), and the measure ignores translation (a falling body never trips it) and changes by less
// than a factor 2 under rotation.
inline constexpr Real kDivergedExtent = 100;

// The run's result and how it ended. result.finite is false unless stop is completed, so that
// RESULT.json and the CLI's exit code report a diverged run as failed.
struct CheckedRun {
  RunResult result;
  RunStop stop = RunStop::completed;
  std::string status = "completed";  // else one line: what happened, at which step, the numbers
  Real peak_extent = 1;  // largest deformed bounding-box diagonal over the rest one, over the run
};

// Runs the scene on mesh (whose rest configuration it starts from); after every step, checks that
// the state is finite and that the body has not diverged (above), and stops at the first step that
// fails. result.steps counts the steps before that one; result's final state is the failed one.
// Throws SceneError for selections that pick no node or a mesh the model refuses.
CheckedRun run_scene_checked(const Scene& scene, TetMesh mesh);

// The check after step n (0-based) of a checked run, shared by the runners: with
// checked.result.finite false (a position, velocity or solve became NaN or infinite) or an
// extent (deformed bounding-box diagonal over the rest one) above kDivergedExtent, it sets
// stop, status and finite and returns false; otherwise it records the extent and returns true.
bool continue_checked_run(std::int64_t n, Real extent, CheckedRun& checked);

// run_scene_checked(scene, mesh).result: reports as run_scene.
RunResult run_scene_on(const Scene& scene, TetMesh mesh);

}  // namespace incise::sim
