#pragma once
// Runs a scene whose "adaptivity" is set: the body is an AdaptiveBody whose
// mesh is refined where the scene's criteria fire and decimated where they no longer do, while
// symplectic Euler steps it. Here and not in sim/scene/ because incise_sim_remesh builds on
// incise_sim (the CLI dispatches: run_scene_checked without adaptivity, this with it).
//
// Per run:
//   - the model is make_model(scene, mesh) (scene_run.h), made once on the start mesh (made
//     constrained Delaunay first, AdaptiveBody; same nodes, possibly flipped tets) and then
//     updated locally by every refinement and decimation;
//   - a vertex is fixed if its REST point lies in a constraint's box (widened by
//     selection_tolerance of the start mesh), so a vertex inserted in a clamp is clamped too;
//     constraints are "fix": "xyz" only (validate_scene);
//   - each load's force is split equally over the alive vertices whose rest point lies in its
//     box, re-selected after every adaptation;
//   - every adaptivity.every steps (not after the last): AdaptationRegions::update on the current
//     state (strain, curvature), refine(refine_field) with l_min (from dt_min if given:
//     l_min_for_dt_min with the fastest material's P-wave speed), quality and the altitude floor,
//     then decimate(keep_field, kDecimationAttempts);
//   - the checks of run_scene_checked after every step: finite state, extent of the alive
//     vertices below kDivergedExtent times the rest one.
// The result describes the FINAL mesh: result.rest, displacement, final_positions have a row per
// alive vertex of the final mesh (its original nodes first, in their order, then the inserted
// ones), num_tets is its tet count. ms_per_step is the median of the timed steps, adaptation
// included on the steps that adapt.

#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"
#include "sim/scene/scene_run.h"

namespace incise::sim::remesh {

// Removal attempts per adaptation: bounds the cost of one adaptation; vertices left over are
// removed by later adaptations.
inline constexpr int kDecimationAttempts = 200;

// Runs scene (scene.adaptivity set) on mesh (from its rest configuration).
//   final_mesh  if given, receives the final compact mesh (rest, x, v, tets, labels), e.g. for
//               .vtu output
// Throws SceneError as run_scene_checked (invalid scene, a selection that picks no node, a mesh
// the model or the remesher refuses: "mesh: ..."), and "adaptivity: ..." if scene.adaptivity is
// not set.
CheckedRun run_adaptive_scene(const Scene& scene, TetMesh mesh, TetMesh* final_mesh = nullptr);

}  // namespace incise::sim::remesh
