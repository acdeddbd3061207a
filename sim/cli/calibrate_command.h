#pragma once

#include <ostream>
#include <string>
#include <vector>

namespace incise::sim {

// `incise calibrate DATA.csv SCENE.json --method ga|cmaes|lm --out MATERIAL.json
//  [--per label|node] [--budget N] [--seed S] [--population P] [--smoothing A]`: fits the
// scene's material constants (SCENE.json in the `incise solve` form: its mesh, model, materials
// and "fix" constraints) to the probe data (sim/calibrate/probe_data.h; docs/calibration.md).
// --per label (default) fits E per label, and nu too for the FEM models; --per node fits seed
// 004's per-node moduli of the mass-spring model. --budget caps the simulations (default 2000).
// Prints a progress line per generation or iteration and a summary on out, and writes
// MATERIAL.json (sim/calibrate/calibration_json.h). Returns kExitOk; kExitUsage with one line
// "incise: ..." on err for bad arguments, a bad data or scene file (what and where) or an
// unwritable MATERIAL.json, having written nothing.
int run_calibrate_command(const std::vector<std::string>& args, std::ostream& out,
                          std::ostream& err);

}  // namespace incise::sim
