#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "sim/core/types.h"
#include "sim/interact/sphere_tool.h"

namespace incise::sim {

// What to simulate and how, as plain values. The members mirror the JSON form read by
// sim/io/scene_json.h member for member; SceneError paths use the JSON names (noted below).
// All quantities SI.

// A box [0, size] meshed on a grid of cells (see make_box_mesh).
struct BoxMeshSpec {
  Vec3 size = Vec3::Zero();     // "size": edge lengths [m], each > 0
  Vec3i cells = Vec3i::Ones();  // "cells": cells per axis, each >= 1
};

// A tet mesh made by CGAL Mesh_3 from an implicit shape (sim/mesh/cgal/mesh_generation.h).
struct GenerateSpec {
  std::string shape;           // "shape": "sphere", "ellipsoid" or "liver"
  Vec3 centre = Vec3::Zero();  // "centre" [m]
  Vec3 radii = Vec3::Zero();   // "radius" (sphere, all three) or "radii" [m], each > 0
  Real cell_size = 0;          // "cell_size" [m], > 0: the largest tet circumradius
};

// A tet mesh made by CGAL Mesh_3 from a labelled segmentation volume in NIfTI
// (sim/mesh/nifti/nifti_segmentation.h), in the volume's own world coordinates.
struct SegmentationSpec {
  std::string file;                    // "file": .nii or .nii.gz, relative to the scene file
  std::map<int, std::string> tissues;  // "labels": {"<value>": "<tissue>"}, every value it holds
  Real cell_size = 0;                  // "cell_size" [m], > 0: the largest tet circumradius
};

enum class MeshSource {
  box,           // "box"
  file,          // "file": gmsh .msh (2.2 or 4.1) or TetGen .node/.ele, relative to the scene file
  generate,      // "generate"
  segmentation,  // "segmentation"
};

struct MeshSpec {
  MeshSource source = MeshSource::box;
  BoxMeshSpec box;                // "box"
  std::string file;               // "file", as written in the scene
  GenerateSpec generate;          // "generate"
  SegmentationSpec segmentation;  // "segmentation"
};

enum class MaterialModel {
  mass_spring,         // "mss": volumetric mass-spring system (sim/models/mass_spring.h)
  linear,              // "linear": small-strain linear FEM
  corotational,        // "corotational": corotational linear FEM, rotations by QR
  corotational_polar,  // "corotational_polar": the same with polar decomposition
  // "corotational_nodal_pressure": corotational_polar with averaged nodal pressure, free of
  // volumetric locking (sim/models/nodal_pressure_fem.h)
  corotational_nodal_pressure,
  stvk,        // "stvk": St Venant-Kirchhoff
  neohookean,  // "neohookean": compressible Neo-Hookean (Joshi et al., eq. 4)
};

// The scene files' names of the material models, as error messages list them.
inline constexpr std::string_view kMaterialModelNames =
    "mss, linear, corotational, corotational_polar, corotational_nodal_pressure, stvk, "
    "neohookean";

// The material model a scene file names `name`, or nullopt (every scene format reads it so).
inline std::optional<MaterialModel> material_model_named(std::string_view name) {
  static constexpr std::pair<std::string_view, MaterialModel> models[] = {
      {"mss", MaterialModel::mass_spring},
      {"linear", MaterialModel::linear},
      {"corotational", MaterialModel::corotational},
      {"corotational_polar", MaterialModel::corotational_polar},
      {"corotational_nodal_pressure", MaterialModel::corotational_nodal_pressure},
      {"stvk", MaterialModel::stvk},
      {"neohookean", MaterialModel::neohookean},
  };
  for (const auto& [named, model] : models) {
    if (named == name) return model;
  }
  return std::nullopt;
}

// The scene files' name of a material model ("mss", "linear", ...).
inline std::string_view material_model_name(MaterialModel model) {
  for (const std::string_view name : {"mss", "linear", "corotational", "corotational_polar",
                                      "corotational_nodal_pressure", "stvk", "neohookean"}) {
    if (material_model_named(name) == model) return name;
  }
  return "mss";
}

struct Material {
  MaterialModel model = MaterialModel::mass_spring;  // "model"
  Real youngs_modulus = 0;                           // "E" [Pa], > 0
  Real poisson_ratio = 0;  // "nu", in (-1, 0.5); the mass-spring model has no free Poisson
                           // ratio and ignores it
  Real density = 0;        // "density" [kg/m^3], > 0
  Real damping = 0.1;      // "damping", in [0, 1]: fraction of the model's reference damping
  // "volume_stiffness" (mss only), >= 0: the mass-spring model's volume-preservation term, as a
  // multiple of E (mass_spring_model.h); 0 = springs only.
  Real volume_stiffness = 0;
};

// The nodes a constraint or load acts on: those inside box (closed, widened by
// selection_tolerance). Every selection must pick at least one node.
struct Selection {
  Box3 box;  // "box": [[x0, y0, z0], [x1, y1, z1]] [m], min <= max
};

using Axes = std::array<bool, 3>;  // x, y, z

// Holds the selected nodes' coordinates on `axes` at rest + displacement: "fix" is a zero
// displacement, "displace" a given one, applied as a linear ramp over the first half of the
// solver's steps and then held. Where constraints overlap, the later one wins on that axis.
struct Constraint {
  Selection where;                   // "where"
  Axes axes = {true, true, true};    // "fix": "xyz" subset, or "axes" of a "displace"
  Vec3 displacement = Vec3::Zero();  // "displace" [m]
};

// A total force split equally over the selected nodes (a load on a prescribed coordinate has
// no effect).
struct Load {
  Selection where;            // "where"
  Vec3 force = Vec3::Zero();  // "force" [N]
};

enum class Integrator {
  symplectic_euler,    // "symplectic_euler" (sim/solve/symplectic_euler.h)
  central_difference,  // "central_difference"
  adaptive_explicit,   // "adaptive_explicit": embedded error estimate, floor dt_min
  implicit_euler,      // "implicit_euler": linearised backward Euler, conjugate gradients
  static_equilibrium,  // "static": the equilibrium (Newton with line search); dt and steps unused
};

enum class LinearSolverChoice { cg, assembled_cg, ldlt };

enum class PreconditionerChoice { automatic, jacobi, block_jacobi, incomplete_cholesky };

struct SolverSettings {
  Integrator integrator = Integrator::symplectic_euler;  // "integrator"
  Real dt = 0;                                           // "dt" [s], > 0
  std::int64_t steps = 0;                                // "steps", >= 1
  Real tolerance = 1e-8;  // "tolerance": relative residual of iterative solves, in (0, 1)
  // "linear_solver" of implicit_euler and static: "cg" (matrix-free conjugate gradients, Jacobi
  // preconditioned; the default), "assembled_cg" (the same on an assembled sparse matrix, whose
  // pattern is kept between steps) or "ldlt" (a sparse Cholesky factorisation preconditioning CG:
  // few iterations, costly factorisations; for small stiff problems).
  LinearSolverChoice linear_solver = LinearSolverChoice::cg;
  // "preconditioner" of the CG solvers: "jacobi", "block_jacobi" (a node's 3x3 block) or
  // "incomplete_cholesky" (block IC(0), kept between steps; assembled_cg only). Default
  // (automatic): incomplete_cholesky with assembled_cg, jacobi with cg.
  PreconditionerChoice preconditioner = PreconditionerChoice::automatic;
};

// Where a live view of the scene looks from, as plain values (the renderer makes a camera of it).
struct ViewSpec {
  Vec3 eye = Vec3::Zero();     // "eye": camera position [m]
  Vec3 target = Vec3::Zero();  // "target": the point looked at [m], not the eye
  Vec3 up = Vec3::UnitZ();     // "up": roughly up on screen; not parallel to target - eye
  Real fov_y_deg = 45;         // "fov_y_deg": vertical field of view [deg], in (0, 180)
};

// Online adaptive remeshing of the body (sim/remesh/): where a criterion fires, the mesh
// is refined in the rest configuration down to fine_size, and coarsened again where it no longer
// does; "adaptivity" absent = a fixed mesh. Runs with solver.integrator "symplectic_euler" and
// "fix": "xyz" constraints only (the remesher holds a vertex by its rest point; it has no
// per-axis or moving constraints). At least one criterion (strain, curvature).
struct AdaptivitySpec {
  // The floor on edge lengths and on the altitudes of created tets [m]: exactly one of "l_min"
  // and "dt_min" [s] is given (> 0); the other is 0. dt_min converts with the fastest material's
  // P-wave speed c as l_min = dt_min c / 0.5 (sim/remesh/time_step_floor.h).
  Real l_min = 0;           // "l_min" [m]
  Real dt_min = 0;          // "dt_min" [s]
  Real fine_size = 0;       // "fine_size" [m], > 0: the target circumradius in the regions
  Real quality = 2.0;       // "quality", > 1: the bound on circumradius / shortest edge
  std::int64_t every = 10;  // "every", >= 1: steps between two adaptations
  bool strain = false;      // "strain": {"on", "off"}, Green strain norms, 0 < off < on
  Real strain_on = 0;
  Real strain_off = 0;
  bool curvature = false;    // "curvature": {"on_degrees", "off_degrees"}, 0 < off < on <= 180
  Real bend_on_degrees = 0;  // the change of a surface edge's bend from rest [deg]
  Real bend_off_degrees = 0;
  // "keep_margin" [m], >= 0: refined vertices within this rest distance of a region are not
  // decimated (hysteresis in space). Absent: fine_size.
  std::optional<Real> keep_margin;
};

struct Scene {
  MeshSpec mesh;      // "mesh"
  Material material;  // "material": the model, and the constants of label 0
  // "materials": {"<label>": {"E", "nu", "density", "damping"?}}: constants per tissue label of
  // a labelled mesh (the model stays material.model); labels not listed use "material"'s.
  std::map<int, Material> materials_by_label;
  std::vector<Constraint> constraints;       // "constraints"
  std::vector<Load> loads;                   // "loads"
  Vec3 gravity = Vec3::Zero();               // "gravity" [m/s^2]
  SolverSettings solver;                     // "solver"; live sessions step with solver.dt and
                                             // ignore solver.steps (except for a "displace" ramp)
  std::optional<SphereTool> tool;            // "tool": the probe of a live session, if any
  std::optional<ViewSpec> view;              // "view": the live view's camera, if given
  std::string vtu_output;                    // "output": {"vtu": path}: also write the final state
  std::optional<AdaptivitySpec> adaptivity;  // "adaptivity": remesh online (sim/remesh/)
};

// Upper bound on mesh.box.cells' product, so that a typo cannot ask for more memory than a
// workstation has (6 tets per cell).
inline constexpr std::int64_t kMaxBoxCells = 1'000'000;

}  // namespace incise::sim
