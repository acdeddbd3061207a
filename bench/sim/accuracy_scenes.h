#pragma once
// The two scenes of the speed-against-error benchmark, built in code, and what their
// errors are measured against.
//   compression  a 2 cm cube compressed along z by a given strain, lateral faces free (the truth-
//                cube strains 5%, 12.5%, 18.25%); symmetry planes x = 0, y = 0, z = 0 hold one
//                coordinate each, the top face is displaced
//   cantilever   a 10 x 2 x 2 cm beam clamped at x = 0 under a tip load (z), about a tenth of
//                its length of deflection for linear elasticity (moderately nonlinear)
// Both on box meshes whose cell counts nest (a coarse level's nodes are nodes of the reference
// level), so that a coarse answer is compared node by node with no interpolation.
#include <optional>
#include <string>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/scene/scene.h"

namespace incise::bench {

using sim::Points;
using sim::Real;
using sim::Vec3;
using sim::Vec3i;

// Soft tissue, as in tests/sim/scene/scene_run_test.cpp.
inline constexpr Real kYoungsModulus = 3000;  // [Pa]
inline constexpr Real kPoissonRatio = 0.3;
inline constexpr Real kDensity = 1000;    // [kg/m^3]
inline constexpr Real kBlockSize = 0.02;  // cube edge [m]
inline constexpr Real kBeamLength = 0.1;  // [m]; cross-section 2 x 2 cm
inline constexpr Real kTipLoad = 1.2e-3;  // [N]: P L^3 / (3 E I) = L / 10 (Euler-Bernoulli)

// The block compressed by strain (> 0 shortens it), on cells^3 cells. Model and solver unset.
sim::Scene compression_scene(Real strain, int cells);

// The cantilever on (5 n, n, n) cells. Model and solver unset.
sim::Scene cantilever_scene(int n);

// The box mesh of a scene (scene.mesh.box).
sim::TetMesh scene_mesh(const sim::Scene& scene);

// The closed-form displacement of the compressed block at the points rest (#nodes by 3), where the
// model has one: linear elasticity u = (nu e x, nu e y, -e z) and Joshi et al.'s compressible
// Neo-Hookean (eq. 15, lateral stretch from traction-free sides). Empty for other models.
std::optional<Points> compression_closed_form(sim::MaterialModel model, Real strain,
                                              const Points& rest);

// Rows of reference (on a box mesh of fine_cells cells) at the nodes of a box mesh of
// coarse_cells cells over the same box; each fine count must be a multiple of the coarse one.
Points restrict_to_coarse(const Points& reference, const Vec3i& fine_cells,
                          const Vec3i& coarse_cells);

// Largest node error |u - reference| relative to the largest |reference| (both #nodes by 3).
Real relative_error(const Points& u, const Points& reference);

// Scene names as in JSON ("mss", "static", ...).
std::string model_name(sim::MaterialModel model);
std::string integrator_name(sim::Integrator integrator);

}  // namespace incise::bench
