#pragma once
// The converged reference of the accuracy benchmark: a scene's static equilibrium on a fine mesh,
// solved with the assembled LDLT-preconditioned Newton solver (sim/solve/static_solver.h). The
// scene path (run_scene_on) uses matrix-free CG, which on the finest meshes of bending problems
// needs thousands of iterations per Newton step; the direct factorisation does not.
#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"
#include "sim/solve/constrained_system.h"

namespace incise::bench {

struct ReferenceResult {
  sim::Points displacement;         // #nodes by 3 [m]
  bool converged = false;           // every load increment met the tolerance
  sim::Real relative_residual = 0;  // the worst increment's, at its end
  double ms = 0;                    // wall time of the whole solve
};

// The equilibrium of scene (its material.model, constraints, loads, gravity) on mesh, reached in
// `increments` equal load increments (displacements, loads and gravity grow linearly, as the
// scene's static solve does), each to relative residual tolerance, the Newton steps solved by
// solver (assembled_ldlt: direct; matrix_free_cg: Jacobi CG).
ReferenceResult reference_static_solve(const sim::Scene& scene, const sim::TetMesh& mesh,
                                       int increments, sim::Real tolerance,
                                       sim::LinearSolver solver);

}  // namespace incise::bench
