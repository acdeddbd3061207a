#include "sim/io/scene_json.h"

#include <cerrno>
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

MeshSpec read_mesh(const json& value) {
  if (value.is_object() && value.contains("file")) {
    throw SceneError("mesh.file", "mesh files are not supported yet (use mesh.box)");
  }
  const JsonObjectReader mesh(value, "mesh", {"box"});
  const JsonObjectReader box(mesh.required("box"), mesh.path("box"), {"size", "cells"});
  MeshSpec spec;
  spec.box.size = box.vec3("size");
  spec.box.cells = box.ivec3("cells");
  return spec;
}

Material read_material(const json& value) {
  const JsonObjectReader object(value, "material", {"model", "E", "nu", "density", "damping"});
  Material material;
  const std::string model = object.string("model");
  if (model != "mss") {
    throw SceneError(object.path("model"),
                     "unknown model " + describe(json(model)) + " (expected: mss)");
  }
  material.model = MaterialModel::mass_spring;
  material.youngs_modulus = object.number("E");
  material.poisson_ratio = object.number("nu");
  material.density = object.number("density");
  if (object.has("damping")) material.damping = object.number("damping");
  return material;
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
  const JsonObjectReader object(value, "solver", {"integrator", "dt", "steps"});
  SolverSettings solver;
  const std::string integrator = object.string("integrator");
  if (integrator != "symplectic_euler") {
    throw SceneError(object.path("integrator"), "unknown integrator " + describe(json(integrator)) +
                                                    " (expected: symplectic_euler)");
  }
  solver.integrator = Integrator::symplectic_euler;
  solver.dt = object.number("dt");
  solver.steps = object.integer("steps");
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
  const JsonObjectReader root(
      value, "", {"mesh", "material", "constraints", "loads", "gravity", "solver", "tool", "view"});
  Scene scene;
  scene.mesh = read_mesh(root.required("mesh"));
  scene.material = read_material(root.required("material"));
  scene.constraints = read_list<Constraint>(root, "constraints", read_constraint);
  scene.loads = read_list<Load>(root, "loads", read_load);
  if (root.has("gravity")) scene.gravity = root.vec3("gravity");
  scene.solver = read_solver(root.required("solver"));
  if (root.has("tool")) scene.tool = read_tool(root.required("tool"));
  if (root.has("view")) scene.view = read_view(root.required("view"));
  validate_scene(scene);
  return scene;
}

Scene parse_scene_text(std::string_view text) {
  json value;
  try {
    value = json::parse(text);
  } catch (const json::parse_error& error) {
    // what() is "[json.exception.parse_error.101] parse error at line 1, column 2: ...".
    std::string reason = error.what();
    const std::size_t start = reason.find("] ");
    if (start != std::string::npos) reason.erase(0, start + 2);
    throw SceneError("", "malformed JSON: " + reason);
  }
  return parse_scene(value);
}

Scene read_scene_file(const std::filesystem::path& file) {
  std::error_code error;
  if (std::filesystem::is_directory(file, error)) throw SceneError("", "is a directory");
  std::ifstream stream(file, std::ios::binary);
  if (!stream) throw SceneError("", std::string("cannot open file (") + std::strerror(errno) + ")");
  std::ostringstream text;
  text << stream.rdbuf();
  if (stream.bad()) throw SceneError("", "cannot read file");
  return parse_scene_text(text.str());
}

}  // namespace incise::sim
