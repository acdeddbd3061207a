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

struct CalculixProblem {
  const TetMesh* mesh = nullptr;  // rest positions and tets (positively oriented)
  Real youngs_modulus = 0;        // [Pa]
  Real poisson_ratio = 0;
  std::vector<int> fixed_nodes;  // all three displacements zero
  Points node_loads;             // #nodes by 3 [N]; rows of zeros are left out
};

// The ccx executable, or nullopt if it is not installed (the tests then fail with this reason).
std::optional<std::filesystem::path> find_ccx();

// Writes job.inp into dir, runs ccx there and returns the #nodes by 3 displacements [m]. Throws
// std::runtime_error with ccx's output when it fails.
Points solve_linear_static(const CalculixProblem& problem, const std::filesystem::path& dir);

}  // namespace incise::sim::reference
