#include "sim/cli/cli.h"

#include <algorithm>
#include <exception>
#include <fstream>
#include <optional>

#include "sim/io/result_json.h"
#include "sim/io/scene_json.h"
#include "sim/scene/run_scene.h"

namespace incise::sim {
namespace {

constexpr const char* kUsage = "usage: incise solve SCENE.json --out RESULT.json, or incise --help";

constexpr const char* kHelp =
    R"(incise - the Incise soft-tissue simulation core from the command line

usage:
  incise solve SCENE.json --out RESULT.json   run a scene, write its result
  incise --help                               show this text

SCENE.json (units SI; members marked ? are optional):
  { "mesh": {"box": {"size": [Lx, Ly, Lz], "cells": [nx, ny, nz]}},
    "material": {"model": "mss", "E": 3000, "nu": 0.45, "density": 1000, "damping"?: 0.1},
    "constraints"?: [ {"where": {"box": [[x0, y0, z0], [x1, y1, z1]]}, "fix": "xyz"},
                      {"where": {"box": ...}, "displace": [dx, dy, dz], "axes"?: "x"} ],
    "loads"?: [ {"where": {"box": ...}, "force": [fx, fy, fz]} ],
    "gravity"?: [0, 0, -9.81],
    "solver": {"integrator": "symplectic_euler", "dt": 1e-4, "steps": 10000} }
  mesh.box       a box with its corner at the origin, 6 tets per cell
  material       "mss": volumetric mass-spring system (Paloc et al. 2006): node mass from
                 density, spring stiffness from E; nu is checked but a mass-spring system has
                 no free Poisson ratio. damping in [0, 1] scales each spring's damping
                 2 sqrt(k (m_i + m_j)) (default 0.1)
  where.box      selects the nodes inside the box (inclusive, tolerance 1e-6 of the mesh size);
                 a box that selects no node is an error
  fix            holds the named coordinates ("x", "xz", "xyz", ...) at rest
  displace       moves the named coordinates (axes, default "xyz") by the displacement, ramped
                 linearly over the first half of the steps and then held; a later constraint
                 wins where constraints overlap
  force          a total force [N], split equally over the selected nodes
  Example: sim/scenes/clamped_box.json (a box clamped at its base, settling under gravity).

RESULT.json:
  {"nodes": N, "tets": M, "rest": [[x, y, z], ...], "displacement": [[ux, uy, uz], ...],
   "steps": k, "ms_per_step": median wall time of a step, "max_speed": largest node speed at
   the end [m/s], "finite": true}

exit codes:
  0  done
  1  the state became non-finite (RESULT.json is written with "finite": false; try a smaller
     dt) or an internal error
  2  usage error, unreadable or invalid scene (one line on stderr names the key), or
     RESULT.json cannot be written
)";

int usage_error(std::ostream& err, const std::string& problem) {
  err << "incise: " << problem << " (" << kUsage << ")\n";
  return kExitUsage;
}

int solve(const std::vector<std::string>& args, std::ostream& err) {
  std::optional<std::string> scene_file;
  std::optional<std::string> result_file;
  for (std::size_t i = 1; i < args.size(); ++i) {
    if (args[i] == "--out") {
      if (i + 1 == args.size()) return usage_error(err, "--out needs a file name");
      result_file = args[++i];
    } else if (!args[i].empty() && args[i][0] == '-') {
      return usage_error(err, "unknown option " + args[i]);
    } else if (scene_file) {
      return usage_error(err, "more than one scene file");
    } else {
      scene_file = args[i];
    }
  }
  if (!scene_file) return usage_error(err, "solve needs a scene file");
  if (!result_file) return usage_error(err, "solve needs --out RESULT.json");

  RunResult result;
  try {
    result = run_scene(read_scene_file(*scene_file));
  } catch (const SceneError& error) {
    err << "incise: " << *scene_file << ": " << error.what() << "\n";
    return kExitUsage;
  }

  std::ofstream out(*result_file);
  out << result_to_json(result).dump() << "\n";
  out.close();
  if (!out) {
    err << "incise: " << *result_file << ": cannot write the result\n";
    return kExitUsage;
  }
  if (!result.finite) {
    err << "incise: " << *scene_file << ": the state became non-finite at step " << result.steps
        << " (try a smaller solver.dt)\n";
    return kExitFailed;
  }
  return kExitOk;
}

}  // namespace

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  try {
    if (args.empty()) return usage_error(err, "no command");
    if (std::find(args.begin(), args.end(), "--help") != args.end() || args[0] == "-h" ||
        args[0] == "help") {
      out << kHelp;
      return kExitOk;
    }
    if (args[0] == "solve") return solve(args, err);
    return usage_error(err, "unknown command " + args[0]);
  } catch (const std::exception& error) {
    err << "incise: internal error: " << error.what() << "\n";
  } catch (...) {
    err << "incise: internal error\n";
  }
  return kExitFailed;
}

}  // namespace incise::sim
