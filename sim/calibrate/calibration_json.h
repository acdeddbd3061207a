#pragma once
// A calibration's result as JSON, the MATERIAL.json of `incise calibrate` and what the server's
// calibration jobs store (docs/calibration.md):
//   {"material": {"model", "E", "nu", "density", "damping"},      the scene's "material" form
//    "materials": {"<label>": {"E", "nu", "density", "damping"}},  other labels, if any
//    "node_moduli": [E_0, ...],                                    per-node calibrations only
//    "calibration": {"method", "parameters": "label" | "node", "misfit", "start_misfit",
//                    (the data's term)
//                    "evaluations", "iterations", "seconds", "stopped",
//                    "history": [...] (the search's objective, the prior included),
//                    "values": [{"name", "owner", "start", "value", "spread"}],
//                    "fits": [{"contact", "node", "distance", "time", "force", "measured",
//                              "start", "fitted"}]}}
// The first two members are exactly a scene file's "material" and "materials".

#include <nlohmann/json.hpp>

#include "sim/calibrate/calibration.h"

namespace incise::sim::calibrate {

nlohmann::json calibration_json(const CalibrationResult& result, Method method);

// A progress line: "generation 12: misfit 3.1e-04 after 480 simulations" (ga, cmaes) or
// "iteration ..." (lm). The misfit is the search's objective (the prior included).
std::string progress_line(Method method, const Progress& progress);

}  // namespace incise::sim::calibrate
