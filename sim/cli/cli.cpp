#include "sim/cli/cli.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <exception>
#include <fstream>
#include <optional>

#include "sim/cli/calibrate_command.h"
#include "sim/cli/mesh_command.h"
#include "sim/cli/plan_command.h"
#include "sim/cli/scene_mesh.h"
#include "sim/cli/surgery_command.h"
#include "sim/io/result_json.h"
#include "sim/io/scene_json.h"
#include "sim/mesh/mesh_file_error.h"
#include "sim/mesh/mesh_info.h"
#include "sim/mesh/read_mesh_file.h"
#include "sim/mesh/vtu_writer.h"
#include "sim/remesh/adaptive_run.h"
#include "sim/scene/run_scene.h"
#include "sim/scene/scene_run.h"

namespace incise::sim {
namespace {

constexpr const char* kUsage =
    "usage: incise solve SCENE.json --out RESULT.json, incise mesh-info MESH, incise mesh "
    "VOLUME.nii --labels 1=NAME --cell-size H --out MESH, incise surgery ..., incise plan ..., "
    "incise calibrate ..., or incise --help";

constexpr const char* kHelp =
    R"(incise - the Incise soft-tissue simulation core from the command line

usage:
  incise solve SCENE.json --out RESULT.json   run a scene, write its result
  incise mesh-info MESH                       counts, labels, size and quality of a tet mesh
  incise mesh VOLUME.nii[.gz] --labels 1=NAME,2=NAME --cell-size H --out MESH.msh|.vtu|.node
                                              mesh a labelled segmentation (NIfTI) with CGAL
  incise surgery SCENE.json --script SCRIPT.json --out RESULT.json
                                              run a surgical scene file with a tool script
                                              (docs/surgical_scene_files.md)
  incise plan SCENE.json --from X,Y,Z --to X,Y,Z [--degree 3] [--probe-radius 0.002]
              [--bound 0] --out PATH.json     the tool path that least enters the scene's
                                              tissues, by their stiffness, and its bones
                                              (seed 004's planning aid; docs/planning.md)
  incise calibrate DATA.csv SCENE.json --method ga|cmaes|lm --out MATERIAL.json
              [--per label|node] [--budget 2000] [--seed 1] [--population P] [--smoothing 1e-5]
                                              fit the scene's material constants to probe
                                              data (seed 004; docs/calibration.md)
  incise --help                               show this text

MESH: a gmsh .msh file (ASCII 2.2 or 4.1; tetrahedra and their physical tags as labels) or a
  TetGen mesh (FILE.node, FILE.ele or the base name FILE; the first .ele attribute is the label).
  mesh-info prints the node and tet counts, tets per label, bounding box, total volume, and per
  tet volume, aspect ratio (longest edge / (2 sqrt(6) inradius), 1 for the regular tet) and
  min/max dihedral angles (range, mean, histogram). Tets read negatively oriented are flipped;
  a malformed file (truncated, bad counts or indices, non-finite coordinates, a zero-volume tet)
  is one error line "incise: FILE:LINE: problem" and exit code 2.

VOLUME: a labelled segmentation in NIfTI-1 or -2 (.nii, .nii.gz; 3D Slicer, ITK-SNAP), one
  integer label per voxel, 0 outside. The mesh keeps the volume's place: its affine (sform, else
  qform, else the voxel sizes) in metres; --labels names every label it holds. mesh prints the
  volume's voxels, spacing, axes and origin, each tissue's voxel and meshed volumes and the
  mesh's quality as mesh-info does. A bad volume (an unknown or empty label, not 3-D, a
  truncated file, a sheared affine, a non-integer voxel) is one error line and exit code 2.

DATA.csv: probe data for calibrate, a header and one row per sample: time_s, contact (an integer
  per contact point), x, y, z (the probe tip [m]), dir_x, dir_y, dir_z (the direction it
  pushes), force_n (the force along it [N]). Per contact at least 5 samples evenly spaced in
  time, the tissue at rest at the first; some force. A bad file is one error line naming the
  line and column, and exit code 2.

SCENE.json (units SI; members marked ? are optional):
  { "mesh": {"box": {"size": [Lx, Ly, Lz], "cells": [nx, ny, nz]}},
    "material": {"model": "mss", "E": 3000, "nu": 0.45, "density": 1000, "damping"?: 0.1,
                 "volume_stiffness"?: 0 (mss only: the volume-preservation term, times E)},
    "constraints"?: [ {"where": {"box": [[x0, y0, z0], [x1, y1, z1]]}, "fix": "xyz"},
                      {"where": {"box": ...}, "displace": [dx, dy, dz], "axes"?: "x"} ],
    "loads"?: [ {"where": {"box": ...}, "force": [fx, fy, fz]} ],
    "gravity"?: [0, 0, -9.81],
    "solver": {"integrator": "symplectic_euler", "dt": 1e-4, "steps": 10000} }
  mesh           one of: "box": a box with its corner at the origin, 5 tets per cell;
                 "file": "organ.msh" (or TetGen) relative to the scene file, labels from it;
                 "generate": {"shape": "sphere"|"ellipsoid"|"liver", "centre"?: [x, y, z],
                 "radius": r | "radii": [rx, ry, rz], "cell_size": h} (CGAL Mesh_3);
                 "segmentation": {"file": "organ.nii.gz", "labels": {"1": "liver", ...},
                 "cell_size": h}: a labelled NIfTI volume meshed as `incise mesh` does
  material       model: "mss" (mass-spring, Paloc 2006; no free Poisson ratio),
                 "linear", "corotational" (QR), "corotational_polar",
                 "corotational_nodal_pressure" (polar, without volumetric locking), "stvk",
                 "neohookean" (Joshi et al., eq. 4). damping in [0, 1]: for mss the fraction of
                 2 sqrt(k (m_i + m_j)) per spring, for FEM a viscosity of damping * l_min / c
                 (default 0.1)
  materials?     {"<label>": {"E", "nu", "density", "damping"?}}: per tissue label (or per
                 tissue name of mesh.segmentation.labels)
  solver         integrator: "symplectic_euler", "central_difference", "adaptive_explicit",
                 "implicit_euler" (CG to "tolerance"?, default 1e-8) or "static" (Newton to
                 "tolerance"; "steps"? load increments, dt unused); "linear_solver"?: "cg"
                 (matrix-free, default), "assembled_cg" (fastest above a few hundred tets) or
                 "ldlt"; "preconditioner"?: "jacobi", "block_jacobi" or "incomplete_cholesky"
                 (assembled_cg only; its default there)
  output?        {"vtu": "final.vtu"}: the final state for ParaView, next to the scene file
  adaptivity?    remesh online where the body strains or bends (sim/remesh/, docs/remeshing.md):
                 {"l_min": m | "dt_min": s (one; refinement keeps edges and new tets' altitudes
                 >= l_min, dt_min = 0.5 l_min / c, solver.dt must be <= dt_min), "fine_size": m
                 (target circumradius where refined), "quality"?: 2 (circumradius / shortest
                 edge), "every"?: 10 (steps between adaptations), "strain"?: {"on": 0.05,
                 "off": 0.03} (Green strain), "curvature"?: {"on_degrees": 20, "off_degrees":
                 10} (surface bend from rest), "keep_margin"?: m (default fine_size)}; at least
                 one criterion; needs "symplectic_euler" and "fix": "xyz" constraints. Loads act
                 on the vertices whose rest point is in their box, new ones included.
                 Example: sim/scenes/adaptive_box.json
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
   the end [m/s], "finite": true, "status": "completed" (else why and at which step),
   "solver": {"converged": bool, "iterations": n,
   "relative_residual": x, "inverted_elements": n}}
  With adaptivity, nodes, tets, rest and displacement describe the FINAL mesh: the original
  nodes first in their order, then the vertices refinement inserted and kept.

