#pragma once

#include <nlohmann/json.hpp>

#include "sim/scene/run_scene.h"

namespace incise::sim {

// The RESULT.json form of a run (`incise solve` contract):
//   {"nodes": N, "tets": M, "rest": [[x, y, z], ...], "displacement": [[ux, uy, uz], ...],
//    "steps": k, "ms_per_step": median [ms], "max_speed": [m/s], "finite": bool,
//    "solver": {"converged": bool, "iterations": n, "relative_residual": x,
//               "inverted_elements": n}}
// ("solver" reports on an iterative solve; a direct explicit run has converged true,
// 0 iterations and residual 0.)
// rest and displacement in metres, one row per node. A non-finite number (only when "finite" is
// false) is written as null, since JSON has no NaN or infinity.
nlohmann::json result_to_json(const RunResult& result);

}  // namespace incise::sim
