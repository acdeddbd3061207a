#pragma once
// Shared by the active-region tests and benchmark: a box clamped at its bottom face, with the
// seed's mass-spring model, poked at the centre of its top face.
#include <functional>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"
#include "sim/solve/active_region.h"

namespace incise::sim::testing {

// Soft tissue as in Paloc 2006's evaluation (E 4 kPa, density 1050 kg/m^3); damping is the
// fraction of eq. 7.
inline constexpr Real kYoungs = 4e3;
inline constexpr Real kDensity = 1050;
inline constexpr Real kDamping = 0.3;

// The mass-spring model (MaterialModel::mss) with the constants above, for any sub-mesh.
ModelFactory mass_spring_factory(Real damping = kDamping);

struct PokeSetup {
  TetMesh mesh;
  std::vector<int> fixed;  // the bottom face (z = 0)
  int poked = -1;          // the top-face node nearest the centre
  Real dt = 0;             // the stable step (stable_time_step, nu 0.3)
};

// A box of size 0.1 x 0.1 x (0.1 cells.z / cells.x) m on a grid of cells.
PokeSetup make_poke_setup(const Vec3i& cells);

// The nodes within radius [m] of node in the rest configuration (the "poked region").
std::vector<int> nodes_near(const TetMesh& mesh, int node, Real radius);

// Sets the external forces of a step (f arrives zeroed).
using LoadAt = std::function<void(int step, Points& f)>;

// A run's record: the positions of the region's nodes after each step, and for the active runs
// the metrics of each step.
struct RunRecord {
  std::vector<Points> region_x;
  std::vector<ActiveRegionMetrics> metrics;
  Points final_x;
  Real seconds = 0;                // wall time of the stepping alone
  std::vector<Real> step_seconds;  // wall time of each step
};

// The reference: every node integrated every step, with the full model's forces and
// symplectic_euler_step.
RunRecord full_run(const PokeSetup& setup, int steps, const std::vector<int>& region,
                   const LoadAt& load);

// The same with ActiveExplicitStepper.
RunRecord active_run(const PokeSetup& setup, const ActiveRegionSettings& settings, int steps,
                     const std::vector<int>& region, const LoadAt& load);

// max over steps and region nodes of |x_a - x_b|, and of |x_b - rest| (the peak displacement).
struct RegionError {
  Real max_error = 0;
  Real peak_displacement = 0;
};
RegionError region_error(const RunRecord& a, const RunRecord& b, const Points& rest,
                         const std::vector<int>& region);

}  // namespace incise::sim::testing