exit codes:
  0  done
  1  the state became non-finite or diverged (RESULT.json is written with "finite": false and
     the "status"; stderr has the same line; try a smaller dt) or an internal error
  2  usage error, unreadable or invalid scene (one line on stderr names the key),
     RESULT.json cannot be written, or an unreadable or malformed mesh file
)";

int usage_error(std::ostream& err, const std::string& problem) {
  err << "incise: " << problem << " (" << kUsage << ")\n";
  return kExitUsage;
}

int solve(const std::vector<std::string>& args, std::ostream& err) {
  const CommandArgs parsed = parse_command_args(args, {"--out"});
  if (!parsed.problem.empty()) return usage_error(err, parsed.problem);
  const std::optional<std::string>& scene_file = parsed.file;
  std::optional<std::string> result_file;
  if (parsed.options.contains("--out")) result_file = parsed.options.at("--out");
  if (!scene_file) return usage_error(err, "solve needs a scene file");
  if (!result_file) return usage_error(err, "solve needs --out RESULT.json");

  RunResult result;
  Scene scene;
  TetMesh final_mesh;  // with adaptivity: the final, remeshed mesh
  const std::filesystem::path scene_dir = std::filesystem::path(*scene_file).parent_path();
  try {
    scene = read_scene_file(*scene_file);
    if (scene.adaptivity) {
      result =
          remesh::run_adaptive_scene(scene, build_scene_mesh(scene, scene_dir), &final_mesh).result;
    } else {
      result = run_scene_checked(scene, build_scene_mesh(scene, scene_dir)).result;
    }
  } catch (const SceneError& error) {
    err << "incise: " << *scene_file << ": " << error.what() << "\n";
    return kExitUsage;
  }
  if (!scene.vtu_output.empty()) {
    const auto vtu = scene_dir / scene.vtu_output;
    try {
      if (scene.adaptivity) {
        write_vtu(vtu, final_mesh);
      } else {
        TetMesh final_state = build_scene_mesh(scene, scene_dir);
        final_state.x = result.final_positions;
        write_vtu(vtu, final_state);
      }
    } catch (const std::exception& error) {
      err << "incise: " << vtu.string() << ": " << error.what() << "\n";
      return kExitUsage;
    }
  }

  std::ofstream out(*result_file);
  out << result_to_json(result).dump() << "\n";
  out.close();
  if (!out) {
    err << "incise: " << *result_file << ": cannot write the result\n";
    return kExitUsage;
  }
  if (!result.finite) {
    err << "incise: " << *scene_file << ": " << result.status << "\n";
    return kExitFailed;
  }
  return kExitOk;
}

