#include "sim/io/scene_json.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>

#include "sim/io/json_object_reader.h"
#include "sim/scene/scene_validation.h"

namespace incise::sim {
namespace {

using nlohmann::json;

// A non-empty subset of "xyz", each letter at most once, in any order.
Axes read_axes(const JsonObjectReader& object, std::string_view key) {
  const std::string text = object.string(key);
  Axes axes = {false, false, false};
  bool valid = !text.empty();
  for (const char c : text) {
    const auto axis = static_cast<std::size_t>(c - 'x');
    if (c < 'x' || c > 'z' || axes[axis]) {
      valid = false;
      break;
    }
    axes[axis] = true;
  }
  if (!valid) {
    throw SceneError(object.path(key),
                     "must be a non-empty subset of \"xyz\" (got " + describe(json(text)) + ")");
  }
  return axes;
}

Selection read_selection(const json& value, const std::string& path) {
  const JsonObjectReader where(value, path, {"box"});
  const json& box = where.required("box");
  const std::string box_path = where.path("box");
  if (!box.is_array() || box.size() != 2) {
    throw SceneError(box_path, "must be [[x0, y0, z0], [x1, y1, z1]] (got " + describe(box) + ")");
  }
  Selection selection;
  selection.box = Box3(read_vec3(box[0], element_path(box_path, 0)),
                       read_vec3(box[1], element_path(box_path, 1)));
  return selection;
}

// "labels": {"<value>": "<tissue>"} of a segmentation: label values 1..255, distinct names.
std::map<int, std::string> read_segmentation_tissues(const json& value, const std::string& path) {
  if (!value.is_object() || value.empty()) {
    throw SceneError(path,
                     "must be an object {\"<label value>\": \"<tissue>\"} naming every "
                     "label the volume holds (got " +
                         describe(value) + ")");
  }
  std::map<int, std::string> tissues;
  for (const auto& [key, item] : value.items()) {
    const std::string item_path = member_path(path, key);
    int label = 0;
    const auto [end, ec] = std::from_chars(key.data(), key.data() + key.size(), label);
    if (ec != std::errc{} || end != key.data() + key.size() || label < 1 || label > 255) {
      throw SceneError(item_path, "a label value must be an integer in 1..255 (0 is outside)");
    }
    if (!item.is_string() || item.get_ref<const std::string&>().empty()) {
      throw SceneError(item_path, "must be the tissue's name (got " + describe(item) + ")");
    }
    const std::string& name = item.get_ref<const std::string&>();
    for (const auto& [other, other_name] : tissues)
      if (other_name == name)
        throw SceneError(item_path, "names " + describe(item) + " again (label " +
                                        std::to_string(other) + " has it)");
    tissues[label] = name;
  }
  return tissues;
}

MeshSpec read_mesh(const json& value) {
  const JsonObjectReader mesh(value, "mesh", {"box", "file", "generate", "segmentation"});
  const int sources = int(mesh.has("box")) + int(mesh.has("file")) + int(mesh.has("generate")) +
                      int(mesh.has("segmentation"));
  if (sources != 1) {
    const char* names = "\"box\", \"file\", \"generate\", \"segmentation\"";
    throw SceneError("mesh",
                     std::string(sources == 0 ? "needs one of " : "has more than one of ") + names);
  }
  MeshSpec spec;
  if (mesh.has("file")) {
    spec.source = MeshSource::file;
    spec.file = mesh.string("file");
    return spec;
  }
  if (mesh.has("segmentation")) {
    spec.source = MeshSource::segmentation;
    const JsonObjectReader g(mesh.required("segmentation"), mesh.path("segmentation"),
                             {"file", "labels", "cell_size"});
    spec.segmentation.file = g.string("file");
    spec.segmentation.tissues = read_segmentation_tissues(g.required("labels"), g.path("labels"));
    spec.segmentation.cell_size = g.number("cell_size");
    return spec;
  }
  if (mesh.has("generate")) {
    spec.source = MeshSource::generate;
    const JsonObjectReader g(mesh.required("generate"), mesh.path("generate"),
                             {"shape", "centre", "radius", "radii", "cell_size"});
    spec.generate.shape = g.string("shape");
    if (g.has("centre")) spec.generate.centre = g.vec3("centre");
    if (g.has("radius") == g.has("radii")) {
      throw SceneError(mesh.path("generate"), "needs one of \"radius\" (a sphere) or \"radii\"");
    }
    spec.generate.radii = g.has("radius") ? Vec3::Constant(g.number("radius")) : g.vec3("radii");
    spec.generate.cell_size = g.number("cell_size");
    return spec;
  }
  const JsonObjectReader box(mesh.required("box"), mesh.path("box"), {"size", "cells"});
  spec.box.size = box.vec3("size");
  spec.box.cells = box.ivec3("cells");
  return spec;
}

// The constants of one material; the model is read by read_material only.
void read_constants(const JsonObjectReader& object, Material& material) {
  material.youngs_modulus = object.number("E");
  material.poisson_ratio = object.number("nu");
  material.density = object.number("density");
  if (object.has("damping")) material.damping = object.number("damping");
}

Material read_material(const json& value) {
  const JsonObjectReader object(value, "material",
                                {"model", "E", "nu", "density", "damping", "volume_stiffness"});
  Material material;
  const std::string name = object.string("model");
  const std::optional<MaterialModel> model = material_model_named(name);
  if (!model) {
    throw SceneError(object.path("model"), "unknown model " + describe(json(name)) +
                                               " (expected: " + std::string(kMaterialModelNames) +
                                               ")");
  }
  material.model = *model;
  read_constants(object, material);
  if (object.has("volume_stiffness")) {
    if (material.model != MaterialModel::mass_spring) {
      throw SceneError(object.path("volume_stiffness"),
                       "only the mss model has a volume term (the FEM models' volume response "
                       "comes from nu)");
    }
    material.volume_stiffness = object.number("volume_stiffness");
  }
  return material;
}

// Keyed by label, or by a tissue's name where the mesh is a segmentation.
std::map<int, Material> read_materials_by_label(const json& value, const Material& base,
                                                const MeshSpec& mesh) {
  if (!value.is_object()) {
    throw SceneError("materials",
                     "must be an object {\"<label>\": {...}} (got " + describe(value) + ")");
  }
  std::map<int, Material> out;
  for (const auto& [key, item] : value.items()) {
    const std::string path = member_path("materials", key);
    int label = -1;
    for (const auto& [value_label, name] : mesh.segmentation.tissues)
      if (mesh.source == MeshSource::segmentation && name == key) label = value_label;
    if (label < 0) {
      const auto [end, ec] = std::from_chars(key.data(), key.data() + key.size(), label);
      if (ec != std::errc{} || end != key.data() + key.size() || label < 0) {
        throw SceneError(path, mesh.source == MeshSource::segmentation
                                   ? "is neither a label nor a tissue of mesh.segmentation.labels"
                                   : "a label must be a non-negative integer");
      }
    }
    if (out.contains(label))
      throw SceneError(path, "sets label " + std::to_string(label) + " a second time");
    const JsonObjectReader object(item, path, {"E", "nu", "density", "damping"});
    Material material = base;
    read_constants(object, material);
    out[label] = material;
  }
  return out;
}

Constraint read_constraint(const json& value, const std::string& path) {
  const JsonObjectReader object(value, path, {"where", "fix", "displace", "axes"});
  Constraint constraint;
  constraint.where = read_selection(object.required("where"), object.path("where"));
  const bool fix = object.has("fix");
  const bool displace = object.has("displace");
  if (fix == displace) {
    throw SceneError(path, fix ? "has both \"fix\" and \"displace\" (give one)"
                               : "needs \"fix\" or \"displace\"");
  }
  if (fix) {
    if (object.has("axes")) {
      throw SceneError(object.path("axes"), "belongs to \"displace\" (\"fix\" names its axes)");
    }
    constraint.axes = read_axes(object, "fix");
  } else {
    constraint.displacement = object.vec3("displace");
    if (object.has("axes")) constraint.axes = read_axes(object, "axes");
  }
  return constraint;
}

Load read_load(const json& value, const std::string& path) {
  const JsonObjectReader object(value, path, {"where", "force"});
  Load load;
  load.where = read_selection(object.required("where"), object.path("where"));
  load.force = object.vec3("force");
  return load;
}

SolverSettings read_solver(const json& value) {
  const JsonObjectReader object(
      value, "solver",
      {"integrator", "dt", "steps", "tolerance", "linear_solver", "preconditioner"});
  static const std::pair<const char*, Integrator> integrators[] = {
      {"symplectic_euler", Integrator::symplectic_euler},
      {"central_difference", Integrator::central_difference},
      {"adaptive_explicit", Integrator::adaptive_explicit},
      {"implicit_euler", Integrator::implicit_euler},
      {"static", Integrator::static_equilibrium},
  };
  SolverSettings solver;
  const std::string integrator = object.string("integrator");
  const auto* found = std::find_if(std::begin(integrators), std::end(integrators),
                                   [&](const auto& i) { return integrator == i.first; });
  if (found == std::end(integrators)) {
    throw SceneError(object.path("integrator"),
                     "unknown integrator " + describe(json(integrator)) +
                         " (expected: symplectic_euler, central_difference, adaptive_explicit, "
                         "implicit_euler, static)");
  }
  solver.integrator = found->second;
  // An equilibrium has no time: dt and steps are optional there (one "step" is the solve).
  const bool is_static = solver.integrator == Integrator::static_equilibrium;
  solver.dt = is_static && !object.has("dt") ? 1.0 : object.number("dt");
  solver.steps = is_static && !object.has("steps") ? 1 : object.integer("steps");
  if (object.has("tolerance")) solver.tolerance = object.number("tolerance");
  if (object.has("linear_solver")) {
    const std::string name = object.string("linear_solver");
    if (name == "cg") {
      solver.linear_solver = LinearSolverChoice::cg;
    } else if (name == "assembled_cg") {
      solver.linear_solver = LinearSolverChoice::assembled_cg;
    } else if (name == "ldlt") {
      solver.linear_solver = LinearSolverChoice::ldlt;
    } else {
      throw SceneError(
          object.path("linear_solver"),
          "unknown linear solver " + describe(json(name)) + " (expected: cg, assembled_cg, ldlt)");
    }
  }
  if (object.has("preconditioner")) {
    const std::string name = object.string("preconditioner");
    if (name == "jacobi") {
      solver.preconditioner = PreconditionerChoice::jacobi;
    } else if (name == "block_jacobi") {
      solver.preconditioner = PreconditionerChoice::block_jacobi;
    } else if (name == "incomplete_cholesky") {
      solver.preconditioner = PreconditionerChoice::incomplete_cholesky;
    } else {
      throw SceneError(object.path("preconditioner"),
                       "unknown preconditioner " + describe(json(name)) +
                           " (expected: jacobi, block_jacobi, incomplete_cholesky)");
    }
    if (solver.preconditioner == PreconditionerChoice::incomplete_cholesky &&
        solver.linear_solver != LinearSolverChoice::assembled_cg) {
      throw SceneError(object.path("preconditioner"),
                       "incomplete_cholesky needs \"linear_solver\": \"assembled_cg\"");
    }
  }
  return solver;
}

// Every member optional: the defaults of SphereTool.
SphereTool read_tool(const json& value) {
  const JsonObjectReader object(value, "tool", {"radius", "stiffness", "damping"});
  SphereTool tool;
  if (object.has("radius")) tool.radius = object.number("radius");
  if (object.has("stiffness")) tool.stiffness = object.number("stiffness");
  if (object.has("damping")) tool.damping = object.number("damping");
  return tool;
}

ViewSpec read_view(const json& value) {
  const JsonObjectReader object(value, "view", {"eye", "target", "up", "fov_y_deg"});
  ViewSpec view;
  view.eye = object.vec3("eye");
  view.target = object.vec3("target");
  if (object.has("up")) view.up = object.vec3("up");
  if (object.has("fov_y_deg")) view.fov_y_deg = object.number("fov_y_deg");
  return view;
}

// Every member but the sizes optional; ranges and the combination with the rest of the scene
// are checked by validate_scene.
AdaptivitySpec read_adaptivity(const json& value) {
  const JsonObjectReader object(
      value, "adaptivity",
      {"l_min", "dt_min", "fine_size", "quality", "every", "strain", "curvature", "keep_margin"});
  if (object.has("l_min") == object.has("dt_min")) {
    throw SceneError("adaptivity", object.has("l_min")
                                       ? "has both \"l_min\" and \"dt_min\" (give one)"
                                       : "needs \"l_min\" or \"dt_min\"");
  }
  AdaptivitySpec spec;
  if (object.has("l_min")) spec.l_min = object.number("l_min");
  if (object.has("dt_min")) spec.dt_min = object.number("dt_min");
  spec.fine_size = object.number("fine_size");
  if (object.has("quality")) spec.quality = object.number("quality");
  if (object.has("every")) spec.every = object.integer("every");
  if (object.has("strain")) {
    const JsonObjectReader strain(object.required("strain"), object.path("strain"), {"on", "off"});
    spec.strain = true;
    spec.strain_on = strain.number("on");
    spec.strain_off = strain.number("off");
  }
  if (object.has("curvature")) {
    const JsonObjectReader curvature(object.required("curvature"), object.path("curvature"),
                                     {"on_degrees", "off_degrees"});
    spec.curvature = true;
    spec.bend_on_degrees = curvature.number("on_degrees");
    spec.bend_off_degrees = curvature.number("off_degrees");
  }
  if (!spec.strain && !spec.curvature) {
    throw SceneError("adaptivity", "needs at least one criterion: \"strain\" or \"curvature\"");
  }
  if (object.has("keep_margin")) spec.keep_margin = object.number("keep_margin");
  return spec;
}

// The elements of an optional array member, each read by read(element, path).
template <typename T, typename Read>
std::vector<T> read_list(const JsonObjectReader& object, std::string_view key, Read read) {
  std::vector<T> items;
  if (!object.has(key)) return items;
  const json& array = object.required(key);
  if (!array.is_array()) {
    throw SceneError(object.path(key), "must be an array (got " + describe(array) + ")");
  }
  for (std::size_t i = 0; i < array.size(); ++i) {
    items.push_back(read(array[i], element_path(object.path(key), i)));
  }
  return items;
}

}  // namespace

Scene parse_scene(const json& value) {
  if (!value.is_object()) {
    throw SceneError("", "the scene must be a JSON object (got " + describe(value) + ")");
  }
  const JsonObjectReader root(value, "",
                              {"mesh", "material", "materials", "constraints", "loads", "gravity",
                               "solver", "tool", "view", "output", "adaptivity"});
  Scene scene;
  scene.mesh = read_mesh(root.required("mesh"));
  scene.material = read_material(root.required("material"));
  if (root.has("materials")) {
    scene.materials_by_label =
        read_materials_by_label(root.required("materials"), scene.material, scene.mesh);
  }
  if (root.has("output")) {
    const JsonObjectReader output(root.required("output"), "output", {"vtu"});
    scene.vtu_output = output.string("vtu");
  }
  scene.constraints = read_list<Constraint>(root, "constraints", read_constraint);
  scene.loads = read_list<Load>(root, "loads", read_load);
  if (root.has("gravity")) scene.gravity = root.vec3("gravity");
  scene.solver = read_solver(root.required("solver"));
  if (root.has("tool")) scene.tool = read_tool(root.required("tool"));
  if (root.has("view")) scene.view = read_view(root.required("view"));
  if (root.has("adaptivity")) scene.adaptivity = read_adaptivity(root.required("adaptivity"));
  validate_scene(scene);
  return scene;
}

Scene parse_scene_text(std::string_view text) {
  return parse_scene(parse_json_text(text));
}

Scene read_scene_file(const std::filesystem::path& file) {
  return parse_scene_text(read_text_file(file));
}

}  // namespace incise::sim
