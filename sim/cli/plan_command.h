#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace incise::sim {

// `incise plan SCENE.json --from X,Y,Z --to X,Y,Z [--degree N] [--probe-radius R]
//  [--bound B] --out PATH.json`: seed 004's planning aid on a surgical scene file
// (sim/surgery/scene_file.h; docs/planning.md). The obstacles are the scene's tissues (each
// tissue's tets sampled on a lattice a probe radius apart, stiffness its Young's modulus over the
// softest tissue's, protected when the scene protects it) and its bones (their surface vertices,
// protected, a thousand times the stiffest tissue). Writes PATH.json:
//   {"scene", "from", "to", "degree", "probe_radius", "penetration_bound",
//    "coefficients": [[x, y, z], ...], "path": [[x, y, z], ...] (65 points),
//    "straight_cost", "cost", "iterations", "max_penetration", "deepest_obstacle",
//    "max_protected_penetration", "within_bound", "problem",
//    "obstacles": [{"name", "points", "stiffness", "protected"}]}
// and one line on out. Returns kExitOk, also when no path stays within the bound (then
// "within_bound" is false and the reason is a second line on err); kExitUsage with one line on
// err for bad arguments, a bad scene file or an unwritable PATH.json.
int run_plan_command(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace incise::sim