int mesh_info(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  if (args.size() != 2) return usage_error(err, "mesh-info needs exactly one mesh file");
  if (!args[1].empty() && args[1][0] == '-') return usage_error(err, "unknown option " + args[1]);
  TetMesh mesh;
  try {
    mesh = read_mesh_file(args[1]);
  } catch (const MeshFileError& error) {
    err << "incise: " << error.what() << "\n";
    return kExitUsage;
  }
  out << "file: " << args[1] << "\n";
  print_mesh_info(mesh, out);
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
    if (args[0] == "mesh-info") return mesh_info(args, out, err);
    if (args[0] == "mesh") return run_mesh_command(args, out, err);
    if (args[0] == "surgery") return run_surgery_command(args, out, err);
    if (args[0] == "plan") return run_plan_command(args, out, err);
    if (args[0] == "calibrate") return run_calibrate_command(args, out, err);
    return usage_error(err, "unknown command " + args[0]);
  } catch (const std::exception& error) {
    err << "incise: internal error: " << error.what() << "\n";
  } catch (...) {
    err << "incise: internal error\n";
  }
  return kExitFailed;
}

std::optional<Real> parse_real(const std::string& text) {
  Real value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

CommandArgs parse_command_args(const std::vector<std::string>& args,
                               std::initializer_list<std::string_view> file_options) {
  CommandArgs parsed;
  for (std::size_t i = 1; i < args.size() && parsed.problem.empty(); ++i) {
    const bool option =
        std::find(file_options.begin(), file_options.end(), args[i]) != file_options.end();
    if (option) {
      if (i + 1 == args.size()) {
        parsed.problem = args[i] + " needs a file name";
      } else {
        parsed.options[args[i]] = args[i + 1];
        ++i;
      }
    } else if (!args[i].empty() && args[i][0] == '-') {
      parsed.problem = "unknown option " + args[i];
    } else if (parsed.file) {
      parsed.problem = "more than one scene file";
    } else {
      parsed.file = args[i];
    }
  }
  return parsed;
}

}  // namespace incise::sim
