#pragma once
// CalculiX (ccx, Debian's calculix-ccx) as a reference solver for the tests: the same tetrahedral
// mesh as linear C3D4 elements, the same material, fixed nodes and nodal loads, a linear static
// step; the node displacements come back from the .dat file.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "sim/core/types.h"
#include "sim/mesh/tet_mesh.h"

namespace incise::sim::reference {

enum class CalculixMaterial {
  linear_elastic,  // *ELASTIC E, nu; a linear static step
  // *HYPERELASTIC, NEO HOOKE: W = C10 (J^-2/3 I1 - 3) + (J - 1)^2 / D1 with C10 = mu / 2 and
  // D1 = 2 / K (K the bulk modulus lambda + 2 mu / 3), so that it agrees with linear elasticity
  // at small strain; the step is geometrically nonlinear (NLGEOM) in increments.
  neo_hooke,
};

// A displacement prescribed on one coordinate of one node (dof 0, 1, 2 = x, y, z).
struct PrescribedDof {
  int node = 0;
  int dof = 0;
  Real value = 0;  // [m]
};

struct CalculixProblem {
  const TetMesh* mesh = nullptr;  // rest positions and tets (positively oriented)
  Real youngs_modulus = 0;        // [Pa]
  Real poisson_ratio = 0;
  CalculixMaterial material = CalculixMaterial::linear_elastic;
  std::vector<int> fixed_nodes;           // all three displacements zero
  std::vector<PrescribedDof> prescribed;  // single coordinates held or moved
  Points node_loads;                      // #nodes by 3 [N]; rows of zeros are left out
  int increments = 1;                     // NLGEOM increments (neo_hooke)
};

// The ccx executable, or nullopt if it is not installed (the tests then fail with this reason).
std::optional<std::filesystem::path> find_ccx();

// Writes job.inp into dir, runs ccx there and returns the #nodes by 3 displacements [m] at the end
// of the step. Throws
// std::runtime_error with ccx's output when it fails.
Points solve_linear_static(const CalculixProblem& problem, const std::filesystem::path& dir);

}  // namespace incise::sim::reference
